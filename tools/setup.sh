#!/usr/bin/env bash
# Install what gimp needs from Debian (when missing) and build it in ./build (Release).
# Usage: tools/setup.sh            (from anywhere; builds <repo>/build)
# With CI=true the build is configured with -DGIMP_WERROR=ON: any compiler warning fails it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
packages=(cmake g++ make pkg-config openmpi-bin petsc-dev slepc-dev libeigen3-dev
          libhdf5-openmpi-dev libgtest-dev python3 python3-numpy python3-matplotlib python3-h5py)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi
# In CI (CI=true) compiler warnings are errors; elsewhere they are only reported.
werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DGIMP_WERROR="$werror" >/dev/null
cmake --build "$root/build" -j"$(nproc)"
