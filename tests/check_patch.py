"""Patch tests: a free block under constant tractions, damped to rest, is uniformly stressed:
sxx = p within 0.5 % at every particle, syy and sxy below 0.5 % of p, plane strain szz = nu p.
On a uniform grid (options/patch.opts) and on a grid refined twice inside the block
(options/patch3.opts, particles of three sizes)."""
import os
import gimptest

args = gimptest.parse_args()
p, nu, E = 1e4, 0.3, 1e7
c = gimptest.Checks()
for scene in ("patch", "patch3"):
    dump = os.path.join(args.work, scene + "_particles.csv")
    out = gimptest.run(args, "options/%s.opts" % scene, ["-gimp_particle_dump", dump])
    d = gimptest.read_csv(dump)
    n = len(d["sxx"])
    err_xx = max(abs(s / p - 1) for s in d["sxx"])
    err_yy = max(abs(s) / p for s in d["syy"])
    err_xy = max(abs(s) / p for s in d["sxy"])
    err_zz = max(abs(s / (nu * p) - 1) for s in d["szz"])
    c.check(scene + " sxx", err_xx < 0.005, "max |sxx/p - 1| = %.2e over %d particles" % (err_xx, n))
    c.check(scene + " syy", err_yy < 0.005, "max |syy|/p = %.2e" % err_yy)
    c.check(scene + " sxy", err_xy < 0.005, "max |sxy|/p = %.2e" % err_xy)
    c.check(scene + " szz", err_zz < 0.005, "max |szz/(nu p) - 1| = %.2e" % err_zz)
    s = gimptest.summary(out)
    ke, se = s["energy"]["kinetic"], s["energy"]["strain"]
    c.check(scene + " at rest", ke < 1e-5 * se, "kinetic %.3e J vs strain %.3e J" % (ke, se))
    # Elongation: plane strain exx = (1 - nu^2) p / E, from the extreme particle centres
    # (the end particles are level-0 particles of half-size 0.025 m in both scenes).
    exx = (1 - nu ** 2) * p / E
    span0 = 1.0 - 2 * 0.025
    meas = (max(d["x"]) - min(d["x"])) / span0 - 1
    c.check(scene + " strain", abs(meas / exx - 1) < 0.01,
            "exx measured %.6e, exact %.6e" % (meas, exx))
c.done()
