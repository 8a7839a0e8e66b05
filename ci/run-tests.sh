#!/usr/bin/env bash
# The default tier's tests: everything built by one cargo call (so cargo packs the compiles on
# the cores), then every test binary side by side: the integration tests (one binary,
# tests/integration.rs) with 8 test threads per core, the unit tests on one thread. The MPI tests share the machine's cores
# through tests/common::cores (a lock file per core): no more MPI ranks run than there are cores,
# and a binary's last long test no longer leaves a core idle while the next binary waits. Each binary's output is printed whole
# as it ends; the exit status is non-zero if any failed. Extra arguments go to every test binary
# (e.g. a test name filter). Called by ci/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
# "KIND PATH" per test executable: lib/bin (unit tests) or test (integration tests). The default
# targets: the io_fields example too, built with the rest rather than by its test.
built=$(cargo test --release --no-run --message-format=json \
  | python3 -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("profile", {}).get("test") and m.get("executable"):
        print(m["target"]["kind"][0], m["executable"])')
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
start=$SECONDS
declare -A name_of
while read -r kind exe; do
  name=$(basename "$exe" | sed 's/-[0-9a-f]*$//')
  if [ "$kind" = test ]; then
    # Many tests at once: most wait for cores (tests/common::cores) or for Python and mpirun.
    "$exe" --test-threads="$((8 * $(nproc)))" "$@" >"$out/$name.log" 2>&1 &
  else
    # The unit tests (no MPI, no cores held) on one thread, in the gaps the MPI tests leave.
    name="$name ($kind)"
    "$exe" --test-threads=1 "$@" >"$out/$name.log" 2>&1 &
  fi
  name_of[$!]=$name
done <<<"$built"
failed=()
for _ in "${!name_of[@]}"; do
  # The binaries in the order they end (wait -n -p: bash 5.1).
  if wait -n -p done; then rc=0; else rc=$?; fi
  name=${name_of[$done]}
  echo "     Ran $name in $((SECONDS - start)) s (rc $rc)"
  cat "$out/$name.log"
  [ "$rc" = 0 ] || failed+=("$name")
done
echo "tests: ${#name_of[@]} binaries side by side in $((SECONDS - start)) s"
if [ "${#failed[@]}" -gt 0 ]; then
  echo "FAILED: ${failed[*]}" >&2
  exit 1
fi
