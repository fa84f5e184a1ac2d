"""Plate with a hole (paper section 4.4) run to rest on the paper's three levels
(options/plate_static.opts) and on the uniform grid of the finest cell, 0.25 mm
(options/plate_uniform_static.opts).

Three levels against uniform. Within 5 mm of the hole centre (level 2's box) the two runs have
the same 0.25 mm cells and the same particles; they differ only in the far field, where the
three-level grid has 0.5 and 1 mm cells. The hole sees that difference only through the smooth
far field, so the two must agree far more closely than either agrees with the reference:
- kt (the edge hoop stress / p at 90 degrees fitted from the particles next to the hole,
  docs/method.md "The hole measure"): within 0.2 % [measured 0.022 %: 2.9407 against 2.9413
  with cut cells];
- the fitted edge hoop stress at 0, 15, ..., 75 degrees (summary.json hoop_0 ... hoop_75):
  within 1e-3 p [measured at most 7.1e-4 p]; hoop_90 (kt) within 0.2 % as kt;
- every particle of the first layer around the hole (hoop.csv): the same particles (angle and
  radius), hoop stress within 1e-3 p below 80 degrees [3.3e-4 p] and within 0.2 % of kt p
  from 80 to 90 degrees [1.7e-3 p at 89.3 degrees: near the top of the hole the hoop stress
  and its radial gradient are largest, and so is the difference].
A wrong transition between levels (zones, hanging nodes, level-1/2 boundaries at 5 and 10 mm)
or a far field solved wrongly on the coarse levels shows up here at every angle.

Against the reference. The finite-width gross-section value of a strip with d/W = 1/15 is
(2 + (1 - d/W)^3) / (1 - d/W) = 3.014 at the edge (docs/validation.md). At 0.25 mm kt is not
converged (docs/validation.md "Hole edge convergence": 2.94 here, 2.4 % below 3.014; it was
3.075 when kt was the first particle's stress at r = 2.025 mm). A band of 3 % around 3.014
(2.924 .. 3.104) holds both, and catches an error of the load or of the stress recovery at the
level of the discretisation error itself (the old band, 2.9 .. 3.2, was 10 % wide).
The hoop stress also goes from about -p at the load axis to its maximum near 90 degrees, as
Kirsch's solution does."""
import csv
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
out3 = gimptest.run(args, "options/plate_static.opts", outdir=os.path.join(args.work, "levels3"))
outu = gimptest.run(args, "options/plate_uniform_static.opts",
                    outdir=os.path.join(args.work, "uniform"))
s3, su = gimptest.summary(out3), gimptest.summary(outu)
m3, mu = s3["measures"], su["measures"]
kt3, ktu = m3["kt"], mu["kt"]
c.check("at rest", s3["status"] == "at_rest" and su["status"] == "at_rest",
        "three levels %s after %d steps, uniform %s after %d steps" %
        (s3["status"], s3["steps"], su["status"], su["steps"]))

# Against the reference: the finite-width edge value 3.014, within 3 %.
KT_REF = (2 + (1 - 1 / 15) ** 3) / (1 - 1 / 15)
for name, kt in (("three levels", kt3), ("uniform", ktu)):
    c.check("kt reference, " + name, abs(kt / KT_REF - 1) <= 0.03,
            "kt = %.4f, %+.2f %% from the finite-width value %.4f (tol 3 %%)" %
            (kt, 100 * (kt / KT_REF - 1), KT_REF))

# Three levels against uniform: kt within 0.2 %, the hoop stress at every angle.
KT_TOL = 0.002
c.check("kt levels = uniform", abs(kt3 / ktu - 1) <= KT_TOL,
        "three levels %.4f (%d particles), uniform 0.25 mm %.4f (%d particles): %+.3f %% "
        "(tol 0.2 %%)" % (kt3, s3["particles"], ktu, su["particles"], 100 * (kt3 / ktu - 1)))
HOOP_TOL = 1e-3  # [p], away from the top of the hole
for a in range(0, 90, 15):
    h3, hu = m3["hoop_%d" % a], mu["hoop_%d" % a]
    c.check("hoop_%d levels = uniform" % a, abs(h3 - hu) <= HOOP_TOL,
            "%.5f against %.5f: |diff| = %.1e p (tol %.0e p)" % (h3, hu, abs(h3 - hu), HOOP_TOL))
h3, hu = m3["hoop_90"], mu["hoop_90"]
c.check("hoop_90 levels = uniform", abs(h3 / hu - 1) <= KT_TOL,
        "%.5f against %.5f: %+.3f %% (tol 0.2 %%, as kt)" % (h3, hu, 100 * (h3 / hu - 1)))


def hoop_rows(out):
    with open(os.path.join(out, "hoop.csv")) as f:
        return [(float(r["angle_deg"]), float(r["r"]), float(r["hoop_over_p"]))
                for r in csv.DictReader(f)]


rows3, rowsu = hoop_rows(out3), hoop_rows(outu)
same = len(rows3) == len(rowsu) and all(
    abs(a[0] - b[0]) < 1e-3 and abs(a[1] - b[1]) < 1e-7 for a, b in zip(rows3, rowsu))
c.check("first layer: same particles", same and len(rows3) > 40,
        "%d and %d particles, angles within 1e-3 deg, radii within 1e-7 m" %
        (len(rows3), len(rowsu)))
if same:
    worst_lo = max((abs(a[2] - b[2]), a[0]) for a, b in zip(rows3, rowsu) if a[0] < 80)
    worst_hi = max((abs(a[2] - b[2]), a[0]) for a, b in zip(rows3, rowsu) if a[0] >= 80)
    c.check("first layer below 80 deg", worst_lo[0] <= HOOP_TOL,
            "max |diff| = %.1e p at %.1f deg (tol %.0e p)" % (worst_lo + (HOOP_TOL,)))
    c.check("first layer 80 .. 90 deg", worst_hi[0] <= KT_TOL * ktu,
            "max |diff| = %.1e p at %.1f deg (tol 0.2 %% of kt = %.1e p)" %
            (worst_hi + (KT_TOL * ktu,)))

near0 = min(rows3, key=lambda r: r[0])
top = max(rows3, key=lambda r: r[2])
c.check("hoop shape", -1.3 < near0[2] < -0.7 and top[0] > 75,
        "hoop/p %.3f at %.1f deg; maximum %.3f at %.1f deg (Kirsch: -1 at 0, 3 at 90)" %
        (near0[2], near0[0], top[2], top[0]))
c.done()
