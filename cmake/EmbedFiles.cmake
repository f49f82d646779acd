# cvc_embed_files(TARGET <name> SOURCES <file> ...)
#
# Embeds each file byte for byte in a generated header <file name, '.' as '_'>.h in the build
# tree, holding `inline constexpr unsigned char <file name, '.' as '_'>[]` (no terminating zero)
# in namespace cvc_embedded. <name> becomes an INTERFACE target whose include path reaches the
# headers, so the binary carries the files (the review page's HTML, script and style) and looks
# nothing up at run time. The headers are regenerated at build time when a file changes.
#
# Run as a script (cmake -DINPUT=... -DOUTPUT=... -DSYMBOL=... -P EmbedFiles.cmake) it writes one
# header; the function adds that step as a custom command.
if(CMAKE_SCRIPT_MODE_FILE)
  file(READ "${INPUT}" hex HEX)
  string(LENGTH "${hex}" hex_length)
  math(EXPR byte_count "${hex_length} / 2")
  string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
  # 24 bytes a line keeps the generated header readable in a debugger (CMake's regular
  # expressions have no {n}, so the group is spelled out).
  string(REPEAT "0x..," 24 line)
  string(REGEX REPLACE "(${line})" "\\1\n" bytes "${bytes}")
  file(WRITE "${OUTPUT}" "// Generated from ${INPUT} by cmake/EmbedFiles.cmake; do not edit.\n#pragma once\n\n"
       "namespace cvc_embedded {\ninline constexpr unsigned char ${SYMBOL}[${byte_count}] = {\n${bytes}\n};\n}\n")
  return()
endif()

set(CVC_EMBED_SCRIPT "${CMAKE_CURRENT_LIST_FILE}")

function(cvc_embed_files)
  cmake_parse_arguments(ARG "" "TARGET" "SOURCES" ${ARGN})
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/embedded")
  file(MAKE_DIRECTORY "${out_dir}")
  set(headers)
  foreach(src IN LISTS ARG_SOURCES)
    get_filename_component(name "${src}" NAME)
    string(MAKE_C_IDENTIFIER "${name}" symbol)
    set(header "${out_dir}/${symbol}.h")
    add_custom_command(
      OUTPUT "${header}"
      COMMAND "${CMAKE_COMMAND}" -DINPUT=${CMAKE_CURRENT_SOURCE_DIR}/${src} -DOUTPUT=${header}
              -DSYMBOL=${symbol} -P "${CVC_EMBED_SCRIPT}"
      DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/${src}" "${CVC_EMBED_SCRIPT}"
      COMMENT "Embedding ${src}"
      VERBATIM)
    list(APPEND headers "${header}")
  endforeach()
  add_custom_target(${ARG_TARGET}_headers DEPENDS ${headers})
  add_library(${ARG_TARGET} INTERFACE)
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_headers)
  target_include_directories(${ARG_TARGET} INTERFACE "${out_dir}")
endfunction()
