"""Grid-node constraints on part of a plane in 3D (-gimp_bcK_x/_y/_z, -gimp_bcK_range a0,a1,b0,b1
in the plane's two other coordinates in axis order, -gimp_bcK_type fixed|roller|x|y|z;
docs/options.md).

Scene (written to the work directory): a 0.8 x 0.6 x 0.4 m block (h = 0.1 m, 2 x 2 x 2 particles
per cell, E = 1e5 Pa, nu = 0.3, rho = 1000) under gravity g = (0, -3, -10) m/s^2 for 0.1 s,
held by two constraints: bc0 on the plane z = 0 over x in [0, 0.4], y in [0, 0.6] (type fixed,
its left half of the bottom), bc1 on the plane y = 0 over x in [0.6, 0.8], z in [0.2, 0.4] (type
y: only v_y). Checked, on one level and on two (a level of h = 0.05 m over
[0.2, 0.6] x [0, 0.3] x [-0.1, 0.2], whose nodes straddle the end of bc0's range), and on two
ranks:
- every node of every level that carries mass (above the solver's cut-off) on either plane, in the
  last frame of fields.h5:
  a velocity component is exactly 0 if and only if a constraint whose plane and range hold the
  node holds that component: on bc0's plane all three in the range and none outside it; on
  bc1's v_y only in its range (its v_x and v_z move; a range read in the wrong axis order would
  hold other nodes); where the planes meet, bc0's range holds all three;
- the particles of the bottom layer above the held part (x0 < 0.3 m) move down by less than a
  tenth of the free fall g t^2 / 2 = 0.05 m [0.0021 m, 0.0022 m on two levels], those beyond
  it (x0 > 0.5 m) by more than half of it [0.030 m]: the block hangs on its held half;
- two ranks (two levels) give one rank's particles within 1e-10 [1e-15], with the same held
  nodes;
- a range in the plane that holds no node (x in [0.41, 0.49]: between the node planes
  x = 0.4 and 0.5) is refused in one line naming -gimp_bc0_range, exit 2.
"""
import os

import h5py
import numpy as np

import compare3d
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
G, T = 10.0, 0.1
SCENE = """-gimp_dim 3
-gimp_scene bc_range3d
-gimp_E 1e5
-gimp_nu 0.3
-gimp_rho 1000
-gimp_h 0.1
-gimp_domain -0.2,-0.2,-0.2,1.0,0.8,0.6
-gimp_body0_box 0,0,0,0.8,0.6,0.4
-gimp_body0_ppc 8
-gimp_gravity 0,-3,-10
-gimp_bcs 2
-gimp_bc0_z 0
-gimp_bc0_range 0,0.4,0,0.6
-gimp_bc0_type fixed
-gimp_bc1_y 0
-gimp_bc1_range 0.6,0.8,0.2,0.4
-gimp_bc1_type y
-ts_max_time %g
-ts_max_steps 100000
-gimp_history_interval 20
""" % T
# (plane axis, plane coordinate, ((axis, lo, hi), (axis, lo, hi)), held components)
BCS = ((2, 0.0, ((0, 0.0, 0.4), (1, 0.0, 0.6)), (0, 1, 2)),
       (1, 0.0, ((0, 0.6, 0.8), (2, 0.2, 0.4)), (1,)))
LEVELS = ["-gimp_levels", "2", "-gimp_level1_box", "0.2,0,-0.1,0.6,0.3,0.2"]
opts = os.path.join(args.work, "bc_range3d.opts")
with open(opts, "w") as f:
    f.write(SCENE)


