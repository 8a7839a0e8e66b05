#!/usr/bin/env bash
# README command 2: set up this machine and run the test suite, in tiers.
#
#   ci/test.sh          the default tier (ci/run-tests.sh): the unit tests (no MPI), then the
#                       integration test binaries side by side, each running as many tests at a
#                       time as there are cores, every test holding a core per MPI rank it launches
#                       from one pool (tests/common::cores: never more ranks than cores).
#   ci/test.sh --fast   the unit tests and the tree's shape (tests/architecture.rs): seconds
#                       after the build, no mpirun.
#   ci/test.sh --slow   the slow tier: the accuracy benchmarks, the script studies end to end and
#                       the tutorial (tests marked #[ignore], each naming why), one at a time;
#                       only those, so it runs after the default tier. Many minutes (docs/developer.md).
#
# Extra arguments go to every test binary (e.g. a test name filter). CI (.ci/run) runs
# ci/lint.sh (fmt, clippy, rustdoc) first, then the default tier, then the slow tier.
set -euo pipefail
cd "$(dirname "$0")/.."
tier=default
case "${1:-}" in
  --fast) tier=fast; shift ;;
  --slow) tier=slow; shift ;;
esac
ci/setup.sh
[ "$tier" = fast ] || ci/setup-paraview.sh
. ci/env.sh
case "$tier" in
  fast)
    cargo test --release --lib "$@"
    cargo test --release --test architecture "$@"
    ;;
  default)
    ci/run-tests.sh "$@"
    ;;
  slow)
    cargo test --release --test '*' "$@" -- --ignored --test-threads=1
    ;;
esac
