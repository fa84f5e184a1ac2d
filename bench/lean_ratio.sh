#!/usr/bin/env bash
# gimp's one-core rate on bench/block.opts as a multiple of the lean reference step's
# (build/bench/lean_step, the same step written plainly for this block alone), measured in
# alternating rounds: the machine's speed moves by up to a factor of two between minutes, and
# the lean step moves with it, so the ratio holds where the rates do not (docs/performance.md,
# *USL and USF with APIC in lanes; the step against the lean reference*).
#
# Usage: bench/lean_ratio.sh [ROUNDS (10)] [STEPS (300)] [-- extra gimp options ...]
#   e.g. bench/lean_ratio.sh 10 300 -- -gimp_update usl
# Environment: GIMP_BUILD_DIR (default <repo>/build), GIMP_BENCH_NOBUILD=1 to skip the build.
# Prints each round's rates (M particle-steps/s: lean over its whole step loop, gimp over the
# stepping stages of -log_view and its Main Stage, where the check after the step ran before it
# moved into the Stress stage) and the median and quartiles of gimp / lean.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${GIMP_BUILD_DIR:-$ROOT/build}"
ROUNDS=10
STEPS=300
if [[ $# -gt 0 && $1 != -- ]]; then ROUNDS=$1; shift; fi
if [[ $# -gt 0 && $1 != -- ]]; then STEPS=$1; shift; fi
if [[ $# -gt 0 && $1 == -- ]]; then shift; fi
[[ $ROUNDS =~ ^[1-9][0-9]*$ ]] || { echo "lean_ratio.sh: ROUNDS $ROUNDS: a positive integer" >&2; exit 2; }
[[ $STEPS =~ ^[1-9][0-9]*$ ]] || { echo "lean_ratio.sh: STEPS $STEPS: a positive integer" >&2; exit 2; }
if [[ "${GIMP_BENCH_NOBUILD:-0}" != 1 ]]; then
  [[ -f "$BUILD/CMakeCache.txt" ]] || cmake -S "$ROOT" -B "$BUILD" >/dev/null
  cmake --build "$BUILD" --target gimp lean_step -j"$(nproc)" >/dev/null
fi
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
bash "$ROOT/bench/machine.sh"
printf '%-6s %10s %10s %8s\n' round lean gimp ratio
for ((i = 1; i <= ROUNDS; ++i)); do
  lean=$("$BUILD/bench/lean_step" -steps "$STEPS" | sed -n 's/.* \([0-9.]*\) M particle-steps\/s.*/\1/p')
  gimp=$("$BUILD/gimp" -options_file "$ROOT/bench/block.opts" -ts_max_steps "$STEPS" \
    -gimp_output_dir "$OUT" -log_view "$@" 2>&1 |
    awk -v n="$STEPS" '/^ *[0-9]+: +(Main Stage|P2G|Forces|Grid update|G2P|Stress):/ { for (f = 2; f <= NF; ++f) if ($f ~ /^[0-9.]+e[-+][0-9]+$/) { s += $f; break } }
      END { if (s > 0) printf "%.2f", 65536 * n / s / 1e6 }')
  [[ -n $lean && -n $gimp ]] || { echo "lean_ratio.sh: a run failed" >&2; exit 1; }
  printf '%-6d %10s %10s %8.3f\n' "$i" "$lean" "$gimp" "$(awk -v a="$gimp" -v b="$lean" 'BEGIN { print a / b }')"
done | tee "$OUT/rounds.txt"
awk '{ print $4 }' "$OUT/rounds.txt" | sort -n | awk '{ r[NR] = $1 }
  END { m = (NR % 2) ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2
        printf "gimp / lean: median %.2f, quartiles %.2f-%.2f over %d rounds\n", m,
          r[int((NR + 3) / 4)], r[int((3 * NR + 3) / 4)], NR }'
