"""Multi-rate time steps per level (-gimp_multirate; docs/method.md, "Multi-rate time steps per
level"; docs/validation.md, "Multi-rate steps").

Checks:
  * one level (R = 1): the multi-rate step is the single-rate step, to round-off, for USL and
    MUSL with APIC, FLIP, PIC and a FLIP/PIC blend, and with a crack (the double cantilever beam
    on one level, PIC, MUSL and USL, opening and pushed shut so that contact acts at every step);
  * momentum: a free elastic block drifting through three levels (options/drift3.opts, ratios 2
    and 3: R = 6, its particles change class on the way) keeps its momentum to round-off with
    every transfer and update scheme (mass cutoff 0: the cutoff drops the momentum of nodes
    lighter than 1e-14 of a particle, with either step);
  * the same answer as the single-rate step on the three-level block of
    bench/block3_tenth.opts (a tenth of the particles in the finest box): strain energy at every
    history row within 1e-4 of the energy, particle velocities and stresses after 200 fine steps
    within 2 % and 0.5 % (L2 over the particles; measured 0.5 % and 0.1 %: level 0 steps with 4
    dt); and under a traction (drift3) the energy balance within 0.1 % of the work;
  * 2 ranks give the 1-rank answer to round-off (the body migrates across the ranks);
  * a restart from a checkpoint equals the straight run exactly;
  * history rows and frames come at coarse-step ends, once each;
  * stability: the three-level block at the CFL limit of its finest cell (-gimp_cfl 1) runs 2000
    fine steps;
  * a finer box sharing an edge with its parent runs (its edge nodes reach the grandparent's
    cells);
  * bad input: the limits of the coarse step and the combinations it is not built for (cracks
    with FLIP, corner and CPDI tracking, XPIC, USF, a run to rest with the impulse rule) are refused in one
    line, as are -gimp_multirate_forces without the option, with MUSL and a bad value of it. The node rule
    is checked by check_multirate_rest.py;
  * a class that comes onto a finer level's nodes within a coarse step (a body near the wave
    speed, ratios 4) stops the run in one line and keeps its summary, in 2D and in 3D.
"""
import csv
import math
import os

import h5py

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
MR = ["-gimp_multirate", "true"]


def dump_run(name, opts, extra, ranks=1):
    dump = os.path.join(W, name + ".csv")
    out = gimptest.run(args, opts, extra + ["-gimp_particle_dump", dump], ranks=ranks,
                       outdir=os.path.join(W, name))
    with open(dump) as f:
        return out, list(csv.DictReader(f))


FIELDS = ("x", "y", "vx", "vy", "sxx", "syy", "sxy", "V", "lx", "ly")


def worst(a, b):
    """The largest difference of each quantity relative to its largest value (dumps by id)."""
    if [p["id"] for p in a] != [p["id"] for p in b]:
        return float("inf")
    out = 0.0
    for k in FIELDS:
        scale = max(abs(float(p[k])) for p in a) or 1.0
        out = max(out, max(abs(float(p[k]) - float(q[k])) for p, q in zip(a, b)) / scale)
    return out


def l2(a, b, keys):
    num = sum((float(p[k]) - float(q[k])) ** 2 for p, q in zip(a, b) for k in keys)
    den = sum(float(p[k]) ** 2 for p in a for k in keys)
    return math.sqrt(num / den)


# One level: R = 1, the multi-rate step is the single-rate one.
ONE = ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_history_interval", "60"]
for update, transfer in (("musl", ["apic"]), ("usl", ["apic"]), ("musl", ["flip", "-gimp_flip",
                                                                           "0.7"]),
                         ("musl", ["flip"]), ("usl", ["flip", "-gimp_flip", "0"])):
    extra = ONE + ["-gimp_update", update, "-gimp_transfer"] + transfer
    tag = "%s_%s" % (update, "_".join(transfer).replace("-gimp_", ""))
    _, a = dump_run("one_" + tag, "bench/block.opts", extra)
    _, b = dump_run("one_mr_" + tag, "bench/block.opts", extra + MR)
    d = worst(a, b)
    c.check("R = 1 equals single-rate (%s, %s)" % (update, " ".join(transfer)), d <= 1e-12,
            "%d particles after 60 steps: largest difference relative to the largest value "
            "%.1e" % (len(a), d))
