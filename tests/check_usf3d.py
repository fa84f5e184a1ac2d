"""USF in 3D (-gimp_update usf, -gimp_dim 3): the stress updated from the grid velocity before the
grid update (docs/method.md, update schemes), on the 3D fixed-free bar of options/bar3d.opts
(25 x 1 x 1 m, nu = 0, axial mode 1: exact period T = 4 L / sqrt(E / rho) = 10 s, tip amplitude
v0 / omega sin(pi x_tip / 2L), energy rho v0^2 A L / 4; see tests/check_bar3d.py).

Runs over 5 periods: USF with the default transfer (APIC) and with FLIP, USL and MUSL (APIC).
Checked (measured on the 2-core machine in brackets):
- USF runs the 5 periods stably and gives the bar's physics: the period within 0.1 % of the
  exact one [APIC 0.022 %, FLIP 0.061 %; the leading dispersion error of the 25-cell quarter
  wave is (k h)^2 / 24 = 0.016 %], the tip amplitude within 1 % [0.39 %, 0.46 %], the energy
  within 1 % of the exact one all along [0.57 %, 0.46 %], no motion across the bar
  (|u_y|, |u_z| < 1e-12 m; the scene is symmetric and nu = 0);
- USF agrees with USL and MUSL within the discretisation error: the tip displacement histories
  differ by less than 3 % of the amplitude [1.3 %, 1.3 %], the size of each scheme's own
  error against the exact tip displacement [USF 0.63 %, USL 1.4 %, MUSL 1.5 %], which is checked
  below 3 % for USF;
- the option acts: USF's tip history differs from USL's and from MUSL's by more than 1e-3 of
  the amplitude [1.3e-2 both] (USF aliased to either scheme would fail);
- USF's stability: with FLIP, USF's critical step is MUSL's (sqrt(3) h / c on this bar,
  docs/validation.md), USL's h / (c sqrt(1.75)): at -ts_dt 0.09 s = 0.9 h / c USF runs 1000
  steps (10 periods) to the end, USL stops as unstable (exit 3) [USL: at step 10].
"""
import math
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
E, L, rho, v0 = 100.0, 25.0, 1.0, 0.1
X_TIP = 24.75  # the probe's particle
omega = math.pi / (2 * L) * math.sqrt(E / rho)
T = 2 * math.pi / omega
AMP = v0 / omega * math.sin(math.pi * X_TIP / (2 * L))
OPTS = "options/bar3d.opts"


def bar(tag, extra):
    out = gimptest.run(args, OPTS, list(extra) + ["-gimp_history_interval", "2"],
                       outdir=os.path.join(args.work, "bar3d_" + tag))
    return gimptest.summary(out), gimptest.history(out)


runs = {"usf": bar("usf", ["-gimp_update", "usf"]),
        "usf flip": bar("usf_flip", ["-gimp_update", "usf", "-gimp_transfer", "flip"]),
        "usl": bar("usl", ["-gimp_update", "usl"]),
        "musl": bar("musl", ["-gimp_update", "musl"])}


def exact_error(h):
    return max(abs(u - AMP * math.sin(omega * t)) for u, t in zip(h["tip_ux"], h["time"])) / AMP


for name in ("usf", "usf flip"):
    s, h = runs[name]
    t, u = h["time"], h["tip_ux"]
    c.check(name + ": completed", s["status"] == "completed" and t[-1] >= 5 * T * 0.999,
            "status %s after %d steps, t = %.2f s (5 periods: %.1f s)" %
            (s["status"], s["steps"], t[-1], 5 * T))
    ups = [t[k - 1] + (t[k] - t[k - 1]) * (-u[k - 1]) / (u[k] - u[k - 1])
           for k in range(1, len(t)) if u[k - 1] < 0 <= u[k]]
    period = (ups[-1] - ups[0]) / (len(ups) - 1) if len(ups) >= 2 else float("nan")
    c.check(name + ": period", len(ups) >= 4 and abs(period / T - 1) < 1e-3,
            "%.5f s from %d upward zero crossings, exact %.5f s, error %.3f %% (tol 0.1 %%)" %
            (period, len(ups), T, 100 * (period / T - 1)))
    amp = max(abs(x) for x in u)
    c.check(name + ": amplitude", abs(amp / AMP - 1) < 0.01,
            "tip amplitude %.5f m, exact %.5f m, error %.2f %% (tol 1 %%)" %
            (amp, AMP, 100 * (amp / AMP - 1)))
    exact = rho * v0 ** 2 * L / 4
    drift = max(abs(k + e - exact) / exact for k, e in zip(h["kinetic"], h["strain"]))
    c.check(name + ": energy", drift < 0.01,
            "max |E / E_exact - 1| = %.2e over the run (tol 1e-2)" % drift)
    lateral = max(abs(x) for x in h["tip_uy"] + h["tip_uz"])
    c.check(name + ": no lateral motion", lateral < 1e-12, "max |u_y|, |u_z| = %.1e m" % lateral)

errors = {n: exact_error(runs[n][1]) for n in ("usf", "usl", "musl")}
c.check("usf: tip displacement against the exact one", errors["usf"] < 0.03,
        "max |u - u_exact| / amplitude: USF %.2e (tol 3e-2); USL %.2e, MUSL %.2e" %
        (errors["usf"], errors["usl"], errors["musl"]))
for other in ("usl", "musl"):
    a, b = runs["usf"][1], runs[other][1]
    same_rows = a["step"] == b["step"]
    d = max(abs(x - y) for x, y in zip(a["tip_ux"], b["tip_ux"])) / AMP if same_rows else 1e9
    c.check("usf agrees with %s" % other, d < 0.03,
            "max tip displacement difference %.2e of the amplitude (tol 3e-2)" % d)
    c.check("usf differs from %s" % other, d > 1e-3,
            "max tip displacement difference %.2e of the amplitude (> 1e-3: the option acts)" % d)

# FLIP at 0.9 h / c: inside USF's (and MUSL's) stable range, outside USL's.
stab = {}
for update in ("usf", "usl"):
    out = os.path.join(args.work, "dt09_" + update)
    p = gimptest.run(args, OPTS, ["-gimp_transfer", "flip", "-gimp_update", update, "-ts_dt",
                                  "0.09", "-ts_max_steps", "1000", "-ts_max_time", "1e9",
                                  "-gimp_history_interval", "10"], outdir=out, expect_ok=False)
    stab[update] = (p.returncode, gimptest.summary(out))
rc, s = stab["usf"]
c.check("usf flip stable at 0.9 h / c", rc == 0 and s["status"] == "completed" and
        s["steps"] == 1000, "exit %d, status %s after %d steps" % (rc, s["status"], s["steps"]))
rc, s = stab["usl"]
c.check("usl flip unstable at 0.9 h / c", rc == 3 and s["status"] == "unstable",
        "exit %d, status %s at step %d" % (rc, s["status"], s["steps"]))
c.done()
