# cvc_add_shaders(TARGET <name> SOURCES <a.comp> ... DEPENDS <x.glsl> ...)
#
# Compiles each GLSL compute shader to SPIR-V with glslangValidator and embeds it as a
# uint32_t array in a generated header <stem>_spv.h (array name <stem>_spv) in the build tree.
# <name> becomes an INTERFACE target whose include path reaches the generated headers, so
# the binary carries its shaders and looks nothing up at run time.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

function(cvc_add_shaders)
  cmake_parse_arguments(ARG "" "TARGET" "SOURCES;DEPENDS" ${ARGN})
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/generated")
  file(MAKE_DIRECTORY "${out_dir}")
  set(headers)
  foreach(src IN LISTS ARG_SOURCES)
    get_filename_component(stem "${src}" NAME_WE)
    set(header "${out_dir}/${stem}_spv.h")
    add_custom_command(
      OUTPUT "${header}"
      COMMAND "${GLSLANG_VALIDATOR}" -V --target-env vulkan1.1 --quiet
              -I"${CMAKE_CURRENT_SOURCE_DIR}" --vn "${stem}_spv"
              -o "${header}" "${CMAKE_CURRENT_SOURCE_DIR}/${src}"
      DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/${src}" ${ARG_DEPENDS}
      COMMENT "Compiling shader ${src} to SPIR-V"
      VERBATIM)
    list(APPEND headers "${header}")
  endforeach()
  add_custom_target(${ARG_TARGET}_spirv DEPENDS ${headers})
  add_library(${ARG_TARGET} INTERFACE)
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_spirv)
  target_include_directories(${ARG_TARGET} INTERFACE "${out_dir}" "${CMAKE_CURRENT_SOURCE_DIR}")
endfunction()
