# Unity builds (docs/building.md): a target's sources compiled a few at a time as one file, so that the headers
# they share (Eigen, nlohmann/json, yaml-cpp, CLI11, the standard library) are parsed, and their templates
# instantiated, once per batch instead of once per file. Measured on the 2-vCPU machine, g++ 12 Release, cold: the
# CLI with the library and the rooms below it took 421 CPU-s file by file and about half of that in batches.
# LOWPAIR_UNITY_BUILD=OFF compiles file by file (a change then recompiles one file instead of its batch).
#
# What it asks of the sources: a name at namespace scope (an anonymous namespace's too) is unique within its
# target, as if the target were one file. A file that must stay alone (a hot path, whose code the benchmarks
# time as it was) is named after EXCEPT.
option(LOWPAIR_UNITY_BUILD "Compile the library, the harness rooms, the CLI and the Python module in batches" ON)

# lowpair_unity(<target> [EXCEPT <source>...])
function(lowpair_unity target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "EXCEPT")
  if(NOT LOWPAIR_UNITY_BUILD)
    return()
  endif()
  # 8 files a batch (CMake's default): the library and most rooms still give both cores a batch
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  if(arg_EXCEPT)
    set_source_files_properties(${arg_EXCEPT} TARGET_DIRECTORY ${target} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
  endif()
endfunction()
