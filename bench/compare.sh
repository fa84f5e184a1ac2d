#!/usr/bin/env bash
# Before/after comparison of two builds on a machine whose speed drifts: bench/run_bench.sh runs
# of the two builds alternate, N rounds, and each (build, scene, transfer, ranks) keeps its best
# (fastest stepping) run, so both builds meet the same periods of the machine.
#
# Usage: bench/compare.sh BUILD_BEFORE BUILD_AFTER [rounds (default 3)]
#   (directories holding a built gimp; e.g. a worktree of the older commit, built with
#   tools/setup.sh or cmake)
# Environment: GIMP_COMPARE_SCENES (default "block block3"), GIMP_COMPARE_TRANSFERS (default
# "apic flip"), GIMP_BENCH_RANKS (default "1 2"), GIMP_COMPARE_EXTRA (gimp options added to
# every run, e.g. "-ts_max_steps 300" for more, shorter rounds).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
A=$1 B=$2 N=${3:-3}
SCENES=${GIMP_COMPARE_SCENES:-block block3}
TRANSFERS=${GIMP_COMPARE_TRANSFERS:-apic flip}
declare -A BEST MEM
printf '%-8s %-6s %-6s %5s %14s %14s %8s %12s %12s\n' scene transfer build ranks 'best Mps/s' \
  'Mps/s/core' speedup 'B/particle' 'runs Mps/s'
for scene in $SCENES; do
  for transfer in $TRANSFERS; do
    declare -A RUNS=()
    for r in $(seq "$N"); do
      for which in before after; do
        dir=$A
        [[ $which == after ]] && dir=$B
        out=$(GIMP_BUILD_DIR=$dir GIMP_BENCH_NOBUILD=1 GIMP_BENCH_REPEAT=1 \
          GIMP_BENCH_OUT="$dir/bench-compare" GIMP_BENCH_OPTS="$ROOT/bench/$scene.opts" \
          bash "$ROOT/bench/run_bench.sh" -gimp_transfer "$transfer" ${GIMP_COMPARE_EXTRA:-} 2>/dev/null)
        while read -r ranks mps bpp; do
          key="$which $ranks"
          RUNS[$key]="${RUNS[$key]:-} $mps"
          if [[ -z "${BEST[$key]:-}" ]] || awk -v a="$mps" -v b="${BEST[$key]}" 'BEGIN { exit !(a > b) }'; then
            BEST[$key]=$mps MEM[$key]=$bpp
          fi
        done < <(awk '/^[0-9]+ +[0-9]+ +[0-9]+ / { print $1, $6, $10 }' <<<"$out")
      done
    done
    for which in before after; do
      one=""
      for key in "${!BEST[@]}"; do
        [[ $key == "$which 1" ]] && one=${BEST[$key]}
      done
      for ranks in ${GIMP_BENCH_RANKS:-1 2}; do
        key="$which $ranks"
        [[ -n "${BEST[$key]:-}" ]] || continue
        awk -v s="$scene" -v t="$transfer" -v w="$which" -v n="$ranks" -v m="${BEST[$key]}" \
          -v o="$one" -v b="${MEM[$key]}" -v runs="${RUNS[$key]}" 'BEGIN {
          sp = o != "" ? sprintf("%.2f", m / o) : "-"
          printf "%-8s %-6s %-6s %5d %14.2f %14.2f %8s %12s  %s\n", s, t, w, n, m, m / n, sp, b, runs }'
      done
    done
    unset BEST MEM RUNS
    declare -A BEST MEM
  done
done
echo
echo "best Mps/s: million particle-steps per second over the stepping stages (-log_view), best of"
echo "$N alternating runs; speedup: against the same build's one rank; B/particle: peak resident"
echo "memory above a 4-particle run, per particle (of the best run)."
