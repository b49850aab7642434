# The simulation core must not depend on file formats, OpenCL or CGAL: these are the libraries
# it may never link, directly or through another target. The same list is what
# cmake/check_core_includes.cmake looks for in the core's preprocessed includes.
set(PLIMSOLL_CORE_FORBIDDEN_LINKS
  "^assimp" "^OpenEXR" "^Imath" "^nlohmann_json" "^CGAL" "^OpenCL" "^OpenSSL" "^PkgConfig::STB"
  "^(-l)?(ssl|crypto|OpenCL|assimp|gmp|mpfr)$")
# The layers above the core that still promise to read and write no file (surface, scene)
# may run on OpenCL, but link no file format.
set(PLIMSOLL_NO_FILE_FORBIDDEN_LINKS
  "^assimp" "^OpenEXR" "^Imath" "^nlohmann_json" "^OpenSSL" "^PkgConfig::STB"
  "^(-l)?(ssl|crypto|assimp)$"
  "^plimsoll_(io|project|export)$")

# Every library `target` links, through all the targets it links (their INTERFACE and, for
# static libraries, private link dependencies), into `out`.
function(plimsoll_collect_links target out)
  set(seen "")
  set(pending ${target})
  while(pending)
    list(POP_FRONT pending current)
    if(current IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${current})
    if(NOT TARGET ${current})
      continue()
    endif()
    get_target_property(type ${current} TYPE)
    set(links "")
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(direct ${current} LINK_LIBRARIES)
      if(direct)
        list(APPEND links ${direct})
      endif()
    endif()
    get_target_property(interface ${current} INTERFACE_LINK_LIBRARIES)
    if(interface)
      list(APPEND links ${interface})
    endif()
    foreach(link IN LISTS links)
      # $<LINK_ONLY:x> is how a static library passes on its private dependencies.
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" link "${link}")
      list(APPEND pending ${link})
    endforeach()
  endwhile()
  list(REMOVE_ITEM seen ${target})
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

# Stops the configure when `target` links a forbidden library.
function(plimsoll_check_core_links target)
  plimsoll_check_links(${target} PLIMSOLL_CORE_FORBIDDEN_LINKS
    "the simulation core may link Eigen and the thread library only (file formats, OpenCL and CGAL belong in the adapters that link the core)")
endfunction()

# Stops the configure when `target`, a layer that reads and writes no file, links a file
# format or a layer that does.
function(plimsoll_check_no_file_links target)
  plimsoll_check_links(${target} PLIMSOLL_NO_FILE_FORBIDDEN_LINKS
    "${target} reads and writes no file (file formats belong in plimsoll_io and the layers above it)")
endfunction()

function(plimsoll_check_links target patterns_variable why)
  plimsoll_collect_links(${target} links)
  foreach(link IN LISTS links)
    foreach(pattern IN LISTS ${patterns_variable})
      if(link MATCHES "${pattern}")
        message(FATAL_ERROR "${target} links ${link}: ${why}. All it links: ${links}")
      endif()
    endforeach()
  endforeach()
endfunction()
