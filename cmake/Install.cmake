# Installation (cmake --install, cpack): the public headers, the shared libraries with their CMake
# package (find_package(wrsfov): wrsfov::compositor, wrsfov::gaze) and pkg-config file, the tools,
# the OpenXR runtime and API layer with their manifests (runtime/, openxr_layer/), and the docs.
# docs/integrating.md says what is public and how to use it.
include(CMakePackageConfigHelpers)

# The public API: the front class and the few structs an integrator fills (include/wrsfov/), the layers
# submission API they take, and the gaze sources. The compositor's internals (compositor/, shaders/) are
# not installed: the library exports them for the project's own runtime and layer only.
set(WRSFOV_FRONT_HEADERS
  include/wrsfov/stereo_compositor.h include/wrsfov/settings.h include/wrsfov/submission.h include/wrsfov/image.h)
set(WRSFOV_PUBLIC_HEADERS
  layers/formats.h layers/frame.h layers/jitter.h layers/status.h layers/swapchain.h)
set(WRSFOV_GAZE_HEADERS
  gaze/sample.h gaze/result.h gaze/angles.h gaze/generator.h gaze/gaze_file.h gaze/source.h
  gaze/hid_descriptor.h gaze/hid_eyetracker.h gaze/hid_device.h gaze/frame_gaze.h gaze/detect.h gaze/stats.h)

set(targets wrsfov_compositor_shared)
set(headers ${WRSFOV_PUBLIC_HEADERS})
if(NOT WRSFOV_COMPOSITOR_ONLY)
  list(APPEND targets wrsfov_gaze_shared)
  list(APPEND headers ${WRSFOV_GAZE_HEADERS})
endif()
set_target_properties(wrsfov_compositor_shared PROPERTIES EXPORT_NAME compositor)
if(TARGET wrsfov_gaze_shared)
  set_target_properties(wrsfov_gaze_shared PROPERTIES EXPORT_NAME gaze)
endif()
install(FILES ${WRSFOV_FRONT_HEADERS} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/wrsfov COMPONENT dev)
foreach(h ${headers})
  get_filename_component(dir ${h} DIRECTORY)
  install(FILES ${h} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/wrsfov/${dir} COMPONENT dev)
endforeach()
install(TARGETS ${targets} EXPORT wrsfovTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT lib NAMELINK_COMPONENT dev)
set(cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/wrsfov)
install(EXPORT wrsfovTargets NAMESPACE wrsfov:: DESTINATION ${cmake_dir} COMPONENT dev)
set(WRSFOV_GAZE_COMPONENT "")
if(TARGET wrsfov_gaze_shared)
  set(WRSFOV_GAZE_COMPONENT ", gaze")
endif()
configure_package_config_file(cmake/wrsfovConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/wrsfovConfig.cmake
                              INSTALL_DESTINATION ${cmake_dir})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/wrsfovConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/wrsfovConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/wrsfovConfigVersion.cmake
        DESTINATION ${cmake_dir} COMPONENT dev)

# pkg-config: wrsfov (compositor) and wrsfov-gaze; the prefix is found from the .pc file's own
# place, so an installed tree can move (a scratch prefix, a .deb's /usr).
file(RELATIVE_PATH PC_UP /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" PC_UP "${PC_UP}")
configure_file(cmake/wrsfov.pc.in ${CMAKE_CURRENT_BINARY_DIR}/wrsfov.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/wrsfov.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)
if(NOT WRSFOV_COMPOSITOR_ONLY)
  configure_file(cmake/wrsfov-gaze.pc.in ${CMAKE_CURRENT_BINARY_DIR}/wrsfov-gaze.pc @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/wrsfov-gaze.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)

  install(TARGETS wrsfov-bench wrsfov-demo wrsfov-gaze wrsfov-preview wrsfov-stress
          RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
  install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT doc)
  install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT doc)
  install(DIRECTORY examples/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples COMPONENT dev)
endif()

include(cmake/Package.cmake)
