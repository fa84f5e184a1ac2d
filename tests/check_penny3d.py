"""A penny-shaped crack of radius a = 10 mm in a 96 mm cube under remote tension sigma = 1 MPa
(options/penny3d.opts: a quarter by symmetry, four levels to 1 mm around the front, a = 10 finest
cells, damped to rest; the front integrals' tube 6 mm). Exact for an infinite body, at every
front point:

    K_I = 2 sigma sqrt(a / pi) = 112.84 kPa m^0.5,   K_II = K_III = 0.

The quarter's front ends on its two symmetry planes x = 0 and y = 0 (rollers), so every front
point's tube takes the particles' mirror images across them (docs/method.md, Symmetry planes;
"images" 2 in summary.json, checked).

Checked at every front point of the quarter (measured in brackets): K_I by the interaction
integral within 5 % of the exact K_I [+1.1 .. +4.3 %] (the target is 3 %: below) and within 1 % of
K from G, sqrt(G E'), E' = E / (1 - nu^2) [-0.7 .. +0.2 %]; K from G within 5 % of the exact
K_I [+1.7 .. +4.1 %] and its mean over the front within 3.5 % [+2.7 %]; |K_II| and |K_III| below
2 % of K_I [1.5e-6]; the measures at the points mirrored about the quarter's diagonal x = y (the
grid, the levels and the polygon are symmetric about it) equal within 1e-5 [5.4e-7; 1.9e-4 when
the domain integral's arc length jumped behind the front's vertices, docs/method.md, G and K
along the front]; the run at
rest (the front's mean K_I changed by less than 0.2 % over its last 400 steps).

K from G is high by the effective front's place among the nodes (most where the front runs along
a node plane, at 0 and 90 degrees: docs/validation.md, 3D cracks) and by the cube's finite size
(about 0.8 %). For a pure mode I field the interaction integral must give K_I = sqrt(G E'), so
K_I inherits that error: the 3 % target holds at 10 of the 16 points, the 6 nearest the
symmetry planes read +3.2 to +4.3 % as K from G does. (Before the interaction integrals took
their curvature terms, K_I read -2.6 .. +0.2 %, below sqrt(G E') by the missing terms, and met 3 % by that
cancellation.)

Then 2 ranks against 1 over the first 200 steps, the ranks' border crossing the front (level 0
split along x at x = 8 mm): every front point's G and K_I to 1e-10 relative.

With --fine (ctest penny3d_fine, label long: about 5 minutes on 2 ranks) the same scene with a
fifth level, 0.5 mm in the box 0..13 x 0..13 x -3..3 mm around the front (a = 20 finest cells,
84,320 particles), the same 6 mm tube, on 2 ranks, checked at the target: K_I within 3 % of the
exact K_I at every front point [+0.93 .. +2.32 %], K from G within 3 % [+1.41 .. +2.56 %] and its
mean within 2.5 % [+1.96 %], K_I within 1 % of K from G, K_II and K_III below 2 %, the mirror
symmetry and the rest as above. The error halves from a = 10 to a = 20 cells (worst K_I 4.3 ->
2.3 %), about 0.8 % of it the cube's finite size. The 2-rank comparison is not repeated."""
import argparse
import math
import sys

import gimptest

pre = argparse.ArgumentParser(add_help=False)
pre.add_argument("--fine", action="store_true")
mine, rest = pre.parse_known_args()
sys.argv = sys.argv[:1] + rest
args = gimptest.parse_args()
E, nu, sigma, a = 2.3e9, 0.3, 1e6, 0.01
Ep = E / (1 - nu * nu)
K0 = 2 * sigma * math.sqrt(a / math.pi)
if mine.fine:
    # The fifth level: 0.5 mm around the front, a = 20 finest cells; the tube stays 6 mm.
    TOL_G, TOL_G_MEAN, TOL_I, TOL_AGREE = 0.03, 0.025, 0.03, 0.01
    out = gimptest.run(args, "options/penny3d.opts",
                       ["-gimp_scene", "penny3d_fine", "-gimp_levels", "5",
                        "-gimp_level4_box", "0,0,-0.003,0.013,0.013,0.003",
                        "-gimp_level4_ratio", "2"], ranks=2, outdir=args.work + "/fine")
else:
    TOL_G, TOL_G_MEAN, TOL_I, TOL_AGREE = 0.05, 0.035, 0.05, 0.01
    out = gimptest.run(args, "options/penny3d.opts")
