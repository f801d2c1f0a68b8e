#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian 12 packages pdgrain needs, only those missing. Idempotent; silent when
# everything is there; runs `apt-get update` only when something is missing.
# `install-deps.sh --slurm` also installs Slurm and munge (slurm-wlm: slurmctld, slurmd, sbatch)
# for the single-node Slurm test of workflows/sweep (tests/slurm); the daemons are not started.
# `install-deps.sh --fuzz` also installs clang 16 with its libFuzzer/sanitizer runtimes and llvm's
# symbolizer (`make test-asan`, `make fuzz`: clang 14 cannot compile std::source_location of
# libstdc++ 12, clang 16 can).
set -euo pipefail
with_slurm=0
with_fuzz=0
for a in "$@"; do
  case "$a" in
    --slurm) with_slurm=1 ;;
    --fuzz) with_fuzz=1 ;;
    *) echo "usage: $0 [--slurm] [--fuzz]" >&2; exit 2 ;;
  esac
done
packages=(
  build-essential cmake ninja-build git pkg-config
  libopenmpi-dev openmpi-bin libhdf5-openmpi-dev hdf5-tools
  libgmsh-dev libcgal-dev libmetis-dev libeigen3-dev libvtk9-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libgtest-dev libbenchmark-dev
  python3-h5py python3-h5py-mpi python3-mpi4py python3-meshio python3-numpy python3-matplotlib
  python3-pytest
  libyaml-cpp-dev python3-jsonschema
  pybind11-dev python3-pybind11 python3-dev
  paraview
)
if [ "$with_slurm" = 1 ]; then
  packages+=(slurm-wlm munge)
fi
if [ "$with_fuzz" = 1 ]; then
  packages+=(clang-16 libclang-rt-16-dev llvm)
fi
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -gt 0 ]; then
  echo "pdgrain: installing missing Debian packages: ${missing[*]}"
  if [ -n "$sudo" ] && ! command -v sudo >/dev/null; then
    echo "pdgrain: need root (or sudo) to install: ${missing[*]}" >&2
    exit 1
  fi
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  echo "pdgrain: packages installed"
fi

# ParaView's Python modules (python3-paraview) conflict with python3-vtk9, which libvtk9-dev
# needs: they cannot be installed together on Debian 12. The tests that read our XDMF/PVD with
# ParaView's pvbatch only need the modules on a path, so the package is unpacked (not installed)
# into .deps/ of this checkout, once.
root="$(cd "$(dirname "$0")/.." && pwd)"
pv="$root/.deps/paraview-python"
if [ ! -d "$pv/usr/lib/python3/dist-packages/paraview" ]; then
  tmp="$(mktemp -d)"
  if (cd "$tmp" && apt-get download -qq python3-paraview >/dev/null 2>&1); then
    mkdir -p "$pv"
    dpkg-deb -x "$tmp"/python3-paraview_*.deb "$pv"
    echo "pdgrain: unpacked python3-paraview into .deps/ (for the ParaView reader tests)"
  else
    echo "pdgrain: could not fetch python3-paraview; the ParaView reader tests will skip" >&2
  fi
  rm -rf "$tmp"
fi