def grid_check(tag, out):
    s = gimptest.summary(out)
    # A node carries mass above the solver's cut-off (-gimp_mass_cutoff, 1e-14 of the mean
    # particle mass): below it the node takes no velocity (a tracked corner a rounding above the
    # block's top face gives the node beyond it a weight of 1e-16).
    cut = 1e-14 * 1000 * 0.8 * 0.6 * 0.4 / s["particles"]
    with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
        last = f["grid"][sorted(f["grid"].keys())[-1]]
        wrong, held, moving = [], [0, 0], [0, 0]
        for k, lv in enumerate(s["levels"]):
            v = np.array(last["level_%d" % k]["velocity"])
            m = np.array(last["level_%d" % k]["mass"])
            h, box = lv["h"], lv["box"]
            tol = 1e-9 * h
            for (iz, iy, ix), mass in np.ndenumerate(m):
                if not mass > cut:
                    continue
                x = [box[0] + ix * h, box[1] + iy * h, box[2] + iz * h]
                vel = v[iz, iy, ix]
                planes, comps = [], set()
                for b, (axis, at, rng, held_comps) in enumerate(BCS):
                    if abs(x[axis] - at) > tol:
                        continue
                    inside = all(lo - tol <= x[a] <= hi + tol for a, lo, hi in rng)
                    planes.append(b)
                    if inside:
                        comps |= set(held_comps)
                        held[b] += 1
                    else:
                        moving[b] += 1
                if not planes:
                    continue
                # held components exactly 0, every other one moving
                if not all((vel[a] == 0.0) == (a in comps) for a in range(3)):
                    wrong.append("level %d node %s (on the plane of bc%s, holding %s): v %s" % (
                        k, x, planes, sorted(comps), list(vel)))
    c.check(tag + ": held nodes", not wrong and min(held) > 0 and min(moving) > 0,
            "nodes with mass on bc0's plane: %d held, %d moving; on bc1's: %d held, %d moving; "
            "%d wrong%s" % (held[0], moving[0], held[1], moving[1], len(wrong),
                            (": " + wrong[0]) if wrong else ""))


def particle_check(tag, d0, d):
    fall = 0.5 * G * T * T
    hold, free = [], []
    for i in range(len(d0["id"])):
        if d0["z"][i] - d0["lz"][i] < 1e-9:  # the bottom layer: the particle touches z = 0
            uz = d["z"][i] - d0["z"][i]
            if d0["x"][i] < 0.3:
                hold.append(-uz)
            elif d0["x"][i] > 0.5:
                free.append(-uz)
    c.check(tag + ": the block hangs on its held half", hold and free and
            max(abs(u) for u in hold) < 0.1 * fall and min(free) > 0.5 * fall,
            "bottom layer: above the range (%d particles) |u_z| <= %.4f m (< %.4f), beyond it "
            "(%d) u_z down >= %.4f m (> %.4f); free fall %.3f m" % (
                len(hold), max(abs(u) for u in hold), 0.1 * fall, len(free), min(free),
                0.5 * fall, fall))


runs = {}
for tag, extra in (("one level", []), ("two levels", LEVELS)):
    name = tag.replace(" ", "_")
    _, dump0 = compare3d.dump_run(args, opts, name + "_0", extra + ["-ts_max_steps", "0"])
    out, dump = compare3d.dump_run(args, opts, name, extra)
    d0, d = compare3d.read_dump(dump0)[1], compare3d.read_dump(dump)[1]
    grid_check(tag, out)
    particle_check(tag, d0, d)
    runs[tag] = d
out2, dump2 = compare3d.dump_run(args, opts, "two_levels_np2", LEVELS, ranks=2)
grid_check("two levels, 2 ranks", out2)
dd, group = compare3d.dump_diff(runs["two levels"], compare3d.read_dump(dump2)[1])
c.check("two levels: 2 ranks = 1 rank", dd < 1e-10,
        "largest difference %.1e of its group's scale (%s); tol 1e-10" % (dd, group))

p = compare3d.dump_run(args, opts, "refused", ["-gimp_bc0_range", "0.41,0.49,0,0.6"],
                       expect_ok=False)
lines = p.stderr.strip().splitlines()
c.check("a range without a node refused", p.returncode == 2 and len(lines) == 1 and
        lines[0].startswith("gimp: error: option -gimp_bc0_range 0.41,0.49,0,0.6:") and
        "no active grid node" in lines[0], "exit %d: %s" % (p.returncode, p.stderr.strip()))
c.done()