# The same with a crack (the double cantilever beam on one 2 mm level, PIC): crack fields,
# faces and contact in the classes' sub-steps.
CRACK = ["-gimp_h", "2e-3", "-gimp_static_tol", "0", "-ts_max_steps", "300",
         "-gimp_history_interval", "300"]
# Closing: the arms pushed together (tractions reversed, 100 times the beam's), so that contact
# acts at every step, also on MUSL's re-projected velocities.
CLOSE = ["-gimp_traction0_value", "0,-3333.33", "-gimp_traction1_value", "0,3333.33"]
for update, load in (("musl", []), ("usl", []), ("musl", CLOSE), ("usl", CLOSE)):
    extra = CRACK + ["-gimp_update", update] + load
    tag = "crack_%s%s" % (update, "_closing" if load else "")
    _, a = dump_run("one_" + tag, "options/dcb_uniform.opts", extra)
    _, b = dump_run("one_mr_" + tag, "options/dcb_uniform.opts", extra + MR)
    d = worst(a, b)
    c.check("R = 1 with a crack equals single-rate (%s, PIC, %s)" %
            (update, "closing" if load else "opening"),
            d <= 1e-12, "%d particles after 300 steps: largest difference relative to the "
            "largest value %.1e" % (len(a), d))

# Momentum to round-off with particles crossing levels (the traction set to zero).
FREE = ["-gimp_traction0_value", "0,0", "-gimp_mass_cutoff", "0", "-ts_max_steps", "798",
        "-gimp_history_interval", "42"]
for update, transfer in (("musl", ["apic"]), ("usl", ["apic"]), ("usl", ["flip"]),
                         ("musl", ["flip"]), ("musl", ["flip", "-gimp_flip", "0"]),
                         ("musl", ["flip", "-gimp_flip", "0.7"])):
    tag = "%s_%s" % (update, "_".join(transfer).replace("-gimp_", ""))
    out, d = dump_run("free_" + tag, "options/drift3.opts",
                      FREE + ["-gimp_update", update, "-gimp_transfer"] + transfer + MR)
    h = gimptest.history(out)
    p0 = math.hypot(h["momentum_x"][0], h["momentum_y"][0])
    err = max(math.hypot(px - h["momentum_x"][0], py - h["momentum_y"][0])
              for px, py in zip(h["momentum_x"], h["momentum_y"])) / p0
    xmin = min(float(p["x"]) for p in d)
    c.check("momentum exact (%s, %s)" % (update, " ".join(transfer)),
            err <= 1e-12 and xmin > 1.2,
            "largest change of the momentum over %d rows %.1e of it; the body crossed into "
            "level 2 (its left end at x = %.3f, level 2 from 1.2)" % (len(h["step"]), err, xmin))

# The same answer as the single-rate step: the block with a tenth of its particles in the
# finest box, and the energy balance under a traction.
BLOCK = ["-ts_max_steps", "200", "-gimp_history_interval", "20"]
sr_out, sr = dump_run("block_sr", "bench/block3_tenth.opts", BLOCK)
mr_out, mr = dump_run("block_mr", "bench/block3_tenth.opts", BLOCK + MR)
hs, hm = gimptest.history(sr_out), gimptest.history(mr_out)
e0 = hs["total"][0]
# (Kinetic + strain: each class's kinetic and strain energy stand at the time of its velocities,
# half its own step before the row, so either alone differs by the slow classes' time offset.)
de = max(abs(a - b) for a, b in zip(
    [k + u for k, u in zip(hs["kinetic"], hs["strain"])],
    [k + u for k, u in zip(hm["kinetic"], hm["strain"])])) / e0
