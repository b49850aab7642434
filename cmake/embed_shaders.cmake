# Writes a C++ source defining one string per GLSL file (render/shaders.h declares them):
# "mesh.vert" becomes plimsoll::editor::shaders::mesh_vert, a raw string literal of the file, so
# the binary carries its shaders and the sources stay files a GLSL tool can read.
# Usage: cmake -DOUTPUT=file.cpp -DINPUTS="a.vert|b.frag" -P embed_shaders.cmake
string(REPLACE "|" ";" INPUTS "${INPUTS}")
set(text "// Generated from editor/render/shaders/ by cmake/embed_shaders.cmake. Do not edit.\n")
string(APPEND text "namespace plimsoll::editor::shaders {\n")
foreach(input IN LISTS INPUTS)
  file(READ "${input}" content)
  if(content MATCHES "\\)PLIMSOLL_GLSL\"")
    message(FATAL_ERROR "${input} contains the raw-string delimiter")
  endif()
  get_filename_component(name "${input}" NAME)
  string(REPLACE "." "_" symbol "${name}")
  string(APPEND text "extern const char* const ${symbol};\n")
  string(APPEND text "const char* const ${symbol} = R\"PLIMSOLL_GLSL(${content})PLIMSOLL_GLSL\";\n")
endforeach()
string(APPEND text "}\n")
file(WRITE "${OUTPUT}.new" "${text}")
file(COPY_FILE "${OUTPUT}.new" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.new")
