#!/usr/bin/env bash
# Runs the scenes of docs/scenes.md (indentation a-d, plate speed vs error, slab speed vs error)
# one process at a time, then writes the tables (Markdown, on stdout and in RUNDIR/tables.md)
# and the figures (docs/img/).
#   runs/scenes_report.sh [RUNDIR]          run everything, then report (about 10 min on 1 core)
#   NORUN=1 runs/scenes_report.sh [RUNDIR]  report only, from the outputs already in RUNDIR
# GIMP=path/to/gimp selects the executable (default build/gimp). RUNDIR defaults to build/scenes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
run="${1:-$root/build/scenes}"
gimp="${GIMP:-$root/build/gimp}"
opts="$root/options"
mkdir -p "$run"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

g() { # name, then gimp arguments
  local name="$1"; shift
  echo "run $name" >&2
  "$gimp" "$@" -gimp_output_dir "$run/$name" > "$run/$name.log" 2>&1
}

if [[ -z "${NORUN:-}" ]]; then
  # Indentation at 20 ns: fields at step 0 and at the final step only.
  g ind_a -options_file "$opts/indentation_a.opts" -ts_max_steps 1000 -gimp_output_interval 0
  g ind_b -options_file "$opts/indentation_b.opts" -ts_max_steps 1000 -gimp_output_interval 0
  g ind_c -options_file "$opts/indentation_c.opts" -ts_max_steps 2000 -gimp_output_interval 0
  # Same, with the refined boxes reaching past the symmetry line x = 0.
  g ind_bx -options_file "$opts/indentation_b.opts" -ts_max_steps 1000 -gimp_output_interval 0 \
    -gimp_level1_box -2e-6,20e-6,20e-6,42e-6
  g ind_cx -options_file "$opts/indentation_c.opts" -ts_max_steps 2000 -gimp_output_interval 0 \
    -gimp_level1_box -4e-6,12e-6,24e-6,40e-6 -gimp_level2_box -2e-6,20e-6,20e-6,40e-6
  # Indentation to 50 ns (the files' own step counts): probe histories; (d) has no tracking.
  g ind_a50 -options_file "$opts/indentation_a.opts"
  g ind_b50 -options_file "$opts/indentation_b.opts"
  g ind_c50 -options_file "$opts/indentation_c.opts"
  g ind_d -options_file "$opts/indentation_d.opts"
  g ind_cx50 -options_file "$opts/indentation_c.opts" \
    -gimp_level1_box -4e-6,12e-6,24e-6,40e-6 -gimp_level2_box -2e-6,20e-6,20e-6,40e-6
  # Plate with a hole, damped to rest (the rest criterion of the static scenes).
  S="-gimp_damping 3e5 -ts_max_steps 60000 -gimp_static_tol 1e-6 -gimp_static_min_time 50e-6
     -gimp_history_interval 100 -gimp_output_interval 0 -gimp_monitor_interval 0"
  g plate_u1 -options_file "$opts/plate_uniform.opts" $S -gimp_h 1e-3
  g plate_u05 -options_file "$opts/plate_uniform.opts" $S -gimp_h 0.5e-3
  g plate_u025 -options_file "$opts/plate_uniform.opts" $S -gimp_h 0.25e-3
  g plate_u0125 -options_file "$opts/plate_uniform.opts" $S -gimp_h 0.125e-3
  g plate_ml -options_file "$opts/plate.opts" $S
  g plate_2l -options_file "$opts/plate_uniform.opts" $S -gimp_h 0.5e-3 -gimp_levels 2 \
    -gimp_level1_box -0.5e-3,-0.5e-3,5e-3,5e-3 -gimp_level1_ratio 2
  g plate_ml0125 -options_file "$opts/plate.opts" $S -gimp_h 0.5e-3
  # Slab, dt proportional to h, same end time 30 us; a fixed grid with room for the stretch.
  D="-gimp_domain -2e-3,-2e-3,12e-3,5e-3"
  g slab_h1 -options_file "$opts/slab.opts" $D -gimp_h 1e-3 -ts_dt 10e-9 -ts_max_steps 3000
  g slab_h05 -options_file "$opts/slab.opts" $D -gimp_h 0.5e-3 -ts_dt 5e-9 -ts_max_steps 6000
  g slab_h025 -options_file "$opts/slab.opts" $D -gimp_h 0.25e-3 -ts_dt 2.5e-9 -ts_max_steps 12000
fi

/usr/bin/python3 "$root/runs/scenes_report.py" "$run" "$root/docs/img" | tee "$run/tables.md"
