"""The step's clock: every phase of a step uses the step that TS takes.

A free block translating at uniform velocity (no load, no stress) must move by v0 T in time T,
every particle, to round-off (x + dt v summed step by step). With -ts_exact_final_time matchstep TS shortens the last steps to
land on -ts_max_time (here 10.5 steps of 1 ms: two last steps of 0.75 ms); a solver that moved
the particles with another step than the grid update (e.g. the next step's dt, read after TS
changed it) puts them 0.25 dt v0 short. The default (stepover) run checks the plain case.
"""
import csv
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
scene = os.path.join(args.work, "translate.opts")
with open(scene, "w") as f:
    f.write("\n".join([
        "-gimp_scene translate", "-gimp_E 1e6", "-gimp_nu 0.3", "-gimp_rho 1000", "-gimp_h 0.1",
        "-gimp_domain 0,0,4,2", "-gimp_body0_box 0.5,0.5,1.5,1.5", "-gimp_body0_ppc 4",
        "-gimp_body0_velocity 2,1", "-ts_dt 1e-3", "-ts_max_steps 100", ""]))
V0 = (2.0, 1.0)
for name, extra, T, steps in [
        ("stepover, 10 steps", ["-ts_max_time", "0.01"], 0.01, 10),
        ("matchstep, 10.5 steps", ["-ts_max_time", "0.0105", "-ts_exact_final_time", "matchstep"],
         0.0105, 11)]:
    out = os.path.join(args.work, name.split(",")[0])
    dump = os.path.join(out, "particles.csv")
    os.makedirs(out, exist_ok=True)
    s = gimptest.summary(gimptest.run(args, scene, extra + ["-gimp_particle_dump", dump],
                                      outdir=out))
    c.check(name + ": end time and steps", abs(s["time"] - T) < 1e-15 and s["steps"] == steps,
            "t = %.17g s after %d steps" % (s["time"], s["steps"]))
    with open(dump) as f:
        rows = list(csv.DictReader(f))
    # Initial positions: sub-cell centres of the 0.05 m particles in the body's cells.
    worst = 0.0
    for r in rows:
        x, y = float(r["x"]), float(r["y"])
        ux = x - (round((x - V0[0] * T - 0.525) / 0.05) * 0.05 + 0.525)
        uy = y - (round((y - V0[1] * T - 0.525) / 0.05) * 0.05 + 0.525)
        worst = max(worst, abs(ux - V0[0] * T) / (V0[0] * T), abs(uy - V0[1] * T) / (V0[1] * T))
        worst = max(worst, abs(float(r["vx"]) - V0[0]), abs(float(r["vy"]) - V0[1]))
    # Round-off: x of order 1.5 m summed over 11 steps, against a displacement of 0.01 m:
    # 11 * 1.1e-16 * 1.5 / 0.01 = 2e-13. The error this guards against is 0.25 dt / T = 2.4e-2.
    c.check(name + ": every particle moved by v0 T", len(rows) == 400 and worst < 1e-11,
            "%d particles, worst relative error %.3g" % (len(rows), worst))
c.done()
