#!/usr/bin/env bash
# The benchmark table of docs/performance.md: bench/run_bench.sh on the one-level block
# (bench/block.opts, 65,536 particles) and the three-level block (bench/block3.opts, 40,960
# particles), each with the default step (MUSL, APIC), with FLIP and with USL and APIC, at 1 and
# 2 ranks.
#
# Usage: bench/run_all.sh [extra gimp options]
# Environment: as bench/run_bench.sh (GIMP_BUILD_DIR, GIMP_BENCH_REPEAT (default here: 3),
# GIMP_BENCH_RANKS, GIMP_BENCH_NOBUILD, GIMP_BENCH_MPIEXEC_ARGS).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export GIMP_BENCH_REPEAT="${GIMP_BENCH_REPEAT:-3}"
bash "$ROOT/bench/machine.sh"
printf '%-12s %-9s %6s %10s %12s %12s %11s\n' scene step ranks particles 'Mps/s' 'Mps/s/core' 'B/particle'
for scene in block block3; do
  for step in musl/apic musl/flip usl/apic; do
    out=$(GIMP_BENCH_OPTS="$ROOT/bench/$scene.opts" bash "$ROOT/bench/run_bench.sh" \
      -gimp_update "${step%/*}" -gimp_transfer "${step#*/}" "$@" 2>/dev/null)
    # The rank rows of run_bench.sh: ranks particles steps step_s wall_s Mps/s Mps/s/core ...
    awk -v s="$scene" -v t="$step" '/^[0-9]+ +[0-9]+ +[0-9]+ / {
      printf "%-12s %-9s %6d %10d %12.2f %12.2f %11s\n", s, t, $1, $2, $6, $7, $10 }' <<<"$out"
    export GIMP_BENCH_NOBUILD=1 # built once
  done
done
echo
echo "Mps/s: million particle-steps per second over the stepping stages of -log_view (best of"
echo "$GIMP_BENCH_REPEAT runs); B/particle: peak resident memory above a 4-particle run, per particle."
