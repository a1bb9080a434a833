#!/usr/bin/env bash
# Installs the Debian packages gazetrace builds and tests with. Idempotent: asks dpkg
# which are missing and, only when some are, runs `apt-get update` then installs just those.
# Not root: prints the one apt-get line to run and exits non-zero.
set -euo pipefail

PACKAGES=(
  cmake ninja-build g++ pkg-config
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools
  libglfw3-dev libglm-dev libosd-dev libtinygltf-dev libstb-dev
  libv4l-dev libopencv-dev
  nlohmann-json3-dev libgtest-dev libbenchmark-dev libcli11-dev libimgui-dev
  xvfb xauth
  clang libclang-rt-dev
  # OpenXR: the loader gazetrace links, and what ../shared/tools/monado.sh needs to build the
  # Monado runtime the OpenXR tests run against (its PACKAGES list), so nothing installs at test time.
  libopenxr-dev libopenxr-loader1
  libudev-dev libeigen3-dev libx11-dev libxrandr-dev libxcb-randr0-dev libx11-xcb-dev libbsd-dev
  libcjson-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "gazetrace: missing Debian packages; run as root:" >&2
  echo "  sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi

echo "gazetrace: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"
