# wrsfov_add_shared_library(target OUTPUT_NAME name WHOLE static libs... PUBLIC deps... PRIVATE deps...)
# An installable shared library made of whole static libraries (already compiled position
# independent), so the sources compile once for the project's programs and for the library.
# Versioned SONAME (lib<name>.so.MAJOR.MINOR while the version is 0.x: every minor may change the
# ABI), only the wrsfov:: namespace exported (cmake/wrsfov.map), no undefined symbols left.
function(wrsfov_add_shared_library target)
  cmake_parse_arguments(ARG "" "OUTPUT_NAME" "WHOLE;PUBLIC;PRIVATE" ${ARGN})
  set(stub ${CMAKE_CURRENT_BINARY_DIR}/${target}_stub.cpp)
  file(WRITE ${stub} "// The library's code comes from whole static libraries (cmake/SharedLibrary.cmake).\n")
  add_library(${target} SHARED ${stub})
  # PRIVATE names what the whole archives leave undefined (OpenCV, hidapi); --no-undefined catches
  # anything missing.
  set(whole)
  foreach(lib ${ARG_WHOLE})
    list(APPEND whole $<TARGET_FILE:${lib}>)
    add_dependencies(${target} ${lib})
  endforeach()
  # The archives are linked as files, not as targets, so none of their static dependencies come
  # along (wrsfov_layers under wrsfov_gaze_frame resolves against libwrsfov_compositor instead).
  target_link_libraries(${target} PRIVATE -Wl,--whole-archive ${whole} -Wl,--no-whole-archive ${ARG_PRIVATE}
                        PUBLIC ${ARG_PUBLIC})
  target_link_options(${target} PRIVATE -Wl,--version-script=${PROJECT_SOURCE_DIR}/cmake/wrsfov.map -Wl,--no-undefined)
  set_target_properties(${target} PROPERTIES
    OUTPUT_NAME ${ARG_OUTPUT_NAME}
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
    LINK_DEPENDS "${PROJECT_SOURCE_DIR}/cmake/wrsfov.map")
  target_include_directories(${target} INTERFACE
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/wrsfov>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
endfunction()
