"""Convergence of the 1D manufactured solution in 3D (options/mms3d.opts): u = A sin(2 pi X)
cos(c pi t) along x in a 1 x h x h bar (neo-Hookean, nu = 0, rollers on the four lateral planes),
over one period, on uniform grids and on two levels (level 1 of ratio 2 over x in [0.25, 0.75],
the bar's whole section), h0 = 1/16, 1/32, 1/64. The errors are the maxima over the period of
the L-inf and volume-weighted RMS norms of the displacement error over every particle
(summary.json measures mms_linf, mms_rms; taken at every history row, here every step).

Checked (measured in brackets): every run completes the period; the particle count (8 per cell;
on two levels 8 per coarse cell and 64 per fine level-0 cell's volume: 36 n); the least-squares
order of both norms >= 1.9 on the uniform grids [2.02, 2.03] and on two levels [2.01, 2.03]
(second order); on two levels the RMS error is no larger than the uniform grid's [0.77
of it]. The lateral displacements are part of the error norm: a 3D kernel that moved particles
across the bar would show."""
import os
import gimptest

args = gimptest.parse_args()
NS = (16, 32, 64)


def run(n, refined):
    h = 1.0 / n
    opts = ["-gimp_h", repr(h), "-gimp_body0_box", "0,0,0,1,%r,%r" % (h, h), "-gimp_bc3_y",
            repr(h), "-gimp_bc5_z", repr(h)]
    if refined:
        opts += ["-gimp_levels", "2", "-gimp_level1_ratio", "2",
                 "-gimp_level1_box", "0.25,0,0,0.75,%r,%r" % (h, h)]
    out = gimptest.run(args, "options/mms3d.opts", opts,
                       outdir=os.path.join(args.work, "mms3d_%s_%d" % ("ref" if refined else "uni", n)))
    s = gimptest.summary(out)
    return {"h": h, "n": n, "status": s["status"], "t": s["time"], "particles": s["particles"],
            "linf": s["measures"]["mms_linf"], "rms": s["measures"]["mms_rms"]}


c = gimptest.Checks()
uniform = []
for refined in (False, True):
    name = "two levels" if refined else "uniform"
    rows = [run(n, refined) for n in NS]
    for r in rows:
        print("%-10s h0 = 1/%-3d particles %6d  L-inf %.4e  RMS %.4e" %
              (name, r["n"], r["particles"], r["linf"], r["rms"]))
    c.check(name + " runs", all(r["status"] == "completed" and abs(r["t"] - 0.02) < 1e-12
                                for r in rows), "every run completed one period")
    want = [(36 if refined else 8) * n for n in NS]
    c.check(name + " particles", [r["particles"] for r in rows] == want,
            "%s (expected %s)" % ([r["particles"] for r in rows], want))
    for key in ("linf", "rms"):
        pair, fit = gimptest.orders(rows, key)
        c.check("%s order %s" % (name, key), fit >= 1.9,
                "least-squares %.3f (pairs %s; tol >= 1.9)" %
                (fit, ", ".join(gimptest.fmt_order(p).strip() for p in pair[1:])))
    if refined:
        ratio = max(r["rms"] / u["rms"] for r, u in zip(rows, uniform))
        c.check("two levels RMS <= uniform", ratio <= 1.0,
                "largest RMS ratio two levels / uniform = %.3f" % ratio)
    else:
        uniform = rows
c.done()
