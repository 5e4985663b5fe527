# ctest script: every mutation patch (tests/mutations/*.patch, tests/mutations/techniques/*.patch)
# still applies to the source tree as it is, so a refactor cannot leave a mutation that
# scripts/mutation-check.sh would refuse as a setup error, unnoticed until the next mutation run.
# Only checks (git apply --check): the tree is never changed.
file(GLOB patches ${SOURCE_DIR}/tests/mutations/*.patch ${SOURCE_DIR}/tests/mutations/techniques/*.patch)
if(NOT patches)
  message(FATAL_ERROR "no mutation patches found under ${SOURCE_DIR}/tests/mutations")
endif()
set(stale "")
list(LENGTH patches count)
foreach(patch IN LISTS patches)
  execute_process(COMMAND ${GIT} apply --check ${patch} WORKING_DIRECTORY ${SOURCE_DIR}
                  RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
  if(NOT rc EQUAL 0)
    string(APPEND stale "  ${patch}:\n${err}")
  endif()
endforeach()
if(NOT stale STREQUAL "")
  message(FATAL_ERROR "mutation patches that no longer apply (regenerate each against the current code):\n${stale}")
endif()
message(STATUS "all ${count} mutation patches apply")
