#!/usr/bin/env bash
# ParaView's own readers check the XDMF output in the tests (tests/io_fields.rs). The package is
# large (about 1 GB with its dependencies) and only the tests need it, so ci/test.sh calls this,
# not ci/main.sh. Where the install fails, it is tried once: a marker in the user's cache stops
# later calls from retrying (delete it to try again), and the test warns that it skipped the
# check. With POROPLAST_REQUIRE_PARAVIEW=1 (CI: .ci/run) the install must succeed.
# xvfb comes with it: Debian's ParaView renders through X and crashes (SIGSEGV) without a display,
# so a picture on a server is `xvfb-run -a pvpython scripts/revolve.py ... --png FILE`.
set -euo pipefail
missing=()
command -v pvpython >/dev/null || missing+=(paraview python3-paraview)
command -v xvfb-run >/dev/null || missing+=(xvfb xauth)   # xvfb-run needs xauth, only recommended
[ ${#missing[@]} -eq 0 ] && exit 0
marker="${XDG_CACHE_HOME:-$HOME/.cache}/poroplast/paraview-unavailable"
require="${POROPLAST_REQUIRE_PARAVIEW:-0}"
if [ -e "$marker" ] && [ "$require" != 1 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]} (pvpython for the tests' XDMF reader check; xvfb-run for pictures without a display)"
sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
if $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null; then
  exit 0
fi
if [ "$require" = 1 ]; then
  echo "setup: ${missing[*]} could not be installed, and POROPLAST_REQUIRE_PARAVIEW=1" >&2
  exit 1
fi
mkdir -p "$(dirname "$marker")" && touch "$marker"
echo "setup: WARNING: ${missing[*]} could not be installed; the tests skip the ParaView reader check" \
  "(not retried: delete $marker to try again)" >&2
