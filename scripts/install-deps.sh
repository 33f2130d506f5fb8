#!/usr/bin/env bash
# Installs the Debian 12 packages incise builds and tests with (oneTBB for the global DFFD's mapping; the viewer:
# GLFW, libepoxy, Dear ImGui, libpng; its pictures: Xvfb and Mesa's llvmpipe through GLX or EGL, no GPU needed;
# the fuzz harnesses: clang 14 and its runtime libraries (libFuzzer, the sanitizers: libclang-rt-14-dev is
# only recommended by clang-14), llvm-14's llvm-symbolizer for the sanitizers' stacks; the Python module:
# pybind11, Python's headers, numpy, pytest for its tests, matplotlib for its examples; Doxygen for the API
# reference). Idempotent: only what is missing is installed.
# Nothing is fetched from anywhere but Debian's package archive.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libopenmesh-dev libtet1.5-dev libglfw3-dev libspdlog-dev catch2 libhidapi-dev
  nlohmann-json3-dev libcli11-dev libcgal-dev libtbb-dev
  clang-format universal-ctags util-linux python3
  libepoxy-dev libimgui-dev libstb-dev libpng-dev
  xvfb xauth libgl1-mesa-dri libglx-mesa0 libegl-mesa0 libegl1
  gnuplot-nox parallel xdotool
  clang-14 libclang-rt-14-dev llvm-14
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib doxygen
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
