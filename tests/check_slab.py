"""Penalty displacement conditions (Eq. 9) on the displacement-controlled slab (paper section
4.3, options/slab.opts): the damped run converges to u_x = delta x / L at the probe within 0.1 %
(the paper reports 0.46 %), the two ends carry equal and opposite reactions equal to the
stress times the current cross-section, and the pure penalty's constraint violation falls as
1 / alpha. Also: traction forces on a three-level grid sum to the applied force."""
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
E, nu, L, H, delta = 175.8e9, 0.28, 10e-3, 3e-3, 0.5e-3

out = gimptest.run(args, "options/slab.opts")
s = gimptest.summary(out)
pr = s["probes"]["probe"]
exact = delta * pr["x0"][0] / L
err = pr["u"][0] / exact - 1
c.check("probe u_x", abs(err) < 1e-3, "u_x %.6e m, exact %.6e m, error %.4f %%" %
        (pr["u"][0], exact, 100 * err))
r0, r1 = s["reactions"]["dbc0"][0], s["reactions"]["dbc1"][0]
c.check("reactions balance", abs(r0 + r1) < 1e-3 * abs(r1), "left %.6e N, right %.6e N" % (r0, r1))
# Static: reaction = sigma_xx times the current height (plane strain, per unit thickness).
sxx = pr["stress"][0]
eyy = -nu / (1 - nu) * (delta / L)  # small-strain lateral strain, to first order
c.check("reaction = stress x area", abs(r1 / (sxx * H * (1 + eyy)) - 1) < 0.01,
        "right reaction %.6e N, sxx H (1 + eyy) = %.6e N" % (r1, sxx * H * (1 + eyy)))
gap = s["constraint_violation"]["dbc1"]["final"]
c.check("constraint violation", gap < 1e-8, "final |u - u_bar| at the right end %.3e m" % gap)

# Pure penalty: the violation scales as 1 / alpha.
gaps = []
for alpha in (2.7e15, 2.7e16):
    o = gimptest.run(args, "options/slab.opts", ["-gimp_penalty", str(alpha), "-gimp_penalty_traction",
                                             "false", "-ts_max_steps", "4000"],
                     outdir=os.path.join(args.work, "penalty_%g" % alpha))
    gaps.append(gimptest.summary(o)["constraint_violation"]["dbc1"]["final"])
ratio = gaps[0] / gaps[1]
c.check("violation ~ 1/alpha", 7 < ratio < 13, "violation %.3e m at alpha 2.7e15, %.3e m at "
        "2.7e16 Pa/m: ratio %.2f" % (gaps[0], gaps[1], ratio))

# Traction forces on a refined grid: after the first (half) step the total momentum is
# dt/2 times the applied force, whatever levels the loaded edge crosses.
o = gimptest.run(args, "options/patch3.opts", ["-gimp_traction1_value", "0,0", "-ts_max_steps", "1",
                                            "-gimp_history_interval", "1", "-gimp_level1_box",
                                            "0.2,0,1.1,0.4", "-gimp_level2_box", "0.8,0.1,1.0,0.3"],
                 outdir=os.path.join(args.work, "traction_sum"))
h = gimptest.history(o)
dt = gimptest.summary(o)["dt"]
applied = 1e4 * 0.4 * 1.0  # p x height x thickness
got = h["momentum_x"][1] / (0.5 * dt)
c.check("traction sum", abs(got / applied - 1) < 1e-12,
        "total nodal traction force %.15e N, applied %.15e N" % (got, applied))
c.done()
