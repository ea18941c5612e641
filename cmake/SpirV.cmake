# wrsfov_add_spirv(TARGET name SOURCES a.comp b.comp DEPENDS shared headers...)
# Compiles each compute shader with glslangValidator into a generated header
# `<name>_spv.h` holding `static const uint32_t <name>_spv[]`, and makes them an
# INTERFACE library so that linking it puts the headers on the include path.
# Nothing is read from disk at run time. SPIR-V 1.0 (Vulkan 1.0), so that the compositor also
# runs on an application's Vulkan 1.0 instance and device (an OpenXR app's, adopted by the runtime).
function(wrsfov_add_spirv)
  cmake_parse_arguments(ARG "" "TARGET" "SOURCES;DEPENDS" ${ARGN})
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/spirv)
  file(MAKE_DIRECTORY ${out_dir})
  set(outputs)
  foreach(src ${ARG_SOURCES})
    # load.comp -> load_spv.h (compute passes); atrium.vert -> atrium_vert_spv.h (other stages)
    get_filename_component(name ${src} NAME_WE)
    get_filename_component(ext ${src} LAST_EXT)
    if(NOT ext STREQUAL ".comp")
      string(SUBSTRING ${ext} 1 -1 stage)
      set(name ${name}_${stage})
    endif()
    set(out ${out_dir}/${name}_spv.h)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.0 --quiet
              -I${CMAKE_CURRENT_SOURCE_DIR} -I${PROJECT_SOURCE_DIR}/shaders --vn ${name}_spv -o ${out}
              ${CMAKE_CURRENT_SOURCE_DIR}/${src}
      DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${src} ${ARG_DEPENDS}
      COMMENT "glslang: ${src}"
      VERBATIM)
    list(APPEND outputs ${out})
  endforeach()
  add_custom_target(${ARG_TARGET}_gen DEPENDS ${outputs})
  add_library(${ARG_TARGET} INTERFACE)
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_gen)
  target_include_directories(${ARG_TARGET} INTERFACE ${out_dir})
endfunction()
