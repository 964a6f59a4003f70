#!/usr/bin/env bash
# The CI recipe of examples/ci/ (github-actions.yml, gitlab-ci.yml), run here: the same commands
# in the same order, the N shard jobs one after another instead of side by side.
#
#   scripts/ci-local.sh N [RUN ARGS...]      e.g. scripts/ci-local.sh 2 --filter 'tonemap/*'
#
# 1. setup and build (each CI job does this; ccache makes the later ones fast);
# 2. shard K of N: `hdrconform run --shard K/N`, balanced with the timings the last merged run
#    kept (timings/results.json, a CI cache; the static cost model on the first run); a shard
#    job passes whenever the shard wrote its output (exit 0, 1, 3 or 4): the merge decides;
# 3. merge: `hdrconform merge merged shard-1 .. shard-N`; its exit code is the pipeline's
#    verdict (README.md, "Exit codes"; 4, pass with warnings, passes);
# 4. the merged results.json becomes the next run's timings (the CI saves the cache);
# 5. the artifacts: merged/junit.xml (published as test results), merged/results.json and
#    merged/report/.
#
# Everything is written under HDRC_CI_DIR (default ci-out/). HDRC_CI_NO_BUILD=1 skips step 1
# and runs HDRC_CI_BINARY (default build/runner/hdrconform): how CTest runs this script
# (runner/ci_local_test.sh) from inside a build. Exit code: the merge's, with 4 mapped to 0.
set -euo pipefail
if [ $# -lt 1 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: scripts/ci-local.sh N [hdrconform run arguments...]  (N: the number of shards)" >&2
  exit 2
fi
n="$1"
shift
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
ci="${HDRC_CI_DIR:-$root/ci-out}"
mkdir -p "$ci"

# 1. Set up and build (examples/ci: the `build` step of every job).
if [ "${HDRC_CI_NO_BUILD:-0}" != 1 ]; then
  ./scripts/setup.sh
  ./scripts/build.sh
fi
hdrconform="${HDRC_CI_BINARY:-$root/build/runner/hdrconform}"

# 2. The shards. The timings file has one path for every shard (relative in the CI recipes;
#    results.json records only its hash: provenance.shard_plan), so all of them plan alike.
timings=()
if [ -f "$ci/timings/results.json" ]; then
  timings=(--timings "$ci/timings/results.json")
  echo "ci-local: shards balanced with $ci/timings/results.json (the last merged run)"
else
  echo "ci-local: no timings yet: shards balanced with the static cost model"
fi
shards=()
for k in $(seq 1 "$n"); do
  echo "ci-local: shard $k/$n"
  code=0
  "$hdrconform" run --shard "$k/$n" "${timings[@]}" --out "$ci/shard-$k" "$@" || code=$?
  case "$code" in
    0 | 1 | 3 | 4) ;;  # the shard's output is complete; the merge judges the run
    *)
      echo "ci-local: shard $k/$n failed with exit $code (bad input or interrupted)" >&2
      exit "$code"
      ;;
  esac
  shards+=("$ci/shard-$k")
done

# 3. The merge: one results.json, junit.xml and report, and the run's exit code.
echo "ci-local: merge"
code=0
"$hdrconform" merge "$ci/merged" "${shards[@]}" || code=$?

# 4. The merged run's per-case seconds balance the next run's shards (the CI's cache save).
if [ -f "$ci/merged/results.json" ]; then
  mkdir -p "$ci/timings"
  cp "$ci/merged/results.json" "$ci/timings/results.json.tmp"
  mv "$ci/timings/results.json.tmp" "$ci/timings/results.json"
fi

# 5. The artifacts.
echo "ci-local: artifacts: $ci/merged/junit.xml $ci/merged/results.json $ci/merged/report/"
case "$code" in
  0) echo "ci-local: pass" ;;
  4) echo "ci-local: pass with warnings (exit 4)"; code=0 ;;
  *) echo "ci-local: exit $code (README.md, \"Exit codes\")" >&2 ;;
esac
exit "$code"