front = gimptest.summary(out)["cracks"][0]["front"]
c = gimptest.Checks()
rows = []
worstG = worstI = mixed = agree = 0.0
for f in front:
    x = f["x"]
    ang = math.degrees(math.atan2(x[1], x[0]))
    eG = math.sqrt(max(f["G"], 0.0) * Ep) / K0 - 1
    eI = f["KI"] / K0 - 1
    m = max(abs(f["KII"]), abs(f["KIII"])) / K0
    agree = max(agree, abs(f["KI"] / math.sqrt(max(f["G"], 0.0) * Ep) - 1))
    rows.append("  %5.1f deg  K(G) %+6.2f %%  K_I %+6.2f %%  K_II %+.1e  K_III %+.1e" %
                (ang, 100 * eG, 100 * eI, f["KII"] / K0, f["KIII"] / K0))
    worstG, worstI, mixed = max(worstG, abs(eG)), max(worstI, abs(eI)), max(mixed, m)
print("front points (angle from x; errors against 2 sigma sqrt(a / pi)):\n" + "\n".join(rows))
c.check("front points", len(front) >= 8 and all(
    abs(math.hypot(f["x"][0], f["x"][1]) - a) < 0.01 * a and abs(f["x"][2]) < 1e-12
    for f in front), "%d points on the quarter of the front" % len(front))
meanG = sum(math.sqrt(max(f["G"], 0.0) * Ep) / K0 - 1 for f in front) / len(front)
c.check("K from G", worstG <= TOL_G and abs(meanG) <= TOL_G_MEAN,
        "worst %.2f %% (tol %g %%), mean over the front %+.2f %% (tol %g %%)" %
        (100 * worstG, 100 * TOL_G, 100 * meanG, 100 * TOL_G_MEAN))
n = len(front)
sym = max(abs(front[i][q] - front[n - 1 - i][q]) / abs(front[i][q]) for i in range(n)
          for q in ("G", "KI"))
c.check("symmetric about x = y", sym <= 1e-5,
        "largest relative difference of G and K_I between mirrored points %.1e" % sym)
c.check("mirror images", all(f["images"] == 2 for f in front),
        "chain ends on a symmetry plane per point: %s" % sorted({f["images"] for f in front}))
c.check("K_I by the interaction integral", worstI <= TOL_I,
        "worst %.2f %% (tol %g %%)" % (100 * worstI, 100 * TOL_I))
c.check("K_I by the interaction integral = K from G", agree <= TOL_AGREE,
        "largest |K_I / sqrt(G E') - 1| %.2f %% (tol %g %%)" % (100 * agree, 100 * TOL_AGREE))
c.check("K_II and K_III", mixed <= 0.02, "max |K_II|, |K_III| = %.1e K_I (tol 2 %%)" % mixed)
k = gimptest.history(out)["crack0_KI_mean"]
change = abs(k[-1] / k[-3] - 1)
c.check("at rest", change <= 2e-3, "mean K_I changed by %.1e over the last 400 steps" % change)
if mine.fine:
    c.done()
    sys.exit(0)

# 2 ranks against 1, the front across the ranks' border: the domain widened to x = -64 mm and
# level 0 split along x (-da_processors_x 2), which puts the border at x = 8 mm, where the front
# (radius 10 mm) crosses it at y = 6 mm.
short = ["-ts_max_steps", "200", "-ts_max_time", "1",
         "-gimp_domain", "-0.064,-0.016,-0.064,0.064,0.064,0.064"]
split = ["-da_processors_x", "2", "-da_processors_y", "1", "-da_processors_z", "1",
         "-gimp_balance", "false"]  # nodes split evenly: the border at x = 8 mm
one = gimptest.summary(gimptest.run(args, "options/penny3d.opts", short,
                                    outdir=args.work + "/np1"))["cracks"][0]["front"]
two = gimptest.summary(gimptest.run(args, "options/penny3d.opts", short + split, ranks=2,
                                    outdir=args.work + "/np2"))["cracks"][0]["front"]
diff = max(abs(p[q] - r[q]) / abs(p[q]) for p, r in zip(one, two) for q in ("G", "KI"))
c.check("2 ranks = 1 rank", len(one) == len(two) and diff <= 1e-10,
        "%d front points, largest relative difference of G and K_I %.1e" % (len(two), diff))
c.done()