dv, ds = l2(sr, mr, ("vx", "vy")), l2(sr, mr, ("sxx", "syy", "sxy"))
c.check("three-level block: kinetic + strain energy",
        len(hs["step"]) == len(hm["step"]) and de <= 1e-4,
        "largest difference over %d rows %.1e of the energy" % (len(hs["step"]), de))
c.check("three-level block: particles", dv <= 0.02 and ds <= 0.005,
        "after 200 fine steps, L2 difference of the velocities %.2e, of the stresses %.2e" %
        (dv, ds))
balance = {}
for name, extra in (("sr", []), ("mr", MR)):
    out = gimptest.run(args, "options/drift3.opts", ["-ts_max_steps", "798"] + extra,
                       outdir=os.path.join(W, "traction_" + name))
    h = gimptest.history(out)
    balance[name] = (h["total"][-1] - h["total"][0]) / h["external_work"][-1]
c.check("energy balance under a traction", abs(balance["mr"]) <= 1e-3,
        "(energy - initial energy - work) / work at the end: multi-rate %.2e, single-rate %.2e"
        % (balance["mr"], balance["sr"]))

# Two ranks, with migration.
MIG = ["-ts_max_steps", "798", "-gimp_history_interval", "42"] + MR
_, one = dump_run("mig1", "options/drift3.opts", MIG)
_, two = dump_run("mig2", "options/drift3.opts", MIG, ranks=2)
d = worst(one, two)
c.check("np = 2 equals np = 1", d <= 1e-12,
        "%d particles after 798 steps: largest difference relative to the largest value %.1e"
        % (len(one), d))

# Restart from a checkpoint (written at step 792, a coarse-step end).
ck_out, full = dump_run("ck_full", "options/drift3.opts", MIG + ["-gimp_checkpoint_interval",
                                                                  "396"])
ck = os.path.join(W, "ck.h5")
os.replace(os.path.join(ck_out, "checkpoint.h5"), ck)
_, again = dump_run("ck_again", "options/drift3.opts", MIG + ["-gimp_restart", ck])
c.check("restart equals the straight run", worst(full, again) == 0.0,
        "largest difference %.1e" % worst(full, again))

# A finer box that shares an edge with its parent: the nodes on that edge reach a coarser cell
# (the grandparent's), and the classes must see that.
out = gimptest.run(args, "bench/block.opts", ["-gimp_h", "0.03125", "-gimp_levels", "3",
                                              "-gimp_level1_box", "0.25,0.25,0.75,0.75",
                                              "-gimp_level1_ratio", "2",
                                              "-gimp_level2_box", "0.25,0.25,0.5,0.5",
                                              "-gimp_level2_ratio", "2", "-ts_max_steps", "400",
                                              "-gimp_history_interval", "400"] + MR,
                   outdir=os.path.join(W, "shared_edge"))
s = gimptest.summary(out)
c.check("nested boxes sharing an edge", s["status"] == "completed" and s["steps"] == 400,
        "%s after %d fine steps" % (s["status"], s["steps"]))

# Reports at coarse-step ends, each once: intervals of 10 fine steps with R = 6.
out = gimptest.run(args, "options/drift3.opts", ["-ts_max_steps", "24", "-gimp_history_interval",
                                                 "10", "-gimp_output_interval", "10"] + MR,
                   outdir=os.path.join(W, "reports"))
steps = [int(x) for x in gimptest.history(out)["step"]]
with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
    frames = sorted(f["particles"].keys())
c.check("reports at coarse ends, once each", steps == [0, 12, 24] and
        frames == ["step_00000000", "step_00000012", "step_00000024"],
        "history rows at steps %s, frames %s" % (steps, frames))

# Stability at the CFL limit of the finest cell.
out = gimptest.run(args, "bench/block3.opts", ["-ts_max_steps", "2000", "-gimp_cfl", "1",
                                               "-gimp_history_interval", "500"] + MR,
                   outdir=os.path.join(W, "cfl1"))
s = gimptest.summary(out)
c.check("stable at the finest cell's CFL limit", s["status"] == "completed" and s["steps"] == 2000,
        "%s after %d fine steps" % (s["status"], s["steps"]))

