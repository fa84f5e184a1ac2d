"""Convergence of the 1D manufactured solution (docs/reference.md, section 2.1;
options/mms_skb1d.opts).

Runs the scene at several resolutions h = 1/n with the time step tied to h (fixed CFL, from
the scene file), prints a table of the displacement errors with the observed orders between
successive resolutions, writes it to <work>/mms_convergence.csv, and asserts that the
least-squares order of both error norms is at least 1.8 (GIMP with the leapfrog start
measures 2.0, so 1.8 catches a lost order).

Extra options (besides those of gimptest.parse_args):
  --levels 16,32,64,128   cells per unit length of the convergence series
  --study                 also run the measurements documented in docs/validation.md (large
                          amplitude, update schemes, FLIP fraction, time step, long runs) and
                          write them to <work>/mms_study.csv; they are printed, not asserted.
"""
import argparse
import csv
import os
import sys
import time

import gimptest

OPTS = "options/mms_skb1d.opts"
PERIOD = 0.02  # s, c = 100 m/s
MIN_ORDER = 1.8

pre = argparse.ArgumentParser(add_help=False)
pre.add_argument("--levels", default="16,32,64,128")
pre.add_argument("--study", action="store_true")
mine, rest = pre.parse_known_args()
sys.argv = sys.argv[:1] + rest
args = gimptest.parse_args()
levels = [int(s) for s in mine.levels.split(",")]


def run(n, tag, extra=()):
    """Run the scene with h = 1/n (strip one cell high, rollers on y = 0 and y = h); return a
    dict of measurements."""
    h = 1.0 / n
    out = os.path.join(args.work, "%s_n%d" % (tag, n))
    t0 = time.time()
    gimptest.run(args, OPTS, ["-gimp_h", repr(h), "-gimp_body0_box", "0,0,1,%r" % h,
                              "-gimp_bc3_y", repr(h)] + list(extra), outdir=out)
    wall = time.time() - t0
    s = gimptest.summary(out)
    hist = gimptest.history(out)
    t = hist["time"]
    per = []  # max L-inf error within each period
    for k in range(int(round(t[-1] / PERIOD))):
        e = [x for x, tt in zip(hist["mms_linf"], t) if k * PERIOD < tt <= (k + 1) * PERIOD * (1 + 1e-9)]
        per.append(max(e) if e else float("nan"))
    return {
        "n": n, "h": h, "dt": t[1] - t[0], "steps": s["steps"], "t_end": s["time"],
        "status": s["status"], "particles": s["particles"],
        "linf": s["measures"]["mms_linf"], "rms": s["measures"]["mms_rms"],
        "hist_linf": max(hist["mms_linf"]), "hist_rows": len(t),
        "ke_end": s["energy"]["kinetic"], "ke_max": max(hist["kinetic"]),
        "linf_per_period": per, "wall": wall,
    }



def orders(rows, key):
    return gimptest.orders(rows, key, "h")


fmt_order = gimptest.fmt_order


def table(title, rows):
    po_inf, fit_inf = orders(rows, "linf")
    po_rms, fit_rms = orders(rows, "rms")
    print(title)
    print("%9s %11s %6s %9s %12s %12s %6s %6s %7s" %
          ("h", "dt [s]", "steps", "particles", "L-inf [m]", "RMS [m]", "p_inf", "p_rms", "wall[s]"))
    for r, a, b in zip(rows, po_inf, po_rms):
        print("1/%-7d %11.4e %6d %9d %12.4e %12.4e %s %s %7.2f" %
              (r["n"], r["dt"], r["steps"], r["particles"], r["linf"], r["rms"], fmt_order(a),
               fmt_order(b), r["wall"]))
    print("least-squares order: L-inf %.3f, RMS %.3f\n" % (fit_inf, fit_rms))
    return po_inf, po_rms, fit_inf, fit_rms


chk = gimptest.Checks()

# ---- Convergence series: A = 1e-4, MUSL, FLIP 1, dt = 0.1 h / c --------------------------
t0 = time.time()
rows = [run(n, "conv") for n in levels]
po_inf, po_rms, fit_inf, fit_rms = table(
    "1D manufactured solution, A = 1e-4, errors = max over one period (%s)" % OPTS, rows)
path = os.path.join(args.work, "mms_convergence.csv")
with open(path, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["h", "n", "dt", "steps", "particles", "linf", "rms", "order_linf", "order_rms",
                "wall_s"])
    for r, a, b in zip(rows, po_inf, po_rms):
        w.writerow([repr(r["h"]), r["n"], "%.6e" % r["dt"], r["steps"], r["particles"],
                    "%.6e" % r["linf"], "%.6e" % r["rms"], "" if a is None else "%.4f" % a,
                    "" if b is None else "%.4f" % b, "%.2f" % r["wall"]])
print("wrote %s (%.1f s for the series)" % (path, time.time() - t0))

chk.check("runs", all(r["status"] == "completed" and abs(r["t_end"] - PERIOD) < 1e-12 and
                      r["hist_rows"] == r["steps"] + 1 for r in rows),
          "%d runs completed one period with a history row every step" % len(rows))
chk.check("measures", all(abs(r["linf"] - r["hist_linf"]) <= 1e-9 * r["linf"] for r in rows),
          "summary mms_linf equals the max of the history.csv column")
