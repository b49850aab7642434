# Fails when a source folder includes a folder of a layer above its own. A path tells what it
# may include: each folder of engine/src, engine/include/plimsoll and editor/ belongs to one
# layer (the table below, which is the target graph of engine/CMakeLists.txt and
# editor/CMakeLists.txt), and a layer may include its own folders and those of the layers it
# lists. Includes are read line by line, whatever preprocessor condition they sit behind:
#   "plimsoll/<folder>/..."  an engine header
#   "<folder>/..."           an engine private header (engine/src) or an editor header
# Usage: cmake -DPROJECT_DIR=<source root> -P check_layers.cmake
cmake_minimum_required(VERSION 3.25)

# layer: its folders
set(folders_core      "core;geometry;bake;physics;graph;plimsoll_eval")
set(folders_compute   "compute")
set(folders_graph_auto "graph_auto")
set(folders_repair    "repair")
set(folders_surface   "surface")
set(folders_samples   "samples")
set(folders_io        "io")
set(folders_scene     "scene")
set(folders_project   "project")
set(folders_export    "export")
set(folders_document  "document")
set(folders_view      "view")
set(folders_render    "render")
set(folders_executable "app;cli")
# The runtime library (engine/runtime, its own build): its public headers, outside the engine.
set(folders_runtime   "plimsoll_runtime")

# layer: the layers below it that it may include (transitively closed by hand: each line lists
# everything the layer sees)
set(sees_core       "")
set(sees_compute    "core")
set(sees_graph_auto "core")
set(sees_repair     "core")
set(sees_surface    "core")
set(sees_samples    "core")
set(sees_io         "core;surface;runtime")
set(sees_scene      "core;compute;surface")
set(sees_project    "core;compute;surface;graph_auto;repair;io;scene")
set(sees_export     "core;compute;surface;graph_auto;repair;io;scene;project;runtime")
set(engine_layers   "core;compute;graph_auto;repair;surface;samples;io;scene;project;export")
set(sees_document   "${engine_layers}")
set(sees_view       "${engine_layers};document")
set(sees_render     "${engine_layers};document;view")
set(sees_executable "${engine_layers};document;view;render;runtime")

set(layers core compute graph_auto repair surface samples io scene project export
           document view render executable runtime)
foreach(layer IN LISTS layers)
  foreach(folder IN LISTS folders_${layer})
    set(layer_of_${folder} ${layer})
  endforeach()
endforeach()

if(NOT PROJECT_DIR)
  message(FATAL_ERROR "usage: cmake -DPROJECT_DIR=<source root> -P check_layers.cmake")
endif()

set(roots "engine/src" "engine/include/plimsoll" "engine/eval/include" "editor")
set(problems "")
set(checked 0)
foreach(root IN LISTS roots)
  file(GLOB_RECURSE sources RELATIVE "${PROJECT_DIR}/${root}"
       "${PROJECT_DIR}/${root}/*.cpp" "${PROJECT_DIR}/${root}/*.h" "${PROJECT_DIR}/${root}/*.hpp")
  foreach(source IN LISTS sources)
    string(REGEX MATCH "^[^/]+" folder "${source}")
    if(NOT DEFINED layer_of_${folder})
      if(source MATCHES "/")
        list(APPEND problems "${root}/${source}: folder '${folder}' has no layer in cmake/check_layers.cmake")
      endif()
      continue()
    endif()
    set(layer ${layer_of_${folder}})
    set(allowed ${folders_${layer}})
    foreach(seen IN LISTS sees_${layer})
      list(APPEND allowed ${folders_${seen}})
    endforeach()
    file(STRINGS "${PROJECT_DIR}/${root}/${source}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    math(EXPR checked "${checked} + 1")
    foreach(line IN LISTS lines)
      if(NOT line MATCHES "#[ \t]*include[ \t]*\"(plimsoll/)?([a-z_0-9]+)/")
        continue()
      endif()
      set(target_folder "${CMAKE_MATCH_2}")
      if(NOT DEFINED layer_of_${target_folder})
        continue()  # not a folder of this project (a library's own header)
      endif()
      if(NOT target_folder IN_LIST allowed)
        string(STRIP "${line}" line)
        list(APPEND problems
          "${root}/${source}: ${line}: layer '${layer}' may not include '${target_folder}/' (layer '${layer_of_${target_folder}}')")
      endif()
    endforeach()
  endforeach()
endforeach()

if(problems)
  list(JOIN problems "\n  " text)
  message(FATAL_ERROR "includes across layers (cmake/check_layers.cmake):\n  ${text}")
endif()
message(STATUS "check_layers: ${checked} files, every include within its layer")
