"""The kernels in lanes (-gimp_lanes: 2D four particles at a time, transfer/lane_loops.hpp; 3D a
node's three components at once, transfer/lane_loops3.hpp) against the scalar kernels: every scene
kind must give the same results to round-off (the lane loops fuse products and sums, FMA).

Each case runs twice, with -gimp_lanes true and false, and compares the last frame of
fields.h5 (every particle field, every particle) and every column of history.csv: the largest
difference over a field or column, relative to its largest magnitude in the two runs, must stay
below 1e-10 (history columns of one quantity, momentum_x, _y, _z or a probe's stress
components, share their family's scale; a momentum's scale includes sum m |v|). The cases cover what decides which particles run in lanes and how their sums are
ordered: one level with APIC (every kernel in lanes), USL and USF (APIC's G2P without the
re-projection), three levels (block particles next to
rows at level borders), the plate with a hole (cut particles, tractions, penalty conditions),
a crack (cracked nodes keep rows), FLIP (its transfers in lanes without contraction, the scalar
values bit for bit: tests/test_stencils.cpp, GridStencils.FlipLanesEqualScalarLoops), corner
tracking (stencil centres other than the positions), two ranks, a step per level (each rate
class's stencils), and for the stress update two
materials, a neo-Hookean one (scalar) and plane stress without domain tracking.

When the processor has no AVX2 the lanes do not run and the comparison is trivial; the script
says so (gimp -info reports which kernels ran).
"""
import math
import os
import re
import sys

import h5py
import numpy as np

import gimptest

args = gimptest.parse_args()
checks = gimptest.Checks()