chk.check("decreasing", all(a["linf"] > b["linf"] and a["rms"] > b["rms"]
                            for a, b in zip(rows, rows[1:])),
          "both error norms decrease with h: L-inf %s" %
          ", ".join("%.3e" % r["linf"] for r in rows))
chk.check("order L-inf", fit_inf >= MIN_ORDER,
          "least-squares order %.3f (>= %.1f); finest pair %.3f" % (fit_inf, MIN_ORDER, po_inf[-1]))
chk.check("order RMS", fit_rms >= MIN_ORDER,
          "least-squares order %.3f (>= %.1f); finest pair %.3f" % (fit_rms, MIN_ORDER, po_rms[-1]))

# ---- Study for docs/validation.md (not asserted) -----------------------------------------
if mine.study:
    t0 = time.time()
    study = []  # (study, A, update, flip, cfl, periods, row)

    def add(name, n, A=1e-4, update="musl", flip=1.0, cfl=0.1, periods=1):
        extra = ["-gimp_mms_amplitude", repr(A), "-gimp_update", update, "-gimp_transfer", "flip", "-gimp_flip", repr(flip),
                 "-gimp_cfl", repr(cfl), "-ts_max_time", repr(periods * PERIOD)]
        if periods > 1:
            extra += ["-gimp_history_interval", "4"]
        tag = "%s_A%g_%s_f%g_c%g_p%d" % (name, A, update, flip, cfl, periods)
        r = run(n, tag, extra)
        study.append((name, A, update, flip, cfl, periods, r))
        return r

    # Time step at fixed h: dt error vs space error.
    dts = [add("dt", 128, cfl=c) for c in (0.2, 0.1, 0.05, 0.025)]
    # Series with a 4x smaller CFL (closer to the spatial error alone).
    fine = [add("fine_dt", n, cfl=0.025) for n in levels]
    # FLIP 0.99 at small amplitude: the PIC fraction adds its own error.
    pic = [add("flip099", n, flip=0.99) for n in levels]
    # Large amplitude series for three schemes.
    big = {}
    for upd, fl in (("musl", 1.0), ("musl", 0.99), ("usl", 1.0)):
        big[(upd, fl)] = [add("large_A", n, A=0.05, update=upd, flip=fl) for n in levels]
    # Update scheme and FLIP fraction at h = 1/64, both amplitudes.
    for A in (1e-4, 0.05):
        for upd in ("usf", "usl", "musl"):
            for fl in (1.0, 0.99):
                add("scheme", 64, A=A, update=upd, flip=fl)
    # Five periods at h = 1/64, A = 0.05: does the error grow from period to period?
    for upd, fl in (("musl", 1.0), ("usf", 1.0), ("usl", 1.0), ("musl", 0.99)):
        add("long", 64, A=0.05, update=upd, flip=fl, periods=5)

    print("Time step at h = 1/128, A = 1e-4 (MUSL, FLIP 1)")
    for r in dts:
        print("  dt %.4e  L-inf %.4e  RMS %.4e" % (r["dt"], r["linf"], r["rms"]))
    for a, b in zip(dts, dts[1:]):
        print("  dt %.3e -> %.3e: change of L-inf %.3e" % (a["dt"], b["dt"], a["linf"] - b["linf"]))
    print()
    table("A = 1e-4, dt = 0.025 h / c (MUSL, FLIP 1)", fine)
    table("A = 1e-4, dt = 0.1 h / c, MUSL, FLIP 0.99", pic)
    print("FLIP 0.99 minus FLIP 1, L-inf: " +
          ", ".join("%.2e" % (p["linf"] - r["linf"]) for p, r in zip(pic, rows)) + "\n")
    for (upd, fl), rs in big.items():
        table("A = 0.05, dt = 0.1 h / c, %s, FLIP %g" % (upd.upper(), fl), rs)
    print("Update scheme and FLIP fraction at h = 1/64, dt = 0.1 h / c")
    print("  %-7s %5s %5s %12s %12s %12s" % ("A", "upd", "flip", "L-inf [m]", "RMS [m]", "L-inf/A"))
    for name, A, upd, fl, cfl, per, r in study:
        if name == "scheme":
            print("  %-7g %5s %5g %12.4e %12.4e %12.4e" % (A, upd, fl, r["linf"], r["rms"], r["linf"] / A))
    print("\nFive periods at h = 1/64, A = 0.05: max L-inf error in each period; final KE / max KE")
    for name, A, upd, fl, cfl, per, r in study:
        if name == "long":
            print("  %-5s FLIP %-5g %s   %.2e" % (upd, fl, " ".join("%.2e" % x for x in r["linf_per_period"]),
                                                 r["ke_end"] / r["ke_max"]))
    path = os.path.join(args.work, "mms_study.csv")
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["study", "A", "update", "flip", "cfl", "periods", "h", "n", "dt", "steps",
                    "particles", "linf", "rms", "ke_end_over_max", "linf_per_period", "wall_s"])
        for name, A, upd, fl, cfl, per, r in study:
            w.writerow([name, repr(A), upd, repr(fl), repr(cfl), per, repr(r["h"]), r["n"],
                        "%.6e" % r["dt"], r["steps"], r["particles"], "%.6e" % r["linf"],
                        "%.6e" % r["rms"], "%.4e" % (r["ke_end"] / r["ke_max"]),
                        ";".join("%.4e" % x for x in r["linf_per_period"]), "%.2f" % r["wall"]])
    print("wrote %s (%.1f s for the study)" % (path, time.time() - t0))

chk.done()
