"""Long validation (ctest label 'long'): the plate with a hole at rest at the finest cell of
0.125 mm, uniform (58,405 particles) against three levels (6,805 particles): the same kt to
0.5 %, within 3 % of Kirsch's solution at the particle's radius times the finite-width factor."""
import math
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
o3 = gimptest.run(args, "options/plate_static.opts", ["-gimp_h", "0.5e-3"],
                  outdir=os.path.join(args.work, "levels3"))
ou = gimptest.run(args, "options/plate_uniform_static.opts", ["-gimp_h", "0.125e-3"],
                  outdir=os.path.join(args.work, "uniform"))
s3, su = gimptest.summary(o3), gimptest.summary(ou)
kt3, ktu = s3["measures"]["kt"], su["measures"]["kt"]
c.check("levels = uniform fine", abs(kt3 / ktu - 1) < 0.005,
        "three levels %.4f in %.1f s, uniform %.4f in %.1f s" %
        (kt3, s3["wall_seconds"], ktu, su["wall_seconds"]))
pr = s3["probes"]["hole_top"]
r = math.hypot(pr["x0"][0] + pr["u"][0], pr["x0"][1] + pr["u"][1])
a2 = (2e-3 / r) ** 2
ref = (0.5 * (1 + a2) + 0.5 * (1 + 3 * a2 * a2)) * 1.0047
c.check("kt against Kirsch", abs(kt3 / ref - 1) < 0.03,
        "kt %.4f at r = %.4f mm, reference %.4f (%.2f %%)" % (kt3, r * 1e3, ref, 100 * (kt3 / ref - 1)))
c.done()
