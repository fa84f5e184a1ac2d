#!/usr/bin/env bash
# Regenerate every figure and table of docs/validation.md.
#
#   runs/make_docs.sh [WORK]        (default WORK: /tmp/gimp-docs)
#
# Builds gimp (cmake, into build/), copies the binary to WORK/gimp (so that a rebuild of build/
# during the run does not change it), then runs, one after the other, the verification scripts
# with their study options and the study scripts, each into WORK/<name>/, and the plot scripts,
# which write docs/img/*.png. The tables are printed by the scripts: each step's output is kept
# in WORK/logs/<name>.log (the step names are the docs/validation.md sections). Set GIMP=path
# to use an existing binary instead of building. Plots need Debian's /usr/bin/python3 with
# matplotlib and numpy.
#
# Took 543 s (9 minutes) on the two-core development machine with other work running before the
# crack steps; the DCB study adds about 30 minutes and the large-load DCB about 7.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${1:-/tmp/gimp-docs}"
py=/usr/bin/python3
mkdir -p "$work/logs"
work="$(cd "$work" && pwd)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

if [ -z "${GIMP:-}" ]; then
  cmake -S "$root" -B "$root/build" > "$work/logs/build.log"
  cmake --build "$root/build" -j2 >> "$work/logs/build.log"
  GIMP="$root/build/gimp"
fi
cp "$GIMP" "$work/gimp"
gimp="$work/gimp"
mpiexec="$(command -v mpiexec || command -v mpirun || echo mpiexec)"

start_all=$SECONDS
step() { # step NAME COMMAND...: run, log, report the time
  local name=$1
  shift
  local t0=$SECONDS
  if ! "$@" > "$work/logs/$name.log" 2>&1; then
    echo "make_docs: step $name failed; see $work/logs/$name.log" >&2
    tail -20 "$work/logs/$name.log" >&2
    exit 1
  fi
  printf '%-22s %5d s   %s\n' "$name" $((SECONDS - t0)) "$work/logs/$name.log"
}

# Convergence: 1D manufactured solution (tables and docs/img/mms_convergence.png).
step mms "$py" "$root/tests/check_mms.py" --gimp "$gimp" --root "$root" --work "$work/mms" \
  --mpiexec "$mpiexec" --levels 16,32,64,128,256 --study
step plot_mms "$py" "$root/tools/plot_mms.py" "$work/mms/mms_convergence.csv" \
  "$work/mms/mms_study.csv"

# Wave reflection at level interfaces (table, docs/img/reflection.png, ratio table).
step reflection "$py" "$root/tests/check_reflection.py" --gimp "$gimp" --root "$root" \
  --work "$work/reflection" --mpiexec "$mpiexec" --levels 8,16,32,64,128
step plot_reflection "$py" "$root/tools/plot_reflection.py" "$work/reflection/reflection.csv"
for r in 3 4; do
  step "reflection_ratio$r" "$py" "$root/tests/check_reflection.py" --gimp "$gimp" \
    --root "$root" --work "$work/reflection_ratio$r" --mpiexec "$mpiexec" --levels 16,32,64 \
    --ratio "$r"
done

# Convergence on a refined grid (tables).
step mms_refined "$py" "$root/tests/check_mms_refined.py" --gimp "$gimp" --root "$root" \
  --work "$work/mms_refined" --mpiexec "$mpiexec" --study

# Fixed-free bar (numbers and docs/img/bar.png).
step bar "$py" "$root/tests/check_bar.py" --gimp "$gimp" --root "$root" --work "$work/bar" \
  --mpiexec "$mpiexec"
step plot_bar "$py" "$root/tools/plot_bar.py" "$work/bar/bar"

# Patch tests (table).
step patch "$py" "$root/runs/study_patch.py" --gimp "$gimp" --root "$root" --work "$work/patch"

# Slab: penalty displacement conditions (tables and docs/img/slab.png).
step slab "$py" "$root/runs/study_slab.py" --gimp "$gimp" --root "$root" --work "$work/slab"
step plot_slab "$py" "$root/tools/plot_slab.py" "$work/slab"

# Critical time step: predicted against bisected (table; needs gimp built with SLEPc).
step stability "$py" "$root/runs/study_stability.py" --gimp "$gimp" --root "$root" \
  --work "$work/stability"

# Velocity transfers: FLIP, PIC, APIC, XPIC(2) on the block to rest, the bar, the spin
step transfers "$py" "$root/runs/study_transfers.py" --gimp "$gimp" --root "$root" \
  --work "$work/transfers"

# Plate with a hole (table and docs/img/plate.png).
step plate "$py" "$root/runs/study_plate.py" --gimp "$gimp" --root "$root" --work "$work/plate"
step plot_plate "$py" "$root/tools/plot_plate.py" "$work/plate"
# Dispersion on one level: APIC and FLIP against the lumped-mass chain (docs/img/dispersion.png).
step dispersion_apic "$py" "$root/runs/study_dispersion.py" --gimp "$gimp" --root "$root" \
  --work "$work/dispersion" --tag apic
step dispersion_flip "$py" "$root/runs/study_dispersion.py" --gimp "$gimp" --root "$root" \
  --work "$work/dispersion" --tag flip --extra "-gimp_transfer flip"
step plot_dispersion "$py" "$root/runs/study_dispersion.py" --root "$root" \
  --work "$work/dispersion" \
  --plot "$work/dispersion/dispersion_apic.csv,$work/dispersion/dispersion_flip.csv"

# Hole edge convergence: the wide plate at a/4, a/8, a/16 and the paper's plate with finer levels
# (table and docs/img/hole_edge.png; about 10 minutes).
step hole "$py" "$root/runs/study_hole.py" --gimp "$gimp" --root "$root" --work "$work/hole"

