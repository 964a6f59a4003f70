#!/usr/bin/env bash
# Installs hdrconform's build and test dependencies (Debian 12 packages) if any is missing.
# Idempotent: when everything is present it does nothing and touches no package index.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  libopenimageio-dev libopenexr-dev libimath-dev
  libgtest-dev nlohmann-json3-dev libcli11-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-dev spirv-tools
  libopencolorio-dev ccache
)
if [ "${HDRC_WITH_BROWSER:-0}" = 1 ]; then packages+=(chromium nodejs npm); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" != 0 ]; then sudo=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
