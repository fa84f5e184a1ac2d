"""Velocity transfers (docs/method.md, "Velocity transfers"; docs/validation.md, "Velocity
transfers"). With the default transfer (APIC):
  - the block of options/rest_tension.opts comes to rest (kinetic / strain energy < 1e-10) on
    one level and on three levels, in fewer steps than FLIP, with EVERY particle's displacement
    within 1e-4 of the exact linear field (relative to its largest value, Poisson contraction
    included) and every particle's stress outside the loaded side's cell column within 1e-5 of
    the traction; the loaded column's in-cell stress mode is reported (docs/validation.md);
  - the undamped bar keeps its total energy within 0.1 % over 20 periods (last period's mean
    against the first's);
  - a square spinning free of load keeps its angular momentum (with the affine spin) within
    1e-10, on one and on three levels.
And XPIC(1) gives PIC's particles up to rounding; XPIC(2) and XPIC(4) bring the free edge
closer to its exact place than PIC, in that order.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gimptest  # noqa: E402
import transfers_measure as tm  # noqa: E402

args = gimptest.parse_args()
c = gimptest.Checks()
for levels in (False, True):
    name = "three levels" if levels else "one level"
    d = tm.rest(args, "default_%d" % levels, [], levels)
    f = tm.rest(args, "flip_%d" % levels, ["-gimp_transfer", "flip"], levels)
    c.check("rest, " + name, d["status"] == "at_rest" and d["steps"] < f["steps"],
            "default at rest after %d steps, FLIP %s after %d" % (d["steps"], f["status"], f["steps"]))
    c.check("displacement, " + name, d["du"] < 1e-4,
            "max over %d particles |u - u_exact| / max |u_exact| = %.2e" % (d["n"], d["du"]))
    c.check("stress, " + name, d["ds_in"] < 1e-5,
            "max |sigma - sigma_exact| / t = %.2e (%.2e in the loaded side's cell column)" %
            (d["ds_in"], d["ds"]))
# XPIC(m): m = 1 is PIC to the last bit; each extra projection brings the free edge closer.
pic = tm.rest(args, "pic_0", ["-gimp_transfer", "flip", "-gimp_flip", "0"], False)
xp = {m: tm.rest(args, "xpic%d_0" % m, ["-gimp_transfer", "xpic", "-gimp_xpic_order", str(m)],
                 False) for m in (1, 2, 4)}
a, b = (gimptest.read_csv(os.path.join(args.work, "rest_%s_0.csv" % t)) for t in ("pic", "xpic1"))
# XPIC forms v_p = S ((v - dt a) + dt a) where PIC has S v: equal up to that rounding, 1e-16 of
# v per step, far below the displacement (1e-6 of the block) and the stress scales compared.
du = max(abs(a[k][i] - b[k][i]) for k in ("x", "y") for i in range(len(a["x"]))) / (8 * tm.EXX)
ds = max(abs(a[k][i] - b[k][i]) for k in ("sxx", "syy", "sxy") for i in range(len(a["x"]))) / tm.T
c.check("xpic(1) = pic", du < 1e-9 and ds < 1e-9 and xp[1]["steps"] == pic["steps"],
        "largest difference of positions %.1e of the end displacement, of stresses %.1e of t; "
        "%d and %d steps" % (du, ds, xp[1]["steps"], pic["steps"]))
c.check("xpic(m) edge", pic["du"] > xp[2]["du"] > xp[4]["du"],
        "displacement error PIC %.2e, XPIC(2) %.2e, XPIC(4) %.2e" %
        (pic["du"], xp[2]["du"], xp[4]["du"]))
drift, t_end = tm.bar_energy(args, "default", [])
c.check("bar energy", abs(drift) < 1e-3 and t_end >= 199.9,
        "total energy drift over 20 periods %.2e (to t = %.1f s)" % (drift, t_end))
for levels in (False, True):
    lv = ["-options_file", os.path.join(args.root, tm.LEVELS)] if levels else []
    L = tm.spin(args, "default_%d" % levels, lv)
    worst = max(abs(x / L[0] - 1) for x in L)
    c.check("angular momentum, %s" % ("three levels" if levels else "one level"), worst < 1e-10,
            "max |L / L0 - 1| = %.2e over %d frames of 4000 steps" % (worst, len(L)))
c.done()
