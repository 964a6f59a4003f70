#!/usr/bin/env bash
# The main job: set up, build, run the full conformance suite (reference vs the Vulkan engine on
# lavapipe), print one line per case, a summary and the report's path. Extra arguments go to
# `hdrconform run` (e.g. --device NAME, --filter GLOB, --out DIR).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh"
exec "${HDRC_BUILD_DIR:-$root/build}/runner/hdrconform" run --out "$root/out" "$@"
