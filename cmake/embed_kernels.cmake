# Writes a C++ source defining kBuoyancyKernelSource: the shared header followed by the kernel
# files, as one raw string literal, so the binary carries its kernels and runs from anywhere.
# Usage: cmake -DOUTPUT=file.cpp -DINPUTS="a.h|b.cl" -P embed_kernels.cmake
string(REPLACE "|" ";" INPUTS "${INPUTS}")
set(text "")
foreach(input IN LISTS INPUTS)
  file(READ "${input}" content)
  get_filename_component(name "${input}" NAME)
  string(APPEND text "// ---- ${name}\n${content}\n")
endforeach()
if(text MATCHES "\\)PLIMSOLL_CL\"")
  message(FATAL_ERROR "kernel sources contain the raw-string delimiter")
endif()
file(WRITE "${OUTPUT}.new"
  "// Generated from kernels/ by cmake/embed_kernels.cmake. Do not edit.\n"
  "namespace plimsoll::detail {\n"
  "extern const char* const kBuoyancyKernelSource;\n"
  "const char* const kBuoyancyKernelSource = R\"PLIMSOLL_CL(${text})PLIMSOLL_CL\";\n"
  "}\n")
file(COPY_FILE "${OUTPUT}.new" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.new")
