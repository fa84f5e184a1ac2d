#!/usr/bin/env bash
# Whole-process time of two gimp binaries on one scene, alternating (the machine's speed drifts,
# so runs of one binary after the other mislead): the wall time of each process as a user sees
# it (the start of MPI and PETSc, setup, the run and its output), each pair's ratio before /
# after and their median. One process at a time, started without a launcher, as a single-rank
# user runs it.
#
# Usage: bench/whole_process.sh GIMP_BEFORE GIMP_AFTER [pairs (default 5)] [-- gimp options]
#   default options: -options_file bench/block3d.opts -gimp_transfer flip
# Example: bench/whole_process.sh /tmp/before/build/gimp build/gimp 5 -- \
#            -options_file bench/block3d.opts -gimp_transfer apic
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
A=$1 B=$2
shift 2
N=5
if [[ $# -gt 0 && $1 != -- ]]; then
  N=$1
  shift
fi
[[ $# -gt 0 && $1 == -- ]] && shift
OPTS=("$@")
[[ ${#OPTS[@]} -eq 0 ]] && OPTS=(-options_file "$ROOT/bench/block3d.opts" -gimp_transfer flip)
bash "$ROOT/bench/machine.sh"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
wall() { # the wall time of one process, in seconds
  local t0 t1
  t0=$(date +%s.%N)
  "$1" "${OPTS[@]}" -gimp_output_dir "$WORK/out" >"$WORK/log" 2>&1 || {
    cat "$WORK/log"
    echo "gimp failed: $1 ${OPTS[*]}" >&2
    exit 1
  }
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }'
}
printf '%5s %10s %10s %8s\n' pair 'before [s]' 'after [s]' ratio
ratios=()
for r in $(seq "$N"); do
  a=$(wall "$A")
  b=$(wall "$B")
  q=$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", a / b }')
  ratios+=("$q")
  printf '%5d %10s %10s %8s\n' "$r" "$a" "$b" "$q"
done
printf '%s\n' "${ratios[@]}" | sort -g |
  awk '{ v[NR] = $1 } END { m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2;
         printf "ratio before / after: median %.2f, from %.2f to %.2f over %d pairs\n", m, v[1], v[NR], NR }'