# Colliding disks: energies and rebound (table and docs/img/disks_energy.png; a few seconds).
step disks "$py" "$root/runs/study_disks.py" --gimp "$gimp" --work "$work/disks"

# Particle domain tracking: tension scene, its two figures, and the MMS with tracking modes.
step tension "$py" "$root/tests/check_tension.py" --gimp "$gimp" --root "$root" \
  --work "$work/tension" --mpiexec "$mpiexec"
step plot_tension "$py" "$root/tools/plot_tension.py" --gimp "$gimp" --work "$work/tension_plot"
step mms_tracking "$py" "$root/runs/study_mms_tracking.py" --gimp "$gimp" \
  --work "$work/mms_tracking"
# Large-deflection cantilever against the elastica: tracking modes and two grids (table and
# docs/img/cantilever.png; about 35 minutes on one core, most of it the two runs at H / h = 8).
step cantilever "$py" "$root/runs/study_cantilever.py" --gimp "$gimp" --root "$root" \
  --work "$work/cantilever" --write-docs

# Cracks: the DCB grid study at rest (table, docs/img/dcb_speed_error.png; about 30 minutes of
# CPU, most of it the uniform 0.5 mm reference) and the large-load DCB (docs/img/dcb_large.png).
step dcb_study "$py" "$root/runs/study_dcb.py" --gimp "$gimp" --work "$work/dcb_study"
# A growing crack that curves toward a hole at two grid sizes (docs/img/crack_hole_path.png,
# about 2 minutes).
step crack_path "$py" "$root/tests/check_crack_path.py" --gimp "$gimp" --root "$root" \
  --work "$work/crack_path" --mpiexec "$mpiexec"
step plot_crack_path "$py" "$root/runs/crack_path.py" "$work/crack_path"
step dcb_large sh -c "cd '$root/options' && '$gimp' -options_file dcb_large.opts \
  -gimp_output_dir '$work/dcb_large' >/dev/null && '$py' '$root/tools/plot_dcb_large.py' '$work/dcb_large'"
# Stable growth in the DCB under a prescribed opening (table, docs/img/dcb_growth.png; about 4
# minutes).
step dcb_growth "$py" "$root/runs/dcb_growth.py" --gimp "$gimp" --work "$work/dcb_growth"

# 3D scenes (docs/validation.md, *3D scenes*; docs/img/halfspace3d.png).
for t in bar3d patch3d penalty3d mms3d thin_plate3d mpi3d shapes3d; do
  step "$t" "$py" "$root/tests/check_$t.py" --gimp "$gimp" --root "$root" --work "$work/$t" \
    --mpiexec "$mpiexec"
done
step halfspace3d "$py" "$root/tests/check_halfspace3d.py" --gimp "$gimp" --root "$root" \
  --work "$work/halfspace3d" --mpiexec "$mpiexec"
step plot_halfspace3d "$py" "$root/tools/plot_halfspace3d.py" "$work/halfspace3d"
# 3D cracks (docs/validation.md, *3D cracks*, *Inclined penny crack (3D)*; docs/performance.md,
# *Penny crack: speed against error*, docs/img/speed_error_penny3d.png, about 17 minutes).
for t in through_crack3d penny3d penny_inclined3d; do
  step "$t" "$py" "$root/tests/check_$t.py" --gimp "$gimp" --root "$root" --work "$work/$t" \
    --mpiexec "$mpiexec"
done
step speed_error_penny3d "$py" "$root/runs/speed_error_penny3d.py" --gimp "$gimp" \
  --work "$work/speed_error_penny3d"
step speed_error3d "$py" "$root/runs/speed_error3d.py" --gimp "$gimp" --work "$work/speed_error3d"

# Scenes report (docs/scenes.md: indentation, plate and slab studies), the plate maps, the
# speed-against-error figure and table (docs/performance.md) and the throughput benchmark.
step scenes "$root/runs/scenes_report.sh" "$work/scenes"
step plate_maps sh -c "cd '$root/options' && '$gimp' -options_file plate_static.opts \
  -gimp_output_dir '$work/plate_static' >/dev/null && '$py' '$root/tools/plot_plate_maps.py' '$work/plate_static'"
step speed_error "$py" "$root/runs/speed_error.py" --gimp "$gimp" --work "$work/speed_error"
step speed_error_multirate "$py" "$root/runs/speed_error_multirate.py" --gimp "$gimp" \
  --work "$work/speed_error_multirate"
step bench_multirate env GIMP_BUILD_DIR="$(dirname "$gimp")" GIMP_BENCH_NOBUILD=1 \
  "$root/bench/multirate.sh"
step bench env GIMP_BUILD_DIR="$(dirname "$gimp")" GIMP_BENCH_NOBUILD=1 "$root/bench/run_bench.sh"
for o in block3d block3d_levels; do
  for t in flip apic; do
    step "bench_${o}_$t" env GIMP_BUILD_DIR="$(dirname "$gimp")" GIMP_BENCH_NOBUILD=1 \
      GIMP_BENCH_OPTS="$root/bench/$o.opts" "$root/bench/run_bench.sh" -gimp_transfer "$t"
  done
done
# Setup time and memory against the particle count in 3D (docs/performance.md, *Large runs*; about
# 4 minutes, 4.7 GB at its largest run).
step setup_scaling "$py" "$root/bench/setup_scaling.py" --gimp "$gimp" --work "$work/setup_scaling"
step dcb_follow "$py" "$root/bench/dcb_follow.py" --gimp "$gimp" --work "$work/dcb_follow"

echo "make_docs: all steps done in $((SECONDS - start_all)) s; tables in $work/logs/, figures in $root/docs/img/"
