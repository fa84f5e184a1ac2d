#!/usr/bin/env bash
# Install, build and run the default test suite (everything but the 'long' label).
# Extra arguments go to ctest, e.g. tools/test.sh -L long for the long validation runs.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/setup.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$root/build"
if [ $# -eq 0 ]; then set -- -LE long; fi
ctest --output-on-failure "$@"
