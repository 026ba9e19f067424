#!/usr/bin/env bash
# Installs the Debian packages Tumble needs, only those missing (a no-op on a ready machine).
set -euo pipefail
pkgs=(build-essential cmake pkg-config git
      libopenmpi-dev openmpi-bin petsc-dev libhdf5-openmpi-dev libeigen3-dev libcli11-dev
      googletest libgtest-dev libtomlplusplus-dev
      python3 python3-numpy python3-scipy python3-h5py python3-matplotlib python3-pil
      chromium)  # the report test loads the HTML report in headless Chromium
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[install] apt-get install ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
