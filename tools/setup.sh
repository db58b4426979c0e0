#!/usr/bin/env bash
# Installs everything mfcd needs on Debian 12 / Ubuntu that is not there yet:
# gfortran, CMake, Ninja, HDF5 (Fortran API), LAPACK, Python 3 with venv, and a virtual
# environment .venv with numpy, matplotlib and h5py for post/ and the regression checks.
# Safe to run again: it installs only what is missing.
#   bash tools/setup.sh           what the build, the main job and the tests need
#   bash tools/setup.sh --gmsh    also gmsh (PyPI) in .venv and the X11/OpenGL libraries its
#                                 wheel links against: for meshing .geo bodies (tools/mesh_body.py)
#   bash tools/setup.sh --mpi     also Debian's OpenMPI (libopenmpi-dev, openmpi-bin) and
#                                 HDF5's parallel library (libhdf5-openmpi-dev): for the
#                                 distributed-memory build, -DMFCD_MPI=ON (doc/parallel.md)
set -euo pipefail
cd "$(dirname "$0")/.."
gmsh=0
mpi=0
for arg in "$@"; do
  case "$arg" in
    --gmsh) gmsh=1 ;;
    --mpi) mpi=1 ;;
    *) echo "setup: unknown option '$arg' (use --gmsh, --mpi or nothing)" >&2; exit 2 ;;
  esac
done

pkgs=()
command -v gfortran >/dev/null 2>&1 || pkgs+=(gfortran)
command -v cmake >/dev/null 2>&1 || pkgs+=(cmake)
command -v ninja >/dev/null 2>&1 || pkgs+=(ninja-build)
command -v python3 >/dev/null 2>&1 || pkgs+=(python3)
command -v git >/dev/null 2>&1 || pkgs+=(git)
python3 -c 'import ensurepip, venv' >/dev/null 2>&1 || pkgs+=(python3-venv)
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q 'install ok installed'; }
have_pkg libhdf5-dev || pkgs+=(libhdf5-dev)
have_pkg liblapack-dev || pkgs+=(liblapack-dev)
have_pkg make || pkgs+=(make)
if [ "$gmsh" = 1 ]; then
  # the libraries libgmsh.so of the PyPI wheel needs on a headless Debian 12
  for p in libglu1-mesa libgl1 libopengl0 libxrender1 libxcursor1 libxfixes3 libxext6 \
           libxft2 libfontconfig1 libxinerama1 libx11-6; do
    have_pkg "$p" || pkgs+=("$p")
  done
fi

if [ "$mpi" = 1 ]; then
  have_pkg libopenmpi-dev || pkgs+=(libopenmpi-dev)
  have_pkg openmpi-bin || pkgs+=(openmpi-bin)
  # HDF5's parallel library for the MPI build's collective snapshots (beside the serial one)
  have_pkg libhdf5-openmpi-dev || pkgs+=(libhdf5-openmpi-dev)
fi

if [ ${#pkgs[@]} -gt 0 ]; then
  echo "setup: installing ${pkgs[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${pkgs[@]}"
fi

if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv"
  python3 -m venv .venv
fi
if ! .venv/bin/python -c 'import numpy, matplotlib, h5py, vtk' >/dev/null 2>&1; then
  echo "setup: installing post/requirements.txt into .venv"
  .venv/bin/python -m pip install -q --upgrade pip
  .venv/bin/python -m pip install -q -r post/requirements.txt
fi
if [ "$gmsh" = 1 ] && ! .venv/bin/python -c 'import gmsh' >/dev/null 2>&1; then
  echo "setup: installing gmsh into .venv"
  .venv/bin/python -m pip install -q gmsh
fi
echo "setup: ok ($(gfortran --version | head -n 1); cmake $(cmake --version | head -n 1 | awk '{print $3}'))"
