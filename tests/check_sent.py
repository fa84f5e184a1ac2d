"""Crack-tip measures on a single-edge-notch tension plate (options/sent.opts), every transfer.

The plate (W = 40 mm, 2H = 160 mm, edge crack a = 16 mm, a/W = 0.4, plane strain, sigma = 1 MPa
on its ends) is damped to rest with -gimp_transfer apic (the default), flip with -gimp_flip 1
and 0 (FLIP and PIC) and xpic (XPIC(2)), 1 mm at the tip (a = 16 cells). At rest each run's
K_I by VCCT and by J is held against the handbook formula for a single-edge-cracked strip,
sigma sqrt(pi a) F(a/W), 0.5 % accurate for H/W >= 1.

Measured (docs/validation.md, *Cracks*, single-edge-notch tension), 1 mm / 0.5 mm at the tip:
  VCCT  -2.46 ... -2.58 % / -1.41 ... -1.59 %  (APIC, FLIP, PIC, XPIC(2))
  J     -2.13 % / -0.85 ... -0.86 %
so both converge at first order toward the handbook value (Richardson: VCCT -0.4 %, J +0.4 %),
and the bound below is the 1 mm error with a margin of a sixth: 3 %. The transfers agree within
0.13 % of K_I (bound 0.5 %), VCCT and J within 0.46 % at 1 mm (0.75 % at 0.5 mm; bound 1 %). Before the opening one cell behind the tip was
the recovered nodal displacement of the field that goes with F, VCCT read the particles'
positions (moved, under MUSL, by another velocity field than the one F integrates) projected
with the kernel: at 1 mm -6.17 % (APIC), -7.00 % (FLIP), -1.72 % (PIC), -3.68 % (XPIC(2)) (this
script run on that binary), which fails the transfer agreement, and all but PIC VCCT / J and
the 3 % bound.

FLIP keeps particle velocity modes the grid does not see (kinetic / strain energy near 1e-4
without end), so its run stops at 3 ms; K_I by VCCT is checked to be steady over its last
0.5 ms.
"""
import math
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()

SIGMA, A, W = 1e6, 0.016, 0.04


def handbook(x):
    """F(a/W) of the single-edge-cracked strip in tension (0.5 % for any a/W, H/W >= 1)."""
    b = math.pi * x / 2
    return (math.sqrt(2 / (math.pi * x) * math.tan(b)) *
            (0.752 + 2.02 * x + 0.37 * (1 - math.sin(b)) ** 3) / math.cos(b))


exact = SIGMA * math.sqrt(math.pi * A) * handbook(A / W)
RUNS = {
    "apic": [],
    "flip": ["-gimp_transfer", "flip", "-gimp_flip", "1", "-ts_max_time", "3e-3"],
    "pic": ["-gimp_transfer", "flip", "-gimp_flip", "0"],
    "xpic": ["-gimp_transfer", "xpic", "-gimp_xpic_order", "2"],
}
BOUND, SPREAD, AGREE = 0.03, 0.005, 0.01
tips = {}
for name, extra in RUNS.items():
    out = gimptest.run(args, "options/sent.opts", extra, outdir=os.path.join(args.work, name))
    s = gimptest.summary(out)
    if name == "flip":
        h = gimptest.history(out)
        last = [k for t, k in zip(h["time"], h["crack0_tip1_KI_vcct"]) if t >= h["time"][-1] - 5e-4]
        drift = (max(last) - min(last)) / exact
        c.check("flip: K_I steady over the last 0.5 ms", s["status"] == "completed" and drift < 1e-3,
                "status %s, K_I by VCCT within %.2g of K" % (s["status"], drift))
    else:
        c.check("%s reaches rest" % name, s["status"] == "at_rest", "status %s" % s["status"])
    t = s["cracks"][0]
    tips[name] = t
    ev, ej = t["KI_vcct"] / exact - 1, t["KI_J"] / exact - 1
    c.check("%s: K_I by VCCT and by J within %g %% of the handbook" % (name, 100 * BOUND),
            abs(ev) < BOUND and abs(ej) < BOUND,
            "VCCT %.6g (%+.2f %%), J %.6g (%+.2f %%), handbook %.6g Pa m^0.5" %
            (t["KI_vcct"], 100 * ev, t["KI_J"], 100 * ej, exact))
    c.check("%s: VCCT and J agree within %g %%" % (name, 100 * AGREE),
            abs(t["KI_vcct"] / t["KI_J"] - 1) < AGREE,
            "VCCT / J - 1 = %+.3f %%" % (100 * (t["KI_vcct"] / t["KI_J"] - 1)))
for key in ("KI_vcct", "KI_J"):
    vals = [t[key] for t in tips.values()]
    spread = (max(vals) - min(vals)) / exact
    c.check("%s the same for every transfer within %g %%" % (key, 100 * SPREAD), spread < SPREAD,
            "max - min = %.3f %% of K (%s)" % (100 * spread, ", ".join(
                "%s %+.2f %%" % (n, 100 * (t[key] / exact - 1)) for n, t in tips.items())))
c.done()
