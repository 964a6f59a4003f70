#!/usr/bin/env bash
# Installs missing dependencies, configures once and builds incrementally. HDRC_BUILD_DIR: the
# build folder (default build/); HDRC_BUILD_TYPE: CMake's build type (default RelWithDebInfo;
# Release, Debug, ... — a folder configured with another type is reconfigured).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
build="${HDRC_BUILD_DIR:-$root/build}"
type="${HDRC_BUILD_TYPE:-}"
# ccache (CMakeLists.txt) shares its cache between clones of this tree in different folders
# (a CI runner's fresh clone, a second worktree): paths under the tree are hashed relative to the
# build folder, and the build folder itself is not hashed. The cost: a cached object's debug info
# names the folder it was first compiled in. A caller's own settings win.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"
configured_type="$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$build/CMakeCache.txt" 2>/dev/null || true)"
if [ ! -f "$build/CMakeCache.txt" ] || { [ -n "$type" ] && [ "$type" != "$configured_type" ]; }; then
  cmake -S "$root" -B "$build" -G Ninja ${type:+-DCMAKE_BUILD_TYPE="$type"} >/dev/null
fi
# Ninja's progress lines are filtered out; a failed build fails this script (pipefail carries
# cmake's status; grep's "nothing left to print" is not a failure).
cmake --build "$build" -- -j"$(nproc)" | { grep -vE '^\[[0-9]+/[0-9]+\] ' || true; }
test -x "$build/runner/hdrconform"
