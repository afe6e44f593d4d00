# One warnings policy for every target of this tree (CONTRIBUTING.md): the library, the harness rooms, the
# CLI, the tests, the benchmarks, the Python module, the examples and the fuzz targets call
# lowpair_warnings(<target>...). Third-party headers come in through imported targets, whose include
# directories are SYSTEM (their warnings are not ours); a directory added by hand is added SYSTEM.
# LOWPAIR_WERROR=ON (CI: .ci/run) turns every warning into an error; off by default, so that a user's newer
# compiler with a new warning still builds. A target's own -Wno-... goes after its lowpair_warnings call.
option(LOWPAIR_WERROR "Treat warnings in lowpair's own code as errors (CI turns it on)" OFF)

# The flags are spelled inside the function (functions are global, variables are not): the fuzz build adds
# this tree with add_subdirectory and calls it from its own scope (tests/fuzz/CMakeLists.txt).
function(lowpair_warnings)
  set(flags -Wall -Wextra -Wpedantic -Wshadow)
  if(LOWPAIR_WERROR)
    list(APPEND flags -Werror)
  endif()
  foreach(target ${ARGN})
    target_compile_options(${target} PRIVATE ${flags})
  endforeach()
endfunction()