CASES = [
    ("block_apic", "bench/block.opts", ["-gimp_h", "0.03125", "-ts_max_steps", "60"], 1),
    ("block3", "bench/block3.opts", ["-ts_max_steps", "20"], 1),
    ("plate", "options/plate.opts", ["-ts_max_steps", "40"], 1),
    ("dcb", "options/dcb.opts", ["-ts_max_steps", "40"], 1),
    # USL and USF: APIC's G2P without its re-projection
    ("block_usl", "bench/block.opts",
     ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_update", "usl"], 1),
    ("indentation_usf", "options/indentation_a.opts", ["-ts_max_steps", "40", "-gimp_update", "usf"],
     1),
    ("block_flip", "bench/block.opts",
     ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_transfer", "flip"], 1),
    ("patch_corners", "options/patch.opts", ["-ts_max_steps", "60", "-gimp_tracking", "corners"],
     1),
    ("block3_2ranks", "bench/block3.opts", ["-ts_max_steps", "20"], 2),
    # a step per level: each rate class's stencils have lane groups of their own
    ("block3_multirate", "bench/block3_tenth.opts",
     ["-gimp_h", "0.03125", "-gimp_level1_box", "0.375,0.375,0.625,0.625", "-gimp_level2_box",
      "0.4375,0.4375,0.5625,0.5625", "-gimp_multirate", "true", "-ts_max_steps", "32"], 1),
    ("bimaterial", "options/bimaterial.opts", ["-ts_max_steps", "60"], 1),
    ("block_neohookean", "bench/block.opts",
     ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_material", "neohookean"], 1),
    ("block_no_tracking", "bench/block.opts",
     ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_tracking", "none", "-gimp_plane",
      "stress"], 1),
    # 3D: a node's three components in lanes (APIC and FLIP, with the re-projection and without,
    # one level and three, a step per level, two ranks); the stress update in lanes of four
    ("block3d_apic", "bench/block3d.opts", ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30"],
     1),
    ("block3d_flip_usl", "bench/block3d.opts",
     ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30", "-gimp_transfer", "flip",
      "-gimp_update", "usl"], 1),
    ("block3d_levels_flip", "bench/block3d_levels.opts",
     ["-gimp_h", "0.125", "-ts_max_steps", "12", "-gimp_transfer", "flip"], 1),
    ("block3d_levels_usf", "bench/block3d_levels.opts", ["-gimp_h", "0.125", "-ts_max_steps", "12", "-gimp_update", "usf"],
     1),
    ("block3d_multirate", "bench/block3d_levels.opts",
     ["-gimp_h", "0.125", "-ts_max_steps", "12", "-gimp_transfer", "flip", "-gimp_multirate", "true"], 1),
    ("block3d_2ranks", "bench/block3d_levels.opts", ["-gimp_h", "0.125", "-ts_max_steps", "12"], 2),
    # the 3D stress update four particles at a time: linear (stretch, none), neo-Hookean (scalar)
    ("block3d_no_tracking", "bench/block3d.opts",
     ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30", "-gimp_tracking", "none"], 1),
    ("block3d_two_materials", "bench/block3d.opts",
     ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30", "-gimp_bodies", "2", "-gimp_body0_box",
      "0,0,0,0.4583333333333333,1,1", "-gimp_body1_box", "0.4583333333333333,0,0,1,1,1",
      "-gimp_body1_ppc", "8", "-gimp_body1_E", "2e9", "-gimp_body1_velocity", "1,1,1",
      "-gimp_body1_velocity_profile", "sine_x", "-gimp_body1_wavenumber", "6.283185307179586"], 1),
    ("block3d_neohookean", "bench/block3d.opts",
     ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30", "-gimp_material", "neohookean"], 1),
]


def last_frame(outdir):
    with h5py.File(os.path.join(outdir, "fields.h5"), "r") as f:
        steps = sorted(f["particles"].keys())
        g = f["particles"][steps[-1]]
        return steps[-1], {k: g[k][:] for k in g}


# The lane loops fuse products and sums (FMA), the scalar kernels do not: the two runs differ at
# round-off, amplified by the scene's conditioning (a neo-Hookean stress from F near I: 1e-12 after
# 60 steps), as the sums of 2 ranks differ from 1 rank's (tests/check_mpi.py, the same bound). Each
# particle field is measured against its largest magnitude in both runs, each history column
# against its family's (below); a wrong lane gives differences of order 1.
TOL = 1e-10


def field_difference(a, b, scale=None):
    """max |a - b| over scale (default: the largest |a|, |b|), 0 where both are 0; NaN in one
    run only: inf."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if np.any(np.isnan(a) != np.isnan(b)):
        return float("inf")
    ok = ~np.isnan(a)
    if not np.any(ok):
        return 0.0
    s = max(np.max(np.abs(a[ok])), np.max(np.abs(b[ok])), scale or 0.0)
    d = np.max(np.abs(a[ok] - b[ok]))
    return 0.0 if d == 0 else (d / s if s > 0 else float("inf"))


def family(column):
    """History columns that are components of one quantity share a scale: momentum_x, _y, _z ->
    momentum; a probe's far_sxx, far_sxy -> far_ (and its ux, uy); a tip's KI_J, KII_J -> K_J,
    G_vcct, GII_vcct -> G_vcct and opening_n, opening_t -> opening_ (a momentum, a shear stress,
    a mode II or a sliding that is physically zero is round-off of its siblings)."""
    if re.fullmatch(r"momentum_[xyz]", column):
        return "momentum"
    column = re.sub(r"(s[xyz][xyz]|u[xyz]|(?<=opening_)[nt])$", "", column)
    return re.sub(r"(?<=_)([KG])I+(?=_|$)", r"\1", column)


def history_scales(ha, hb, frame):
    """The scale of each history column: the largest magnitude over its family in both runs; a
    momentum's also sum_p m_p |v_p| of the last frame; the separation's (a gap in units of the
    particles' size, from positions) at least 1."""
    scales = {"separation": 1.0}
    for h in (ha, hb):
        for k, col in h.items():
            vals = [abs(float(v)) for v in col if not math.isnan(float(v))]
            f = family(k)
            scales[f] = max(scales.get(f, 0.0), max(vals) if vals else 0.0)
    m, v = frame["m"], frame["v"]
    speed = np.linalg.norm(v.reshape(len(m), -1), axis=1)
    scales["momentum"] = max(scales.get("momentum", 0.0), float(np.sum(m * speed)))
    return scales


def run_case(name, opts, extra, ranks, lanes):
    out = os.path.join(args.work, "%s_%s" % (name, lanes))
    p = gimptest.run(args, opts, extra=extra + ["-gimp_lanes", lanes, "-gimp_history_interval", "5", "-info", ":sys"],
                     ranks=ranks, outdir=out, expect_ok=False)
    if p.returncode != 0:
        sys.stdout.write(p.stdout[-2000:])
        sys.stderr.write(p.stderr[-2000:])
        raise SystemExit("gimp failed on %s (-gimp_lanes %s)" % (name, lanes))
    return out, "in lanes: yes" in p.stdout + p.stderr or \
        "lanes of four particles: yes" in p.stdout + p.stderr


# Every run first, two at a time; then the comparisons in the order of CASES.
done = gimptest.concurrently([
    (lambda case=case, lanes=lanes: run_case(*case, lanes))
    for case in CASES for lanes in ("true", "false")])
used = done[0][1]
for i, (name, opts, extra, ranks) in enumerate(CASES):
    runs = {"true": done[2 * i][0], "false": done[2 * i + 1][0]}
    step_a, a = last_frame(runs["true"])
    step_b, b = last_frame(runs["false"])
    worst, where = 0.0, ""
    missing = [k for k in a if k not in b] + [k for k in b if k not in a]
    for k in a:
        if k not in b or a[k].shape != b[k].shape:
            continue
        d = field_difference(a[k], b[k])
        if d > worst:
            worst, where = d, k
    checks.check("%s: particles" % name,
                 step_a == step_b and not missing and worst <= TOL,
                 "frame %s, %d fields, largest difference %.1e of its field's scale%s (tol %.0e)%s" %
                 (step_a, len(a), worst, " (%s)" % where if where else "", TOL,
                  "; missing: %s" % missing if missing else ""))
    ha, hb = gimptest.history(runs["true"]), gimptest.history(runs["false"])
    hw, hwhere = 0.0, ""
    scales = history_scales(ha, hb, a)
    rows = len(ha["step"]) == len(hb["step"]) and set(ha) == set(hb)
    for k in ha:
        if k in ("wall_seconds", "cpu_seconds") or k not in hb or len(ha[k]) != len(hb[k]):
            continue
        d = field_difference(np.array(ha[k], dtype=float), np.array(hb[k], dtype=float),
                             scales[family(k)])
        if d > hw:
            hw, hwhere = d, k
    checks.check("%s: history" % name, rows and hw <= TOL,
                 "%d rows, largest difference %.1e of its column's scale%s" %
                 (len(ha["step"]), hw, " (%s)" % hwhere if hwhere else ""))
print("lanes ran: %s" % ("yes" if used else "no (no AVX2 here: the comparison is trivial)"))
checks.done()
