# plimsoll_embed_files(OUTPUT SCRIPT COMMENT INPUTS...): generates OUTPUT (a .cpp holding the
# INPUTS' text) with the cmake -P script SCRIPT, again whenever an input or the script changes.
# The OpenCL kernels (engine) and the GLSL shaders (editor) are embedded this way.
function(plimsoll_embed_files output script comment)
  string(REPLACE ";" "|" input_list "${ARGN}")
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${output} -DINPUTS=${input_list} -P ${script}
    DEPENDS ${ARGN} ${script}
    COMMENT "${comment}"
    VERBATIM)
endfunction()
