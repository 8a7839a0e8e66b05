#!/usr/bin/env bash
# Installs what poroplast needs on a Debian 12 machine: PETSc 3.18, Open MPI, METIS, parallel
# HDF5, gmsh, libclang (bindgen), the Python plotting packages and OpenBLAS (serial; it takes
# over libblas.so.3: a MUMPS factorisation of the default scene's 5k-dof system took 55 ms
# instead of 138 ms with the reference BLAS). Idempotent, and silent when nothing is missing.
# Runs apt-get as root (or through sudo). ParaView, which only the tests use, is ci/setup-paraview.sh's.
set -euo pipefail
# Rust first: nothing else helps without it. The dependencies need 1.85 or newer.
need=1.85
if ! command -v cargo >/dev/null; then
  echo "setup: Rust (cargo) not found. Install Rust $need or newer, e.g. as the user who builds:" >&2
  echo "  curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y && . \"\$HOME/.cargo/env\"" >&2
  exit 1
fi
have=$(cargo --version | awk '{print $2}')
if [ "$(printf '%s\n%s\n' "$need" "$have" | sort -V | head -1)" != "$need" ]; then
  echo "setup: cargo $have is older than the $need this build needs: run \`rustup update stable\`" >&2
  exit 1
fi
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
# The python3 on PATH may not be Debian's (pyenv): give it the packages too.
if ! python3 -c 'import numpy, h5py, matplotlib' 2>/dev/null; then
  echo "setup: installing numpy, h5py, matplotlib for $(command -v python3)"
  python3 -m pip install --quiet --disable-pip-version-check numpy h5py matplotlib
fi

