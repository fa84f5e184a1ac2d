"""Levels that follow a point (options/follow_spin.opts: a square moving at (1, 0.5) m/s and
spinning at 0.1 rad/s, its fine box following the particle at its corner):
  - the box moves by whole level-0 cells, keeps its size, and keeps the followed particle more
    than the margin (1 m) from its faces after each move; it moves at least 4 times and some
    level-0 particles are split;
  - every move keeps the particles' mass, momentum, angular momentum sum m (x × v) + m ε:Bᵀ and
    kinetic + strain energy (summary.json's regrids, before and after) to 1e-13 of their size;
  - the split particles: every particle of the final state lies in the body (the rigid motion of
    the square), with the volume of the level that holds it or a coarser one, and the ids are
    unique;
  - with -gimp_follow_merge true, the particles a box leaves merge back: fewer particles, each
    move keeping mass, momentum and angular momentum to 1e-13 and the energy within 1e-4;
  - the grid frames (grid.xmf) place level 1 where it was when each frame was written;
  - the whole run keeps momentum and APIC's angular momentum to 1e-12 (the frames);
  - 2 ranks make the same moves and give the 1-rank history to round-off, and a restart from a
    checkpoint taken between moves gives the history, the particles and the moves bit for bit.
In 3D (options/follow_spin3d.opts, a box spinning about no principal axis while it moves): the
box moves, each move keeps the sums, the run keeps the angular momentum vector to 1e-12, and 2
ranks make the same moves and history.
(docs/validation.md, *Levels that follow a point*)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gimptest  # noqa: E402
import h5py  # noqa: E402

SCENE = "options/follow_spin.opts"
MARGIN, H0, SIDE = 1.0, 1.0, 4.0
args = gimptest.parse_args()
c = gimptest.Checks()

def dump(outdir):
    os.makedirs(outdir, exist_ok=True)
    return ["-gimp_particle_dump", os.path.join(outdir, "particles.csv")]


one = os.path.join(args.work, "one")
KEEP = ["-gimp_follow_merge", "false"]  # the exact moves; the default merge is checked below
out = gimptest.run(args, SCENE, KEEP + dump(one), outdir=one)
s = gimptest.summary(out)
moves = s["measures"]["regrids"]
added = sum(r["particles_added"] for r in moves)
c.check("the box moves", len(moves) >= 4 and added > 0,
        "%d moves, %d particles added by splits" % (len(moves), added))

# Whole cells, same size, the followed particle inside the margin after each move.
hist = gimptest.history(out)
ok, worst = True, 1e300
for r in moves:
    b = np.array(r["box"])
    ok = ok and np.allclose(b / H0, np.round(b / H0), atol=1e-12)
    ok = ok and np.allclose(b[2:] - b[:2], SIDE, atol=1e-12)
c.check("whole cells, same size", ok, "boxes: %s" % [r["box"] for r in moves])
final = np.array(s["levels"][1]["box"])
px = np.array(s["probes"]["probe0"]["x0"]) + np.array(s["probes"]["probe0"]["u"])
clear = min(np.min(px - final[:2]), np.min(final[2:] - px))
c.check("the point inside its margin at the end", clear > 0,
        "the probe's particle %.3f m from the final box's nearest face (margin %.1f m; it "
        "moves when nearer)" % (clear, MARGIN))

# Each move keeps the conserved sums.
def rel(a, b, scale):
    return np.abs(np.array(a) - np.array(b)).max() / scale


def conservation(moves, name, energy=1e-13):
    worst = {"mass": 0.0, "momentum": 0.0, "angular momentum": 0.0, "energy": 0.0}
    for r in moves:
        b, a = r["before"], r["after"]
        worst["mass"] = max(worst["mass"], rel(a["mass"], b["mass"], b["mass"]))
        worst["momentum"] = max(worst["momentum"],
                                rel(a["momentum"], b["momentum"], np.linalg.norm(b["momentum"])))
        worst["angular momentum"] = max(
            worst["angular momentum"], rel(a["angular_momentum"], b["angular_momentum"],
                                           np.linalg.norm(b["angular_momentum"])))
        worst["energy"] = max(worst["energy"], rel(a["energy"], b["energy"], b["energy"]))
    for k, v in worst.items():
        bound = energy if k == "energy" else 1e-13
        c.check("%s: a move keeps the %s" % (name, k), v < bound,
                "largest relative change over the moves %.1e (bound %.0e)" % (v, bound))


conservation(moves, "2D")

# The final particles: in the body, sizes of some level, unique ids.
d = gimptest.read_csv(os.path.join(out, "particles.csv"))
x, y = np.array(d["x"]), np.array(d["y"])
ids = np.array(d["id"])
c.check("ids unique", len(set(ids)) == len(ids), "%d particles" % len(ids))
V = np.array(d["V"])
sizes = np.array([0.25, 0.0625])  # level 0 and level 1 particles (2 x 2 per cell)
off = np.abs(V[:, None] / sizes[None, :] - 1).min(axis=1).max()
c.check("particle volumes of a level", off < 0.01,
        "largest distance of V from a level's particle volume: %.2e (of it)" % off)
t = s["time"]
w, v0, centre0 = 0.1, np.array([1.0, 0.5]), np.array([2.0, 2.0])
cx = centre0 + v0 * t
rot = np.array([[np.cos(-w * t), -np.sin(-w * t)], [np.sin(-w * t), np.cos(-w * t)]])
loc = (np.stack([x, y], 1) - cx) @ rot.T  # into the square's frame
outside = np.abs(loc).max() - 2.0
c.check("particles in the body", outside < 0.25,
        "the farthest particle centre %.3f m beyond the rigidly moved square (half a particle of "
        "level 0 is 0.25 m)" % outside)

# The grid frames show level 1 where it was when each was written (after the step's report,
# before that step's move).
import re  # noqa: E402
xmf = open(os.path.join(out, "grid.xmf")).read()
frames = re.findall(r'<Grid Name="step_(\d+)".*?<Grid Name="level_1".*?Format="XML">([^<]*)<',
                    xmf, re.S)
wrong = []
for step, origin in frames:
    n = int(step)
    later = [r for r in moves if r["step"] >= n]
    box = later[0]["previous"] if later else s["levels"][1]["box"]
    y0, x0 = (float(v) for v in origin.split())
    if abs(x0 - box[0]) > 1e-12 or abs(y0 - box[1]) > 1e-12:
        wrong.append((n, (x0, y0), box[:2]))
c.check("grid frames at their boxes", len(frames) >= 8 and not wrong,
        "%d frames; wrong: %s" % (len(frames), wrong))

# The run's momentum and angular momentum (the frames).
L, P = [], []
with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
    for k in sorted(f["particles"].keys()):
        g = f["particles"][k]
        m, xx, vv, B = g["m"][:], g["x"][:], g["v"][:], g["B"][:]
        L.append((m * (xx[:, 0] * vv[:, 1] - xx[:, 1] * vv[:, 0] + B[:, 2] - B[:, 1])).sum())
        P.append((m[:, None] * vv).sum(axis=0))
dL = max(abs(l - L[0]) for l in L) / abs(L[0])
dP = max(np.linalg.norm(p - P[0]) for p in P) / np.linalg.norm(P[0])
c.check("the run keeps momentum and angular momentum", dL < 1e-12 and dP < 1e-12,
        "over %d frames: |dL| / |L0| %.1e, |dP| / |P0| %.1e" % (len(L), dL, dP))

# With -gimp_follow_merge true the parts a box leaves merge back: mass, momentum and angular
# momentum kept to round-off, the energy of the parts' motion about their centre (here the spin's,
# about 1e-5 of the total per move) left to B.
merge = os.path.join(args.work, "merge")
outm = gimptest.run(args, SCENE, ["-gimp_follow_merge", "true"] + dump(merge), outdir=merge)
sm = gimptest.summary(outm)
movesm = sm["measures"]["regrids"]
merged = [r for r in movesm if r["particles_added"] < 0]
c.check("merge: parts merge back", merged and sm["particles"] < s["particles"],
        "%d of %d moves removed particles; %d particles at the end against %d kept"
        % (len(merged), len(movesm), sm["particles"], s["particles"]))
conservation(movesm, "merge", energy=1e-4)  # the parts' motion about their centre: energy

# 2 ranks, and a restart between moves, keeping and merging.
def ranks_and_restart(extra, name, out, hist, moves):
    out2 = gimptest.run(args, SCENE, extra, ranks=2, outdir=os.path.join(args.work, "two" + name))
    h2 = gimptest.history(out2)
    # Each column against its largest value. The stresses are small here (0.07 Pa against E =
    # 1e4 Pa: the rotation's strain is 1e-5), so their round-off, 1e-16 E, is 1e-11 of them.
    diff = max(max(abs(a - b) for a, b in zip(hist[k], h2[k])) / max(abs(a) for a in hist[k])
               for k in ("kinetic", "strain", "momentum_x", "momentum_y", "probe0_ux",
                         "probe0_uy", "probe0_sxx", "probe0_syy", "probe0_sxy"))
    c.check("%s: 2 ranks give the 1-rank run" % name, diff < 1e-10 and
            [r["step"] for r in gimptest.summary(out2)["measures"]["regrids"]] ==
            [r["step"] for r in moves],
            "the same moves; largest difference in a history column %.1e of its largest value"
            % diff)
    half = os.path.join(args.work, "restart" + name)
    stop = (moves[0]["step"] + moves[1]["step"]) // 2
    gimptest.run(args, SCENE, extra + ["-ts_max_steps", str(stop), "-gimp_checkpoint_interval",
                                       str(stop)], outdir=half)
    gimptest.run(args, SCENE, extra + ["-gimp_restart", os.path.join(half, "checkpoint.h5")] +
                 dump(half), outdir=half)
    same = all(open(os.path.join(out, f), "rb").read() == open(os.path.join(half, f), "rb").read()
               for f in ("history.csv", "particles.csv"))
    same = same and gimptest.summary(half)["measures"]["regrids"] == moves
    c.check("%s: a restart between moves continues bit for bit" % name, same,
            "restart at step %d (moves at %s)" % (stop, [r["step"] for r in moves]))


ranks_and_restart(KEEP, "keep", out, hist, moves)
ranks_and_restart(["-gimp_follow_merge", "true"], "merge", outm, gimptest.history(outm), movesm)

# 3D: a box moving and spinning about no principal axis (options/follow_spin3d.opts).
SCENE3 = "options/follow_spin3d.opts"
out3 = gimptest.run(args, SCENE3, [], outdir=os.path.join(args.work, "one3d"))
s3 = gimptest.summary(out3)
moves3 = s3["measures"]["regrids"]
c.check("3D: the box moves", len(moves3) >= 3 and sum(r["particles_added"] for r in moves3) > 0,
        "%d moves, %d particles added" % (len(moves3), sum(r["particles_added"] for r in moves3)))
conservation(moves3, "3D, merging", energy=1e-4)
L = []
with h5py.File(os.path.join(out3, "fields.h5"), "r") as f:
    for k in sorted(f["particles"].keys()):
        g = f["particles"][k]
        m, xx, vv, B = g["m"][:], g["x"][:], g["v"][:], g["B"][:]
        spin = np.stack([B[:, 7] - B[:, 5], B[:, 2] - B[:, 6], B[:, 3] - B[:, 1]], axis=1)
        L.append((m[:, None] * (np.cross(xx, vv) + spin)).sum(axis=0))
dL = max(np.linalg.norm(l - L[0]) for l in L) / np.linalg.norm(L[0])
c.check("3D: the run keeps the angular momentum vector", dL < 1e-12,
        "over %d frames: |L - L0| / |L0| %.1e" % (len(L), dL))
out32 = gimptest.run(args, SCENE3, [], ranks=2, outdir=os.path.join(args.work, "two3d"))
h3, h32 = gimptest.history(out3), gimptest.history(out32)
diff = max(max(abs(a - b) for a, b in zip(h3[k], h32[k])) / max(abs(a) for a in h3[k])
           for k in ("kinetic", "strain", "momentum_x", "momentum_z", "probe0_ux", "probe0_sxx"))
c.check("3D: 2 ranks give the 1-rank run", diff < 1e-10 and
        [r["step"] for r in gimptest.summary(out32)["measures"]["regrids"]] ==
        [r["step"] for r in moves3],
        "the same moves; largest difference in a history column %.1e of its largest value"
        % diff)
c.done()
