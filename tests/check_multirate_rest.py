"""Multi-rate steps with the node rule (-gimp_multirate_forces node, with -gimp_update usl;
docs/method.md, "Multi-rate time steps per level", "The node rule"): static answers.

Checks:
  * rest: the block of options/rest_tension.opts on three levels (ratios 2 and 2, R = 4) comes
    to rest under the multi-rate step (kinetic / strain energy below 1e-10, the run's rest
    criterion) with sigma_xx = t and sigma_yy = sigma_xy = 0 at every particle within 1e-4 of t,
    with FLIP, APIC and PIC (measured up to 6.3e-5; the single-rate step 2e-6 to 7e-5). The
    impulse rule does not come to rest on this scene (kinetic / strain energy 3e-4 at the end);
  * the same answer as the single-rate step at rest on a second layout (h0 = 0.25 m, the boxes
    [3, 5] x [1, 3] and [3.5, 4.5] x [1.5, 2.5]; FLIP): every particle's stress within 1e-5 of t
    of the single-rate run's (measured 2e-6);
  * the plate with a hole at rest (options/plate_static.opts, three levels): kt of the hoop
    stress curve and the strain energy equal the single-rate run's within 0.2 % and 1e-3;
  * stability: the three-level block at CFL 0.6 of its finest cell, 4000 fine steps without
    growth: no damping, the energy at the end below the initial and never more than 1 % above it
    (USL itself, single-rate, is stable to between 0.7 and 0.8; the node rule between 0.6 and 0.7);
  * momentum: a block drifting through three levels (options/drift3.opts, R = 6, particles
    change class), pushed for 6 ms and then free, stressed and vibrating, keeps its momentum at
    coarse-step ends from then on to round-off (1e-12) with APIC, FLIP and PIC. (With a fixed rate per level instead of the anchor class, a force
    correction could fall due at a node every particle had left and was lost: up to 1.6e-8.);
  * 2 ranks give the 1-rank answer to round-off (1e-12, each component against the largest value
    of its vector or tensor) on the drift (the body migrates across the ranks) and on the double
    cantilever beam of options/dcb.opts (a crack with contact; 3000 steps);
  * a restart from a checkpoint equals the straight run exactly.
The beam at rest against the single-rate run is the long-label check check_dcb_multirate.py.
"""
import csv
import math
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
NODE = ["-gimp_multirate", "true", "-gimp_multirate_forces", "node", "-gimp_update", "usl"]
LEVELS = ["-options_file", os.path.join(args.root, "options", "rest_tension_levels.opts")]
LAYOUT2 = ["-gimp_h", "0.25", "-gimp_levels", "3", "-gimp_level1_box", "3,1,5,3",
           "-gimp_level1_ratio", "2", "-gimp_level2_box", "3.5,1.5,4.5,2.5",
           "-gimp_level2_ratio", "2", "-ts_max_steps", "100000"]
T = 1e-4
FLIP = ["-gimp_transfer", "flip"]


def dump_run(tag, opts, extra, ranks=1):
    """Run opts with extra, dumping the particles; the summary and the dump ordered by id."""
    dump = os.path.join(W, tag + ".csv")
    out = gimptest.run(args, opts, extra + ["-gimp_particle_dump", dump], ranks=ranks,
                       outdir=os.path.join(W, tag))
    with open(dump) as f:
        rows = sorted(csv.DictReader(f), key=lambda p: int(p["id"]))
    return gimptest.summary(out), rows


def rest_run(tag, extra):
    return dump_run(tag, "options/rest_tension.opts", extra)


def worst(a, b):
    """The largest difference of each quantity relative to the largest value of its family
    (dumps by id): a component's round-off is that of its vector or tensor, so sigma_yy of a
    block pushed along x, a small share of the stress, is measured against the stress."""
    out = float("inf") if [p["id"] for p in a] != [q["id"] for q in b] else 0.0
    for family in (("x", "y"), ("vx", "vy"), ("sxx", "syy", "sxy"), ("V",), ("lx", "ly")):
        scale = max(abs(float(p[k])) for p in a for k in family) or 1.0
        for k in family:
            out = max(out, max(abs(float(p[k]) - float(q[k])) for p, q in zip(a, b)) / scale)
    return out


for name, extra in (("flip", FLIP), ("apic", ["-gimp_transfer", "apic"]),
                    ("pic", FLIP + ["-gimp_flip", "0"])):
    s, rows = rest_run("rest_" + name, LEVELS + NODE + extra)
    sxx = max(abs(float(p["sxx"]) / T - 1) for p in rows)
    other = max(max(abs(float(p[k])) for p in rows) for k in ("syy", "sxy")) / T
    c.check("rest (%s): at rest" % name, s["status"] == "at_rest",
            "status %s after %d fine steps" % (s["status"], s["steps"]))
    c.check("rest (%s): the uniaxial stress at every particle within 1e-4 t" % name,
            sxx < 1e-4 and other < 1e-4,
            "largest |sigma_xx / t - 1| %.2e, |sigma_yy|, |sigma_xy| / t %.2e over %d particles"
            % (sxx, other, len(rows)))

