# The cli_version test (tests/CMakeLists.txt), run with cmake -P -DCLI=<lowpair> -DEXPECTED=<version>:
# `lowpair --version` prints exactly "lowpair <version>" and exits 0.
execute_process(COMMAND ${CLI} --version RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out STREQUAL "lowpair ${EXPECTED}\n" OR NOT err STREQUAL "")
  message(FATAL_ERROR "lowpair --version: exit ${rc}, stdout '${out}', stderr '${err}'; "
                      "expected exit 0 and 'lowpair ${EXPECTED}'")
endif()
message(STATUS "${out}")
