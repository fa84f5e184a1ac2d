"""Multi-rate time steps per level in 3D (-gimp_multirate; docs/method.md, "Multi-rate time steps
per level"; docs/validation.md, "Multi-rate steps").

The scene: options/block3d_multirate.opts, a damped elastic plate on three levels (ratios 2 and
2, R = 4) under a ramped traction of 1 MPa, 14,560 particles, about a tenth of them in the finest
class. 1200 fine steps with -gimp_multirate false and true. With --scene bench/block3d_tenth.opts
(ctest multirate3d_tenth) the same checks on the larger plate whose finest box holds a tenth of
the particles (126,592; measured: probes within 0.25 % of the load in both runs, the energy
balances 0.02 % apart).

Checks:
  * the answer: both probes' sigma_xx (one in the finest box, one on level 0) within 1 % of the
    load at the end, in both runs;
  * the energy: (kinetic + strain) / external work at the end within 0.1 % of the single-rate
    run's (measured 0.06 %; the damping takes the rest of the work in both);
  * 2 ranks give the 1-rank answer to round-off: every particle quantity within 1e-10 of its
    largest value (measured 1.2e-12, in sigma_yy and sigma_zz: the sums over ranks add in another
    order, and the lateral stresses are 0.5 % of the load);
  * bad input in 3D: a step limit that is not a whole number of coarse steps is refused in one
    line.
The wall times of the single-rate and multi-rate runs (one rank) are printed, not asserted.
"""
import argparse
import csv
import os
import sys

import gimptest

pre = argparse.ArgumentParser(add_help=False)
pre.add_argument("--scene", default="options/block3d_multirate.opts",
                 help="the scene (relative to --root), a plate under the same load")
mine, rest = pre.parse_known_args()
sys.argv = sys.argv[:1] + rest
args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
SCENE = mine.scene
MR = ["-gimp_multirate", "true"]
LOAD = 1e6
FIELDS = ("x", "y", "z", "vx", "vy", "vz", "sxx", "syy", "szz", "V")


def dump_run(name, extra, ranks=1):
    dump = os.path.join(W, name + ".csv")
    out = gimptest.run(args, SCENE, extra + ["-gimp_particle_dump", dump], ranks=ranks,
                       outdir=os.path.join(W, name))
    with open(dump) as f:
        return out, list(csv.DictReader(f))


def worst(a, b):
    """The largest difference of each quantity relative to its largest value (dumps by id)."""
    if [p["id"] for p in a] != [p["id"] for p in b]:
        return float("inf")
    out = 0.0
    for k in FIELDS:
        scale = max(abs(float(p[k])) for p in a) or 1.0
        out = max(out, max(abs(float(p[k]) - float(q[k])) for p, q in zip(a, b)) / scale)
    return out


res = {}
for tag, extra in (("single", []), ("multirate", MR)):
    out, dump = dump_run(tag, extra)
    h, s = gimptest.history(out), gimptest.summary(out)
    res[tag] = {"dump": dump, "wall": s["wall_seconds"], "steps": s["steps"],
                "fine": h["fine_sxx"][-1], "coarse": h["coarse_sxx"][-1],
                "balance": (h["kinetic"][-1] + h["strain"][-1]) / h["external_work"][-1]}
for tag, r in res.items():
    err = max(abs(r["fine"] - LOAD), abs(r["coarse"] - LOAD)) / LOAD
    c.check("%s: probe stresses at the load" % tag, r["steps"] == 1200 and err <= 0.01,
            "sigma_xx %.4g (finest box), %.4g (level 0) after %d steps: %.2f %% off the load"
            % (r["fine"], r["coarse"], r["steps"], 100 * err))
a, b = res["single"], res["multirate"]
de = abs(b["balance"] - a["balance"]) / a["balance"]
c.check("energy balance as the single-rate step's", de <= 1e-3,
        "(kinetic + strain) / external work %.5f multi-rate, %.5f single-rate: %.3f %% apart"
        % (b["balance"], a["balance"], 100 * de))

_, two = dump_run("multirate_np2", MR, ranks=2)
d = worst(b["dump"], two)
c.check("np = 2 equals np = 1", d <= 1e-10,
        "%d particles after 1200 steps: largest difference relative to the largest value %.1e"
        % (len(two), d))

p = gimptest.run(args, SCENE, MR + ["-ts_max_steps", "10"], expect_ok=False,
                 outdir=os.path.join(W, "bad"))
lines = [line for line in p.stderr.splitlines() if line.strip()]
needle = "option -ts_max_steps 10: with -gimp_multirate true it must be a multiple"
c.check("refused: steps not a multiple of R", p.returncode == 2 and len(lines) == 1 and
        needle in lines[0], "exit %d: %s" % (p.returncode, lines[0] if lines else "(no message)"))

print("wall seconds (one rank, one run each; not asserted): single-rate %.2f, multi-rate %.2f, "
      "ratio %.2f" % (a["wall"], b["wall"], a["wall"] / b["wall"]))
c.done()
