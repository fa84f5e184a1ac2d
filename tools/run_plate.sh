#!/usr/bin/env bash
# Install, build and run the main job: the plate with a hole (options/plate.opts), 4000 steps.
# Extra arguments go to gimp (e.g. -log_view). Output: build/output/plate/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/setup.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$root/build"
./gimp -ts_max_steps 4000 -options_file plate.opts "$@"
