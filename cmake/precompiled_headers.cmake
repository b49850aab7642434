# Precompiled headers for the targets whose files each parse the same large headers (the tests,
# the CLI and the editor): about half of such a file's compile time is parsing GoogleTest,
# nlohmann/json, Eigen and CLI11, and a precompiled header parses them once per target. A
# test file: 33 s without, 12 s with (at -O1; 59 s and 30 s under the sanitizers), measured
# with g++ 12 on the CI machine's kind of core. The engine's libraries compile without them, so
# that a missing include there still fails the build.
#
# ccache caches compiles that use a precompiled header only with the sloppiness below; where
# the compiler launcher is ccache, it runs with it.
set(PLIMSOLL_PCH_COMMON
  <algorithm> <array> <cmath> <cstdint> <filesystem> <fstream> <functional> <map> <memory>
  <optional> <sstream> <string> <string_view> <unordered_map> <vector>
  <Eigen/Dense> <nlohmann/json.hpp>)

# The two builds of a CI run (the full one, and the one without OpenCL, CGAL and GUI under the
# sanitizers) compile different code, so ccache gives neither the other's objects with or
# without them; each compiles whole in a cold run, and faster with them.
# PLIMSOLL_PRECOMPILED_HEADERS=OFF turns them off.
option(PLIMSOLL_PRECOMPILED_HEADERS "Precompiled headers for the tests, the CLI and the editor" ON)

# plimsoll_precompile_headers(TARGET [HEADER ...]): the common headers and the extra ones.
function(plimsoll_precompile_headers target)
  if(PLIMSOLL_PRECOMPILED_HEADERS)
    target_precompile_headers(${target} PRIVATE ${PLIMSOLL_PCH_COMMON} ${ARGN})
  endif()
endfunction()

if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache$")
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env
      CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
      ${CMAKE_CXX_COMPILER_LAUNCHER})
endif()

# Unity builds for the same targets: their files are compiled in batches, each batch one
# translation unit, so that the inline code of the large headers (CLI11's whole App with its
# virtual functions, GoogleTest's and nlohmann/json's templates), which a precompiled header
# parses once but every file still compiles and optimises, is compiled once per batch. Files
# of one target therefore share one namespace scope: a helper in an anonymous namespace needs a
# name of its own in the target. PLIMSOLL_UNITY_BUILD=OFF compiles file by file.
option(PLIMSOLL_UNITY_BUILD "Compile the tests, the CLI and the editor in batches of files" ON)

# plimsoll_unity_build(TARGET BATCH_SIZE): files per translation unit. Smaller batches keep
# both of CI's cores busy and rebuild less after an edit; larger ones compile less in all.
function(plimsoll_unity_build target batch_size)
  if(PLIMSOLL_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${batch_size})
    # g++ takes a type of a file's anonymous namespace used in a class of the same file for one
    # from a header once the file is included into a batch: not a problem of one file alone.
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
endfunction()
