# cpack -G DEB: one package, wrsfov, with the libraries, headers, CMake and pkg-config files, tools,
# the OpenXR runtime and API layer with their manifests, and the docs. The runtime dependencies
# come from dpkg-shlibdeps (the libraries the binaries link); Vulkan needs a driver at run time.
set(CPACK_PACKAGE_NAME wrsfov)
set(CPACK_PACKAGE_VENDOR "wrsfov")
set(CPACK_PACKAGE_CONTACT "wrsfov developers <wrsfov@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Stereo VR foveation compositor with weighted reservoir sampling (Vulkan compute)")
set(CPACK_PACKAGE_DESCRIPTION
    "Gaze-contingent foveation and weighted reservoir sampling for stereo frames: a C++ library\n(layers API, Vulkan compute compositor, CPU reference), gaze sources (synthetic, recorded,\nHID eye trackers), benchmark and stress tools, a stereo preview, a simulated-HMD OpenXR runtime\nand an OpenXR API layer.")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_STRIP_FILES ON)  # the build's debug information stays in the build tree
# Not linked, but needed at run time: a Vulkan driver (a GPU's, or Mesa's lavapipe) and, for the
# compositor's shaders' headers, glm and the Vulkan headers when building against it.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "mesa-vulkan-drivers | vulkan-icd")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libvulkan-dev, libglm-dev, vulkan-validationlayers, libopenxr-loader1")
include(CPack)
