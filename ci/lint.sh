#!/usr/bin/env bash
# The code's own checks, which CI runs before the tests (.ci/run): formatting, clippy with
# warnings as errors, and the API docs with rustdoc warnings as errors (broken links included).
set -euo pipefail
cd "$(dirname "$0")/.."
for tool in rustfmt clippy; do
  if ! cargo "${tool/rustfmt/fmt}" --version >/dev/null 2>&1; then
    echo "lint: cargo ${tool/rustfmt/fmt} not found: installing the rustup component $tool"
    rustup component add "$tool"
  fi
done
cargo fmt --check
cargo clippy --release --all-targets --quiet -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --quiet
echo "lint: ok (fmt, clippy, rustdoc)"
