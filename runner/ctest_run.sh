#!/bin/sh
# How CTest judges an `hdrconform run` (runner/CMakeLists.txt: conformance groups, validation,
# worst model): `ctest_run.sh WHAT HDRCONFORM ARGS...` runs HDRCONFORM ARGS and maps its exit code
# (README.md, "Exit codes") onto CTest's pass/fail/skip:
#   4 (pass with warnings)   passes, after saying so (the warnings are in the run's output);
#   3 (engine unavailable)   FAILS: a run that asked for a Vulkan device and got none checked
#                            nothing, and a green CI must not mean that. On a machine without
#                            Vulkan, HDRC_ALLOW_NO_VULKAN=1 makes it a skip instead (exit 77,
#                            the tests' SKIP_RETURN_CODE);
#   anything else            is the test's result as it is.
what="$1"
shift
"$@"
rc=$?
case "$rc" in
  4)
    echo "$what: pass with warnings (exit 4)"
    exit 0
    ;;
  3)
    case "${HDRC_ALLOW_NO_VULKAN:-0}" in
      "" | 0 | false | no)
        echo "$what: FAILED: the candidate engine was unavailable (exit 3), so nothing was" \
          "checked; on a machine without Vulkan, HDRC_ALLOW_NO_VULKAN=1 makes this a skip" >&2
        exit 3
        ;;
      *)
        echo "$what: skipped: the candidate engine was unavailable (exit 3) and" \
          "HDRC_ALLOW_NO_VULKAN is set"
        exit 77
        ;;
    esac
    ;;
esac
exit "$rc"
