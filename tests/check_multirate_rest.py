"""Multi-rate steps with the node rule (-gimp_multirate_forces node; docs/method.md, "Multi-rate
time steps per level", "The node rule"): static answers.

Checks:
  * rest: the block of options/rest_tension.opts on three levels (ratios 2 and 2, R = 4) comes
    to rest under the multi-rate step (kinetic / strain energy below 1e-10, the run's rest
    criterion) and sigma_xx equals the traction t at every particle within 1e-4 of t with FLIP
    and MUSL, APIC and USL, PIC and USL (the single-rate step: 2e-6 to 7e-5), and within 1e-3
    with APIC and MUSL (measured 8.5e-4); sigma_yy and sigma_xy within the same bounds of t.
    The impulse rule does not come to rest on this scene (kinetic / strain energy 3e-4 at the
    end, sigma_xx off by up to 66 % with APIC and MUSL);
  * the plate with a hole at rest (options/plate_static.opts, three levels, FLIP/PIC blend,
    MUSL): the stress concentration kt of the hoop stress curve and the strain energy equal the
    single-rate run's within 0.2 % and 1e-3;
  * stability: the three-level block at the CFL limit of its finest cell (-gimp_cfl 1) runs 2000
    fine steps without growth: no damping, the energy at the end below the initial and never
    more than 2 % above it (measured 0.8 %; the impulse rule 1.1 %, single-rate 0.1 %);
  * momentum: a free block drifting through three levels (options/drift3.opts, R = 6, particles
    change class) keeps its momentum at coarse-step ends to 1e-12 with MUSL (with USL the
    corrections of a node that every particle left inside its step are lost: about 1e-9).
"""
import csv
import json
import math
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
NODE = ["-gimp_multirate", "true", "-gimp_multirate_forces", "node"]
LEVELS = ["-options_file", os.path.join(args.root, "options", "rest_tension_levels.opts")]
T = 1e-4

for name, extra, tol in (("flip, musl", ["-gimp_transfer", "flip"], 1e-4),
                         ("apic, usl", ["-gimp_transfer", "apic", "-gimp_update", "usl"], 1e-4),
                         ("pic, usl", ["-gimp_transfer", "flip", "-gimp_flip", "0",
                                       "-gimp_update", "usl"], 1e-4),
                         ("apic, musl", ["-gimp_transfer", "apic"], 1e-3)):
    tag = name.replace(", ", "_")
    dump = os.path.join(W, "rest_" + tag + ".csv")
    out = gimptest.run(args, "options/rest_tension.opts",
                       LEVELS + NODE + extra + ["-gimp_particle_dump", dump],
                       outdir=os.path.join(W, "rest_" + tag))
    s = gimptest.summary(out)
    with open(dump) as f:
        rows = list(csv.DictReader(f))
    sxx = max(abs(float(p["sxx"]) / T - 1) for p in rows)
    rest = max(max(abs(float(p[k])) for p in rows) for k in ("syy", "sxy")) / T
    c.check("rest (%s): at rest" % name, s["status"] == "at_rest",
            "status %s after %d fine steps" % (s["status"], s["steps"]))
    c.check("rest (%s): sigma_xx = t at every particle within %g" % (name, tol), sxx < tol,
            "largest |sigma_xx / t - 1| %.2e over %d particles" % (sxx, len(rows)))
    c.check("rest (%s): sigma_yy, sigma_xy = 0 within %g t" % (name, tol), rest < tol,
            "largest |sigma_yy|, |sigma_xy| / t %.2e" % rest)

res = {}
for tag, extra in (("single", []), ("node", NODE)):
    out = gimptest.run(args, "options/plate_static.opts", extra,
                       outdir=os.path.join(W, "plate_" + tag))
    res[tag] = gimptest.summary(out)
a, b = res["single"], res["node"]
dk = b["measures"]["kt"] / a["measures"]["kt"] - 1
de = b["energy"]["strain"] / a["energy"]["strain"] - 1
c.check("plate at rest: both runs at rest", a["status"] == b["status"] == "at_rest",
        "single-rate %s (%d steps, %.2f s), node rule %s (%d steps, %.2f s)" %
        (a["status"], a["steps"], a["wall_seconds"], b["status"], b["steps"], b["wall_seconds"]))
c.check("plate at rest: kt within 0.2 % of the single-rate run", abs(dk) < 2e-3,
        "kt %.5f against %.5f (%+.3f %%)" % (b["measures"]["kt"], a["measures"]["kt"], 100 * dk))
c.check("plate at rest: strain energy within 1e-3", abs(de) < 1e-3, "difference %+.2e" % de)

out = gimptest.run(args, "bench/block3.opts", NODE + ["-ts_max_steps", "2000", "-gimp_cfl", "1",
                                                      "-gimp_history_interval", "100"],
                   outdir=os.path.join(W, "cfl1"))
s = gimptest.summary(out)
h = gimptest.history(out)
e = [k + u for k, u in zip(h["kinetic"], h["strain"])]
growth, end = max(e) / e[0] - 1, e[-1] / e[0] - 1
c.check("stable at the finest cell's CFL limit", s["status"] == "completed" and s["steps"] == 2000
        and growth < 0.02 and end < 0, "%s after %d fine steps; energy at most %.2e above the "
        "initial, %.2e at the end" % (s["status"], s["steps"], growth, end))

FREE = ["-gimp_traction0_value", "0,0", "-gimp_mass_cutoff", "0", "-ts_max_steps", "798",
        "-gimp_history_interval", "42", "-gimp_output_interval", "0"]
for name, extra in (("apic", ["-gimp_transfer", "apic"]), ("flip", ["-gimp_transfer", "flip"]),
                    ("pic", ["-gimp_transfer", "flip", "-gimp_flip", "0"])):
    out = gimptest.run(args, "options/drift3.opts", FREE + NODE + extra,
                       outdir=os.path.join(W, "drift_" + name))
    h = gimptest.history(out)
    p0 = math.hypot(h["momentum_x"][0], h["momentum_y"][0])
    err = max(math.hypot(px - h["momentum_x"][0], py - h["momentum_y"][0])
              for px, py in zip(h["momentum_x"], h["momentum_y"])) / p0
    c.check("momentum at coarse ends (musl, %s)" % name, err < 1e-12,
            "largest change of the momentum over %d rows %.1e of it" % (len(h["step"]), err))
c.done()
