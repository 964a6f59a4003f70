#!/usr/bin/env bash
# Set up, build and run every test under CTest: unit tests and the conformance run.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh"
cd "${HDRC_BUILD_DIR:-$root/build}"
exec ctest --output-on-failure -j"$(nproc)" "$@"