# Bad input.
cases = [
    ("steps not a multiple of R", "bench/block3.opts", ["-ts_max_steps", "10"],
     "option -ts_max_steps 10: with -gimp_multirate true it must be a multiple"),
    ("time limit inside a coarse step", "options/wave_interface.opts",
     ["-ts_max_time", "0.0849"], "option -ts_max_time 0.0849"),
    ("cracks with FLIP", "options/dcb.opts", ["-gimp_flip", "1"],
     "option -gimp_flip 1: with cracks and -gimp_multirate true the velocities must be PIC or "
     "APIC"),
    ("corner tracking", "bench/block3.opts", ["-gimp_tracking", "corners"],
     "option -gimp_multirate true: not built with corner or CPDI tracking"),
    ("xpic", "bench/block3.opts", ["-gimp_transfer", "xpic"],
     "option -gimp_multirate true: not built with -gimp_transfer xpic"),
    ("usf", "bench/block3.opts", ["-gimp_update", "usf"],
     "option -gimp_multirate true: not built with -gimp_update usf"),
    ("a run to rest", "options/plate_static.opts", [],
     "option -gimp_static_tol 1e-06: a run to rest with -gimp_multirate true needs "
     "-gimp_multirate_forces node and -gimp_update usl"),
    ("the node rule with musl", "bench/block3.opts", ["-gimp_multirate_forces", "node"],
     "option -gimp_multirate_forces node: needs -gimp_update usl"),
    ("-gimp_multirate_forces bad value", "bench/block3.opts", ["-gimp_multirate_forces", "nodes"],
     "option -gimp_multirate_forces nodes: must be one of impulse, node"),
]


def refused(name, opts, extra, needle):
    """The run stops with exit 2 and one error line that holds needle."""
    p = gimptest.run(args, opts, extra, expect_ok=False, outdir=os.path.join(W, "bad"))
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    c.check("refused: " + name, p.returncode == 2 and len(lines) == 1 and needle in lines[0],
            "exit %d: %s" % (p.returncode, lines[0] if lines else "(no message)"))


for name, opts, extra, needle in cases:
    refused(name, opts, extra + MR, needle)
refused("-gimp_multirate_forces without -gimp_multirate", "bench/block3.opts",
        ["-gimp_multirate_forces", "node"],
        "option -gimp_multirate_forces node: acts only with -gimp_multirate true")
refused("a multi-rate checkpoint without -gimp_multirate", "options/drift3.opts",
        ["-gimp_restart", ck], "option -gimp_multirate false (the default): the checkpoint")


def stops(name, opts, extra, needle):
    """The run stops with exit 3 and one error line that holds needle, keeping its summary."""
    out = os.path.join(W, "stops_" + name)
    p = gimptest.run(args, opts, extra + MR, expect_ok=False, outdir=out)
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    kept = os.path.exists(os.path.join(out, "summary.json"))
    c.check("stops: " + name, p.returncode == 3 and len(lines) == 1 and needle in lines[0]
            and kept, "exit %d, summary kept %s: %s"
            % (p.returncode, kept, lines[0] if lines else "(no message)"))


# A class that comes onto a finer level's nodes within a coarse step: a body moving at about
# 0.9 c_p with ratios 4 (16 fine steps per coarse step), in 2D and in 3D (startClass's test).
FAST = ["-gimp_level1_ratio", "4", "-gimp_level2_ratio", "4"]
stops("a class reaching a finer level (2D)", "options/drift3.opts",
      FAST + ["-gimp_body0_velocity", "120,0", "-ts_dt", "1.4e-5", "-ts_max_steps", "320"],
      "a particle of level 1's rate class reached level 2's nodes within a coarse step")
stops("a class reaching a finer level (3D)", "options/block3d_multirate.opts",
      FAST + ["-gimp_body0_velocity", "1100,0,0", "-gimp_domain", "-0.25,-0.25,-0.25,2,2.125,2.125",
              "-ts_max_steps", "128"],
      "a particle of level 1's rate class reached level 2's nodes within a coarse step")
c.done()
