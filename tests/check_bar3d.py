"""3D fixed-free bar, axial mode 1 (options/bar3d.opts): a 25 x 1 x 1 m square bar with nu = 0,
so the 1D solution is exact in 3D (no lateral coupling). Exact period T = 4 L / sqrt(E / rho) =
10 s, tip amplitude v0 / omega, energy rho v0^2 A L / 4.

Three runs: the default (APIC, MUSL, linear Jaumann material, stretch tracking), FLIP with USL
and the neo-Hookean material, and the default without domain tracking. (USL without tracking
loses 22 % of the energy here, in 2D as in 3D alike: a property of the scheme, not checked.) Each
must give:
- the period within 0.5 % of T, measured between the first and last upward
  zero crossings of the tip displacement over 5 periods [0.03 %, 0.06 %];
- the amplitude within 2 % and the total energy within 1 % of the exact one over the run;
- no motion across the bar: |u_y|, |u_z| at the tip below 1e-12 m (the scene is symmetric and nu
  = 0: a lateral displacement would be a bug of the 3D kernels)."""
import math
import gimptest

args = gimptest.parse_args()
E, L, rho, v0 = 100.0, 25.0, 1.0, 0.1
omega = math.pi / (2 * L) * math.sqrt(E / rho)
T = 2 * math.pi / omega
c = gimptest.Checks()
RUNS = (("apic", []),
        ("flip neohookean usl", ["-gimp_transfer", "flip", "-gimp_material", "neohookean",
                                 "-gimp_update", "usl"]),
        ("tracking none", ["-gimp_tracking", "none"]))
for name, extra in RUNS:
    out = gimptest.run(args, "options/bar3d.opts", extra + ["-gimp_history_interval", "2"],
                       outdir="%s/bar3d_%s" % (args.work, name.replace(" ", "_")))
    h = gimptest.history(out)
    t, u = h["time"], h["tip_ux"]
    ups = [t[k - 1] + (t[k] - t[k - 1]) * (-u[k - 1]) / (u[k] - u[k - 1])
           for k in range(1, len(t)) if u[k - 1] < 0 <= u[k]]
    c.check(name + " crossings", len(ups) >= 4, "%d upward zero crossings" % len(ups))
    if len(ups) >= 2:
        period = (ups[-1] - ups[0]) / (len(ups) - 1)
        c.check(name + " period", abs(period / T - 1) < 0.005,
                "measured %.5f s, exact %.5f s, error %.3f %% (tol 0.5 %%)" %
                (period, T, 100 * (period / T - 1)))
    amp = max(abs(x) for x in u)
    c.check(name + " amplitude", abs(amp * omega / v0 - 1) < 0.02,
            "tip amplitude %.5f m, exact %.5f m" % (amp, v0 / omega))
    e = [k + s for k, s in zip(h["kinetic"], h["strain"])]
    exact = rho * v0 ** 2 * L / 4
    drift = max(abs(x / exact - 1) for x in e)
    c.check(name + " energy", drift < 0.01 and t[-1] >= 5 * T * 0.999,
            "max |E / E_exact - 1| = %.2e over %.1f periods" % (drift, t[-1] / T))
    lateral = max(max(abs(x) for x in h["tip_uy"]), max(abs(x) for x in h["tip_uz"]))
    c.check(name + " no lateral motion", lateral < 1e-12, "max |u_y|, |u_z| = %.1e m" % lateral)
c.done()
