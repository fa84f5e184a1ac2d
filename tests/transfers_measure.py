"""Measures of the velocity transfers shared by tests/check_transfers.py and
runs/study_transfers.py: the block pulled to rest (options/rest_tension.opts), the undamped bar
(options/bar.opts) and the spinning square, each from gimp's own outputs."""
import math
import os

import gimptest

E, NU, T = 100.0, 0.3, 1e-4  # rest_tension.opts
EXX, EYY = T * (1 - NU * NU) / E, -T * NU * (1 + NU) / E
LEVELS = "options/rest_tension_levels.opts"


def rest(args, tag, extra, levels):
    """Run the block to rest; the worst particle errors against the exact linear state."""
    lv = ["-options_file", os.path.join(args.root, LEVELS)] if levels else []
    d0 = os.path.join(args.work, "rest0_%d.csv" % levels)
    if not os.path.exists(d0):
        gimptest.run(args, "options/rest_tension.opts", lv + ["-ts_max_steps", "0",
                     "-gimp_particle_dump", d0], outdir=os.path.join(args.work, "rest0_%d" % levels))
    dump = os.path.join(args.work, "rest_%s.csv" % tag)
    out = gimptest.run(args, "options/rest_tension.opts", lv + list(extra) +
                       ["-gimp_particle_dump", dump], outdir=os.path.join(args.work, "rest_" + tag))
    s = gimptest.summary(out)
    a, b = gimptest.read_csv(d0), gimptest.read_csv(dump)
    assert a["id"] == b["id"]
    X, Y = a["x"], a["y"]
    umax = max(math.hypot(EXX * x, EYY * y) for x, y in zip(X, Y))
    r = {"status": s["status"], "steps": s["steps"], "n": len(X), "du": 0, "ds": 0, "ds_in": 0}
    xedge = max(x + l for x, l in zip(X, a["lx"]))
    for k in range(len(X)):
        du = math.hypot(b["x"][k] - X[k] - EXX * X[k], b["y"][k] - Y[k] - EYY * Y[k]) / umax
        ds = max(abs(b["sxx"][k] - T), abs(b["syy"][k]), abs(b["sxy"][k])) / T
        r["du"] = max(r["du"], du)
        r["ds"] = max(r["ds"], ds)
        if X[k] < xedge - 1.0:  # outside the loaded side's level-0 cell column (h = 1)
            r["ds_in"] = max(r["ds_in"], ds)
    return r


def bar_energy(args, tag, extra, periods=20):
    """Drift of the bar's total energy: its mean over the last period against the first (a
    history row's kinetic energy is that of half-step velocities, so single rows oscillate)."""
    out = gimptest.run(args, "options/bar.opts", list(extra) + ["-ts_max_time", str(10.0 * periods),
                       "-gimp_history_interval", "5"], outdir=os.path.join(args.work, "bar_" + tag))
    h = gimptest.history(out)
    e = [k + s for k, s in zip(h["kinetic"], h["strain"])]
    first = [x for x, t in zip(e, h["time"]) if t <= 10.0]
    last = [x for x, t in zip(e, h["time"]) if t >= 10.0 * (periods - 1)]
    return sum(last) / len(last) / (sum(first) / len(first)) - 1, h["time"][-1]


def spin(args, tag, extra, steps=4000):
    """Total angular momentum with APIC's spin term, sum_p m_p (x_p x v_p + B_yx - B_xy), over
    the particle frames of fields.h5 of the square of options/spin.opts."""
    import h5py
    out = gimptest.run(args, "options/spin.opts", ["-ts_max_steps", str(steps),
                       "-gimp_output_interval", str(steps // 10)] + list(extra),
        outdir=os.path.join(args.work, "spin_" + tag))
    L = []
    with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
        for k in sorted(f["particles"].keys()):
            g = f["particles"][k]
            m, x, v, B = g["m"][:], g["x"][:], g["v"][:], g["B"][:]
            L.append(float(sum(m * (x[:, 0] * v[:, 1] - x[:, 1] * v[:, 0] + B[:, 2] - B[:, 1]))))
    return L
