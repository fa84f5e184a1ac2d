#!/usr/bin/env bash
# Install, build and run the default test suite: the unit tests, the regression tier (every
# scene against its stored answer) and the fast bad-input and fault checks, about 4.5 minutes
# on 2 cores (tests/CMakeLists.txt describes the tiers). Extra arguments go to ctest instead of the
# default selection:
#   tools/test.sh -L verification    the physics verification checks and the slow bad-input
#                                    and fault tables (about 6 minutes)
#   tools/test.sh -L faults          every bad-input and fault check
#   tools/test.sh -L long            the long validation runs
#   tools/test.sh -L regression      the regression tier alone
#   tools/test.sh -R mpi             tests by name
# Tests run two at a time (GIMP_TEST_JOBS=N for another number; a test that runs MPI ranks
# takes as many slots as it has ranks).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/setup.sh"    # configures with -DGIMP_WERROR=ON when CI=true
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$root/build"
if [ $# -eq 0 ]; then set -- -LE 'long|verification'; fi
ctest -j"${GIMP_TEST_JOBS:-2}" --output-on-failure "$@"
