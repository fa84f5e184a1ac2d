"""Crack-tip measures and energy with explicit cracks.

1. Central crack in a wide plate (options/central_crack.opts, three levels, a = 10 cells of
   1 mm at the tips): at rest, K_I from VCCT and from J within 1.5 % of the closed form
   sigma sqrt(pi a) sqrt(sec(pi a / W)) at both tips (measured: VCCT -0.07 %, J +1.10 %),
   VCCT and J within 2 % of each other (measured 1.16 %), K_II below 1e-3 of K_I (pure mode I),
   the two tips equal to 1e-9 (the scene is symmetric about x = 80 mm).
1b. The same crack turned 30 degrees (options/inclined_crack.opts, mixed mode): K_I and K_II by
   the interaction integral within 2.5 % of K_0 cos^2(30) and K_0 sin(30) cos(30) at both tips
   (measured +1.71 % and +1.15 %); the tips equal (point symmetry). VCCT's values are printed:
   with a tip off the grid's nodes they are low (K_I -9.4 %, K_II -25 %; docs/validation.md).
2. The same plate on 2 ranks (the crack crosses the rank border) gives the 1-rank tip measures
   to 1e-10.
3. Energy: the free bar of options/crack_vibration.opts with an edge crack whose faces close and
   open once a period, undamped, keeps kinetic + strain energy within 1 % over 10 periods
   (measured 0.60 %; the same bar without the crack: 0.55 %), so contact does no work; and the
   faces do close: contact is active at some step.
"""
import csv
import math
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()

# 1. Central crack.
SIGMA, A, W = 1e6, 0.01, 0.16
exact = SIGMA * math.sqrt(math.pi * A) * math.sqrt(1.0 / math.cos(math.pi * A / W))
runs = []
for ranks in (1, 2):
    out = os.path.join(args.work, "central%d" % ranks)
    runs.append(gimptest.summary(gimptest.run(args, "options/central_crack.opts", ranks=ranks,
                                              outdir=out)))
s = runs[0]
tips = s["cracks"]
c.check("central crack reaches rest", s["status"] == "at_rest", "status %s" % s["status"])
for t in tips:
    ev, ej = t["KI_vcct"] / exact - 1, t["KI_J"] / exact - 1
    c.check("central crack tip %d: K_I within 1.5 %%" % t["end"], abs(ev) < 0.015 and abs(ej) < 0.015,
            "K_I VCCT %.6g (%+.2f %%), J %.6g (%+.2f %%), closed form %.6g Pa m^0.5" %
            (t["KI_vcct"], 100 * ev, t["KI_J"], 100 * ej, exact))
    c.check("central crack tip %d: VCCT and J agree within 2 %%" % t["end"],
            abs(t["KI_vcct"] / t["KI_J"] - 1) < 0.02,
            "VCCT / J - 1 = %+.3f %%" % (100 * (t["KI_vcct"] / t["KI_J"] - 1)))
    c.check("central crack tip %d: pure mode I" % t["end"],
            abs(t["KII_vcct"]) < 1e-3 * t["KI_vcct"] and abs(t["KII_J"]) < 1e-3 * t["KI_J"],
            "K_II VCCT %.3g, J %.3g Pa m^0.5" % (t["KII_vcct"], t["KII_J"]))
sym = max(abs(tips[0][k] - tips[1][k]) / abs(tips[0][k]) for k in ("KI_vcct", "KI_J"))
c.check("central crack: both tips equal", len(tips) == 2 and sym < 1e-9,
        "relative difference %.3g" % sym)
keys = ("G_vcct", "G_J", "KI_vcct", "KI_J")
diff = max(abs(runs[0]["cracks"][q][k] - runs[1]["cracks"][q][k]) / abs(runs[0]["cracks"][q][k])
           for q in range(2) for k in keys)
c.check("central crack: 2 ranks equal 1 rank", diff < 1e-10, "worst relative difference %.3g"
        % diff)

# 1b. Inclined crack, mixed mode.
s = gimptest.summary(gimptest.run(args, "options/inclined_crack.opts",
                                  outdir=os.path.join(args.work, "inclined")))
beta = math.radians(30.0)
KI, KII = exact * math.cos(beta) ** 2, exact * math.sin(beta) * math.cos(beta)
c.check("inclined crack reaches rest", s["status"] == "at_rest", "status %s" % s["status"])
for t in s["cracks"]:
    e1, e2 = t["KI_J"] / KI - 1, t["KII_J"] / KII - 1
    c.check("inclined crack tip %d: K_I and K_II within 2.5 %%" % t["end"],
            abs(e1) < 0.025 and abs(e2) < 0.025,
            "K_I %.6g (%+.2f %%), K_II %.6g (%+.2f %%) against %.6g, %.6g Pa m^0.5; VCCT K_I "
            "%+.2f %%, K_II %+.2f %%" % (t["KI_J"], 100 * e1, t["KII_J"], 100 * e2, KI, KII,
                                         100 * (t["KI_vcct"] / KI - 1),
                                         100 * (t["KII_vcct"] / KII - 1)))
ts = s["cracks"]
sym = max(abs(ts[0][k] - ts[1][k]) / abs(ts[0][k]) for k in ("KI_J", "KII_J"))
c.check("inclined crack: both tips equal", len(ts) == 2 and sym < 1e-9,
        "relative difference %.3g" % sym)

# 3. Energy of a vibrating cracked bar.
out = os.path.join(args.work, "vibration")
proc = gimptest.run(args, "options/crack_vibration.opts", ["-info", ":sys"], outdir=out,
                    expect_ok=False)
touching = sum(1 for line in proc.stdout.splitlines()
               if "cracked nodes in contact" in line and ": 0 cracked" not in line)
c.check("the vibrating bar's crack faces close", proc.returncode == 0 and touching > 0,
        "exit %d; contact at %d of the steps' contact passes" % (proc.returncode, touching))
with open(os.path.join(out, "history.csv")) as f:
    rows = list(csv.DictReader(f))
energy = [float(r["kinetic"]) + float(r["strain"]) for r in rows]
drift = max(abs(e / energy[0] - 1) for e in energy)
c.check("undamped cracked bar keeps its energy over 10 periods", drift < 0.01 and
        float(rows[-1]["time"]) >= 1.6e-3 - 1e-12,
        "max |E / E0 - 1| = %.3g over %s s" % (drift, rows[-1]["time"]))
c.done()
