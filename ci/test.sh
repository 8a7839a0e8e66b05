#!/usr/bin/env bash
# README command 2: set up this machine and run the whole test suite (2-rank tests included).
set -euo pipefail
cd "$(dirname "$0")/.."
ci/setup.sh
ci/setup-paraview.sh
. ci/env.sh
cargo test --release "$@"