sa, a = rest_run("layout2_single", LAYOUT2 + FLIP + ["-gimp_update", "usl"])
sb, b = rest_run("layout2_node", LAYOUT2 + FLIP + NODE)
diff = max(abs(float(p[k]) - float(q[k])) for p, q in zip(a, b)
           for k in ("sxx", "syy", "sxy")) / T
c.check("second layout: both at rest, the same stresses within 1e-5 t",
        sa["status"] == sb["status"] == "at_rest" and [p["id"] for p in a] ==
        [q["id"] for q in b] and diff < 1e-5,
        "single-rate %s (%d steps), node rule %s (%d steps); largest stress difference %.2e t"
        % (sa["status"], sa["steps"], sb["status"], sb["steps"], diff))

res = {}
for tag, extra in (("single", ["-gimp_update", "usl"]), ("node", NODE)):
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

out = gimptest.run(args, "bench/block3.opts", NODE + FLIP + ["-ts_max_steps", "4000",
                                                             "-gimp_cfl", "0.6",
                                                             "-gimp_history_interval", "100"],
                   outdir=os.path.join(W, "cfl"))
s = gimptest.summary(out)
h = gimptest.history(out)
e = [k + u for k, u in zip(h["kinetic"], h["strain"])]
growth, end = max(e) / e[0] - 1, e[-1] / e[0] - 1
c.check("stable at CFL 0.6", s["status"] == "completed" and s["steps"] == 4000 and
        growth < 0.01 and end < 0, "%s after %d fine steps; energy at most %.2e above the "
        "initial, %.2e at the end" % (s["status"], s["steps"], growth, end))

# The traction pushes the block for 6 ms (step 122) and stops: from then on the block drifts
# stressed and vibrating, so every class's forces are large, and its momentum must stay.
FREE = ["-gimp_traction0_ramp", "0,1,0.006,1,0.0061,0", "-gimp_mass_cutoff", "0",
        "-ts_max_steps", "798", "-gimp_history_interval", "42", "-gimp_output_interval", "0"]
for name, extra in (("apic", ["-gimp_transfer", "apic"]), ("flip", FLIP),
                    ("pic", FLIP + ["-gimp_flip", "0"])):
    out = gimptest.run(args, "options/drift3.opts", FREE + NODE + extra,
                       outdir=os.path.join(W, "drift_" + name))
    h = gimptest.history(out)
    rows = [i for i, st in enumerate(h["step"]) if st >= 126]
    px0, py0 = h["momentum_x"][rows[0]], h["momentum_y"][rows[0]]
    p0 = math.hypot(px0, py0)
    err = max(math.hypot(h["momentum_x"][i] - px0, h["momentum_y"][i] - py0) for i in rows) / p0
    c.check("momentum at coarse ends after the load (%s)" % name, err < 1e-12,
            "largest change of the momentum over %d rows %.1e of it; strain energy %.3g J at "
            "the end" % (len(rows), err, h["strain"][-1]))
DRIFT = NODE + ["-ts_max_steps", "798"]
_, one = dump_run("np1", "options/drift3.opts", DRIFT)
s2, two = dump_run("np2", "options/drift3.opts", DRIFT, ranks=2)
migrated = s2["measures"]["particles_migrated"]
d = worst(one, two)
c.check("np = 2 equals np = 1", d < 1e-12 and migrated > 0,
        "%d particles after 798 steps (%d migrations): largest difference relative to the "
        "largest value of its family %.1e" % (len(one), migrated, d))
# Restart from a checkpoint written at a coarse end (step 792): the node rule keeps nothing from
# one coarse step to the next (every class and every anchor starts at sub-step 0).
_, full = dump_run("ck_full", "options/drift3.opts", DRIFT + ["-gimp_checkpoint_interval", "396"])
ck = os.path.join(W, "ck.h5")
os.replace(os.path.join(W, "ck_full", "checkpoint.h5"), ck)
_, again = dump_run("ck_again", "options/drift3.opts", DRIFT + ["-gimp_restart", ck])
d = worst(full, again)
c.check("restart equals the straight run", d == 0.0, "largest difference %.1e" % d)

BEAM = NODE + ["-gimp_static_tol", "0", "-ts_max_steps", "3000"]
_, one = dump_run("dcb_np1", "options/dcb.opts", BEAM)
_, two = dump_run("dcb_np2", "options/dcb.opts", BEAM, ranks=2)
d = worst(one, two)
c.check("np = 2 equals np = 1 with a crack", d < 1e-12,
        "%d particles after 3000 steps: largest difference relative to the largest value of its "
        "family %.1e" % (len(one), d))
c.done()
