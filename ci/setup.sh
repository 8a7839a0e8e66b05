#!/usr/bin/env bash
# Installs what poroplast needs on a Debian 12 machine: PETSc 3.18, Open MPI, METIS, parallel
# HDF5, gmsh, libclang (bindgen), the Python plotting packages and OpenBLAS (serial; it takes
# over libblas.so.3: a MUMPS factorisation of the default scene's 5k-dof system took 55 ms
# instead of 138 ms with the reference BLAS). Idempotent, and silent when nothing is missing.
# Runs apt-get as root (or through sudo).
set -euo pipefail
pkgs=(petsc-dev openmpi-bin libopenmpi-dev libmetis-dev libhdf5-openmpi-dev gmsh libclang-dev clang
      pkg-config python3 python3-numpy python3-h5py python3-matplotlib
      libopenblas0-serial)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
# ParaView's own readers check the XDMF output in the tests (tests/io_fields.rs): best effort,
# as the package is large (about 1 GB with its dependencies); the test says loudly when it is
# missing.
if ! command -v pvpython >/dev/null; then
  echo "setup: installing paraview (pvpython, for the XDMF reader check)"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends paraview python3-paraview >/dev/null \
    || echo "setup: WARNING: paraview could not be installed; the ParaView reader check will be skipped" >&2
fi
# The python3 on PATH may not be Debian's (pyenv): give it the packages too.
if ! python3 -c 'import numpy, h5py, matplotlib' 2>/dev/null; then
  echo "setup: installing numpy, h5py, matplotlib for $(command -v python3)"
  python3 -m pip install --quiet --disable-pip-version-check numpy h5py matplotlib
fi
command -v cargo >/dev/null || { echo "setup: cargo not found: install Rust first (https://rustup.rs)" >&2; exit 1; }
