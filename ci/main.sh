#!/usr/bin/env bash
# README command 1: set up this machine, build, and run the default scene on 2 MPI ranks.
# Ends with the path of the run directory.
set -euo pipefail
cd "$(dirname "$0")/.."
ci/setup.sh
. ci/env.sh
cargo build --release --quiet
# Under the launcher, so that Ctrl-C stops the run cleanly (a checkpoint, exit 75; 76 in the set-up).
target/release/poroplast mpirun -n 2 run "$@"
