# One bounded libFuzzer run for ctest (fuzz/<target>_run): FUZZER for SECONDS, new inputs into
# SCRATCH, seeds read from SEEDS, crash inputs written to ARTIFACTS, with the dictionary DICT.
# Fails when libFuzzer finds a crash, a timeout, a leak or an out-of-memory.
file(MAKE_DIRECTORY ${SCRATCH} ${ARTIFACTS})
set(_dict)
if(EXISTS ${DICT})
  set(_dict -dict=${DICT})
endif()
execute_process(
  COMMAND ${FUZZER} ${SCRATCH} ${SEEDS} ${_dict} -max_total_time=${SECONDS} -timeout=10 -rss_limit_mb=2048
          -artifact_prefix=${ARTIFACTS}/ -print_final_stats=1
  RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "${FUZZER} failed (${_rc}); the input is in ${ARTIFACTS}/. Reproduce with `${FUZZER} FILE`, "
                      "minimise with -minimize_crash=1, and keep it in tests/fuzz/regressions/ (docs/testing.md, Fuzzing)")
endif()
