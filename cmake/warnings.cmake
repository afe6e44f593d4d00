# One warnings policy for every target of this tree (CONTRIBUTING.md): the library, the harness rooms, the
# CLI, the tests, the benchmarks, the Python module, the examples and the fuzz targets call
# lowpair_warnings(<target>). Third-party headers come in through imported targets, whose include
# directories are SYSTEM (their warnings are not ours); a directory added by hand is added SYSTEM.
# LOWPAIR_WERROR=ON (CI: .ci/run) turns every warning into an error; off by default, so that a user's newer
# compiler with a new warning still builds.
option(LOWPAIR_WERROR "Treat warnings in lowpair's own code as errors (CI turns it on)" OFF)
set(LOWPAIR_WARNING_FLAGS -Wall -Wextra -Wpedantic -Wshadow)
if(LOWPAIR_WERROR)
  list(APPEND LOWPAIR_WARNING_FLAGS -Werror)
endif()

function(lowpair_warnings)
  foreach(target ${ARGN})
    target_compile_options(${target} PRIVATE ${LOWPAIR_WARNING_FLAGS})
  endforeach()
endfunction()
