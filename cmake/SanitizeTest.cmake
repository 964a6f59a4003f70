# The CTest test `sanitize` (label `sanitize`): scripts/sanitize.sh builds build-sanitize (clang,
# ASan + UBSan, fuzzers) beside this build and runs its unit tests, its conformance run (checking
# the goldens with another compiler and configuration) and a bounded run of each fuzzer. Off in the
# sanitizer build itself.
option(HDRC_SANITIZE_TEST "Add the CTest test that runs scripts/sanitize.sh (part of the test command)" ON)
if(HDRC_SANITIZE_TEST AND NOT HDRC_SANITIZE AND NOT HDRC_FUZZ)
  add_test(NAME sanitize COMMAND ${CMAKE_SOURCE_DIR}/scripts/sanitize.sh)
  # Started first (it is the longest), in parallel with the other tests. Its limit catches a hang,
  # not a slow machine: on a cold compiler cache the instrumented build alone takes about 20 of the
  # 2 cores' minutes while the main tests share them (measured 2026-11-26: build and tests 28.5
  # minutes on a machine also running a second build); 45 minutes at most.
  set_tests_properties(sanitize PROPERTIES LABELS "sanitize;goldens" COST 10000 TIMEOUT 2700)
endif()
