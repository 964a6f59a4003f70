#!/usr/bin/env bash
# CTest `ci_local`: the CI recipe of examples/ci, as scripts/ci-local.sh runs it, over a small
# slice of the suite in 2 shards, twice: the first pipeline balances its shards with the static
# cost model, the second with the timings the first one's merge kept (a path that is relative in
# the CI recipes, recorded by its content's hash only). Each time: exit 0; the merged output holds
# junit.xml, results.json and the report, as plain files (no symlink: GitLab's artifacts follow
# none); every case of the slice once.
#   ci_local_test.sh SOURCE_DIR HDRCONFORM WORK_DIR
set -euo pipefail
src="$1"
hdrconform="$2"
work="$3"
filter='tonemap/shaper_pq/dev3_*,tonemap/shaper_pq/dev4_*'
rm -rf "$work"
mkdir -p "$work"
fail() {
  echo "ci_local: FAILED: $*" >&2
  exit 1
}
want="$("$hdrconform" list --filter "$filter" | wc -l)"
[ "$want" -gt 2 ] || fail "the slice has $want cases"
for pipeline in 1 2; do
  code=0
  HDRC_CI_DIR="$work/ci" HDRC_CI_NO_BUILD=1 HDRC_CI_BINARY="$hdrconform" \
    "$src/scripts/ci-local.sh" 2 --filter "$filter" -j 2 >"$work/log-$pipeline" 2>&1 || code=$?
  cat "$work/log-$pipeline"
  if [ "$code" = 3 ]; then  # no Vulkan device: as runner/ctest_run.sh judges it
    case "${HDRC_ALLOW_NO_VULKAN:-0}" in
      "" | 0 | false | no) fail "the Vulkan engine was unavailable (exit 3): nothing was checked" ;;
      *) echo "ci_local: skipped: no Vulkan device and HDRC_ALLOW_NO_VULKAN is set"; exit 77 ;;
    esac
  fi
  [ "$code" = 0 ] || fail "pipeline $pipeline: ci-local.sh exited $code"
  m="$work/ci/merged"
  for f in junit.xml results.json report/index.html; do
    [ -f "$m/$f" ] || fail "pipeline $pipeline: no $m/$f"
  done
  links="$(find "$work/ci" -type l | head -5)"
  [ -z "$links" ] || fail "pipeline $pipeline: symlinks in the outputs: $links"
  got="$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["cases"]))' "$m/results.json")"
  [ "$got" = "$want" ] || fail "pipeline $pipeline: merged $got cases, the slice has $want"
  plan="$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["provenance"]["shard_plan"])' "$m/results.json")"
  echo "ci_local: pipeline $pipeline: shard plan: $plan"
  case "$pipeline:$plan" in
    "1:static") ;;
    2:"timings sha256 "*" ($want cases timed)") ;;
    *) fail "pipeline $pipeline: unexpected shard plan '$plan'" ;;
  esac
  [ -f "$work/ci/timings/results.json" ] || fail "pipeline $pipeline kept no timings"
done
echo "ci_local: 2 pipelines of 2 shards, $want cases each, merged and published as plain files"
