#!/usr/bin/env bash
# Installs the Debian packages snert needs, only those missing. Idempotent: a second run
# on a ready machine does nothing but check. `--bench` adds the packages of `make bench`.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libglfw3-dev libimgui-dev libglm-dev libosmesa6-dev libegl-dev libgl1-mesa-dri libstb-dev
  python3-glad fonts-dejavu-core
  libgtest-dev libgmock-dev libbenchmark-dev libtbb-dev nlohmann-json3-dev
  libinsighttoolkit5-dev zlib1g-dev libcli11-dev
  xvfb xauth x11-apps imagemagick
  clang clang-format libclang-rt-14-dev
  tetgen libmeshoptimizer-dev
  python3-meshio python3-vtk9  # the fe_formats test reads the FE formats back with them
)
# `make bench` only (scripts/setup.sh --bench): VTK's flying edges as the peer, and numpy for
# making the CT benchmark volume (python3-vtk9 is in the list above already, for the tests).
if [ "${1:-}" = "--bench" ]; then
  packages+=(python3-vtk9 python3-numpy)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "snert setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
