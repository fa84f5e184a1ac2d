#!/usr/bin/env bash
# Multi-rate steps against the single-rate step (docs/performance.md, "Multi-rate steps"): the
# same scene with -gimp_multirate false and true, runs alternating (this machine's speed drifts),
# N rounds, best of each. Prints per scene and transfer: the particles per rate class, the
# stepping time (the -log_view stages P2G, Forces, Grid update, G2P, Stress) and the wall time
# (summary.json wall_seconds) of both, and their ratios; and the median over the rounds of each
# round's stepping ratio (a single run and the per-level run right after it: this machine's
# speed drifts by 10 % and more between runs, and a pair of neighbours shares its period, where
# the best of each mode may come from different ones).
#
# Usage: bench/multirate.sh [rounds (default 3)] [extra gimp options]
# Environment: GIMP_BUILD_DIR (default <repo>/build, built first unless GIMP_BENCH_NOBUILD=1),
#   GIMP_MULTIRATE_SCENES (default "block3_tenth block3"; a scene is bench/NAME.opts, else
#   options/NAME.opts, e.g. block3d_multirate), GIMP_MULTIRATE_TRANSFERS ("apic flip").
set -euo pipefail
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${GIMP_BUILD_DIR:-$ROOT/build}"
N=${1:-3}
shift || true
SCENES=${GIMP_MULTIRATE_SCENES:-block3_tenth block3}
TRANSFERS=${GIMP_MULTIRATE_TRANSFERS:-apic flip}
if [[ "${GIMP_BENCH_NOBUILD:-0}" != 1 ]]; then
  [[ -f "$BUILD/CMakeCache.txt" ]] || cmake -S "$ROOT" -B "$BUILD" >/dev/null
  cmake --build "$BUILD" --target gimp -j"$(nproc)" >/dev/null
fi
OUT="$BUILD/bench-multirate"
mkdir -p "$OUT"
stepping() { # the stepping stages of a -log_view file and its Main Stage (the check after each
  # step runs there for the per-level step, in the Stress stage for the single step), in seconds
  awk '/^ *[0-9]+: +(Main Stage|P2G|Forces|Grid update|G2P|Stress):/ {
         for (i = 1; i <= NF; ++i) if ($i ~ /^[0-9.]+e[+-][0-9]+$/) { s += $i; break } }
       END { printf "%.3f", s }' "$1"
}
printf '%-13s %-5s %-26s %9s %9s %8s %9s %9s %8s %6s %8s %7s %8s\n' scene transfer \
  'classes (every 4, 2, 1)' 'step 1' 'step mr' ratio 'wall 1' 'wall mr' ratio work 'of work' \
  pairs 'of work'
for scene in $SCENES; do
  for transfer in $TRANSFERS; do
    best_s=(1e9 1e9) best_w=(1e9 1e9)
    pairs=()
    classes=""
    for r in $(seq "$N"); do
      for i in 0 1; do
        mr=$([[ $i == 1 ]] && echo true || echo false)
        dir="$OUT/${scene}_${transfer}_$mr"
        opts="$ROOT/bench/$scene.opts"
        [[ -f "$opts" ]] || opts="$ROOT/options/$scene.opts"
        "$BUILD/gimp" -options_file "$opts" -gimp_transfer "$transfer" \
          -gimp_multirate "$mr" -gimp_output_dir "$dir" -log_view ":$dir.log" -info \
          "$@" >"$dir.out" 2>&1
        s=$(stepping "$dir.log")
        w=$(sed -n 's/.*"wall_seconds": *\([0-9.eE+-]*\).*/\1/p' "$dir/summary.json")
        best_s[i]=$(awk -v a="${best_s[i]}" -v b="$s" 'BEGIN { print (b < a ? b : a) }')
        best_w[i]=$(awk -v a="${best_w[i]}" -v b="$w" 'BEGIN { print (b < a ? b : a) }')
        [[ $i == 1 ]] && raw=$(grep -m1 'particles per rate class' "$dir.out" |
          sed 's/.*rate class: *//') && classes=$(sed 's/ (every [0-9]*)//g' <<<"$raw")
        [[ $i == 0 ]] && s_single=$s
        [[ $i == 1 ]] && pairs+=("$(awk -v a="$s_single" -v b="$s" 'BEGIN { print a / b }')")
      done
    done
    printf '%s\n' "${pairs[@]}" >"$OUT/${scene}_${transfer}_pairs.txt" # (each round's, in order)
    pair=$(printf '%s\n' "${pairs[@]}" | sort -g |
      awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }')
    # The particle-work ratio: R N particle-steps per coarse step single-rate against
    # sum_c (R / m_c) N_c per-level; the stepping ratio as a share of it.
    work=$(awk '{ R = 0; for (i = 2; i <= NF; i += 3) { e = $(i + 1) + 0; if (e > R) R = e }
                  n = 0; w = 0; for (i = 1; i <= NF; i += 3) { e = $(i + 2) + 0; n += $i; w += R / e * $i }
                  printf "%.2f", R * n / w }' <<<"$(sed 's/[()]//g' <<<"$raw")")
    awk -v sc="$scene" -v tr="$transfer" -v cl="$classes" -v s0="${best_s[0]}" \
      -v s1="${best_s[1]}" -v w0="${best_w[0]}" -v w1="${best_w[1]}" -v wk="$work" \
      -v pr="$pair" 'BEGIN {
      printf "%-13s %-5s %-26s %9.2f %9.2f %8.2f %9.2f %9.2f %8.2f %6.2f %7.0f%% %7.2f %7.0f%%\n",
        sc, tr, cl, s0, s1, s0 / s1, w0, w1, w0 / w1, wk, 100 * (s0 / s1) / wk, pr, 100 * pr / wk }'
  done
done
echo
echo "step: stepping stages of -log_view [s]; wall: summary.json wall_seconds [s]; best of $N"
echo "alternating runs each; 1: -gimp_multirate false, mr: true; ratio: single / multi-rate;"
echo "work: the particle-work ratio (R N over sum_c (R / m_c) N_c); of work: the stepping ratio"
echo "as a share of it (80 % asked); pairs: the median over the rounds of a round's stepping"
echo "ratio (its single run against the per-level run right after it), and its share of work;"
echo "each round's in $OUT/SCENE_TRANSFER_pairs.txt."
