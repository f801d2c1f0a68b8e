#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian 12 packages pdgrain needs, only those missing. Idempotent; silent when
# everything is there; runs `apt-get update` only when something is missing.
set -euo pipefail
packages=(
  build-essential cmake ninja-build git pkg-config
  libopenmpi-dev openmpi-bin libhdf5-openmpi-dev hdf5-tools
  libgmsh-dev libcgal-dev libmetis-dev libeigen3-dev libvtk9-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libgtest-dev libbenchmark-dev
  python3-h5py python3-meshio python3-numpy python3-matplotlib python3-pytest
  libyaml-cpp-dev python3-jsonschema
  paraview
)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "pdgrain: installing missing Debian packages: ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "pdgrain: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "pdgrain: packages installed"
