#!/usr/bin/env bash
# Installs hdrconform's build and test dependencies (Debian 12 packages) if any is missing.
# Idempotent: when everything is present it does nothing and touches no package index.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  libopenimageio-dev openimageio-tools libopenexr-dev libimath-dev
  libgtest-dev nlohmann-json3-dev libcli11-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-dev glslang-tools spirv-tools
  libopencolorio-dev ccache bubblewrap
)
# An XML parser for the tests that read junit.xml as a CI's JUnit publisher does.
packages+=(libexpat1-dev)
# The sanitizer build and the fuzzers (scripts/sanitize.sh, fuzz/): clang with its ASan, UBSan and
# libFuzzer runtimes (Debian puts those in libclang-rt-14-dev, which `clang` does not pull in).
packages+=(clang libclang-rt-14-dev)
# `goldens diff --since REV` reads the old goldens from git (runner/goldens_diff.h), and its test
# makes a repository.
packages+=(git)
# The real-GPU check (scripts/gpu-check.py), which CTest's gpu_check.lavapipe runs end to end.
packages+=(python3)
# The report's browser test (report/browser_test): Debian's Chromium, and Node.js with npm unless
# a node/npm is already on the PATH (e.g. NodeSource's nodejs, which bundles npm and conflicts
# with Debian's npm package).
packages+=(chromium)
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" != 0 ]; then sudo=sudo; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The browser test's npm dependencies (playwright-core, which drives /usr/bin/chromium; it never
# downloads a browser), from its package-lock.json. Reinstalled only when the lock file changes.
browser_test="$(cd "$(dirname "$0")/.." && pwd)/report/browser_test"
stamp="$browser_test/node_modules/.hdrc-lock.sha256"
lock_sum="$(sha256sum "$browser_test/package-lock.json" | cut -d' ' -f1)"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$lock_sum" ]; then
  echo "setup: npm ci in report/browser_test" >&2
  (cd "$browser_test" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  echo "$lock_sum" >"$stamp"
fi
