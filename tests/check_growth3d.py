"""Crack growth along a 3D front (-gimp_crack_growth mts; docs/method.md, Crack growth in 3D).

Quick part (default suite; ctest growth3d_quick runs --part one, the 1-rank run, its checks and
the restart, and growth3d_ranks --part ranks, the 2-rank run against it; without --part both):
options/penny_growth3d.opts, a penny crack of radius 5 mm in a block under a sudden 2 MPa,
toughness 1 J/m^2, 150 steps.
  - The front grows: at least 3 growth checks advance it, every front point has advanced by
    the end (history.csv crack0_advance_mean > 0 and _max within one step of the growth length)
    and each increment record lies one growth step (0.5 mm) ahead of a front point of the crack
    before it, in the crack's plane z = 0.
  - The crack's front stays symmetric about the quarter's diagonal x = y (the grid, the polygon
    and the load are): the summary's front points and growth records mirrored pairwise to 1e-9.
  - 2 ranks give the 1-rank run: the ranks split along z at the crack's plane
    (-da_processors_z 2), so that the two faces of the crack and the nodes on the plane belong
    to different ranks; the growth records (time, point, place) equal, G, K and the particle dump
    within 1e-10 of their scale.
  - A restart from the checkpoint of step 100 (after the front grew) equals the uninterrupted run
    bit for bit (the particle dump, history.csv, summary.json but its timing keys, the last
    frame).

With --physics (ctest growth3d, label verification; about 4 minutes): the penny crack of
options/penny3d.opts started at a = 8 mm with toughness 1 J/m^2 (below G as soon as the load
arrives), growth length 2 mm: every front point grows twice, the crack then has radius a' = 8 +
2 / cos(pi / 52) mm (its 52-gon's vertices moved out along their bisectors) and stops; the run
damps to rest and K must be that of the grown crack, K_I = 2 sigma sqrt(a' / pi), at every front
point, with the same tolerances as tests/check_penny3d.py's for the crack given at 10 mm on the
same grid (K_I and K from G within 5 %, K from G's mean within 3.5 %, K_I within 1 % of K from G,
K_II and K_III under 2 % of K_I): the second velocity fields, contact and tubes follow the grown
front.
Then the quick part's scene with a growth length of 20 mm, 400 steps: the front grows from 5 to
13.5 .. 14.1 mm, its ends sliding along the symmetry planes, and stops (one warning) only when
it comes within 2 cells of the block's faces, where no tube fits: checked that it reached 12 mm
everywhere and stopped for that reason.
Then a crack through a slab in plane strain (options/through_crack3d.opts, toughness 20 J/m^2,
8 mm of growth) grows as its 2D twin (options/through_crack2d.opts): the same 8 increments at the
same checks, the 3D front points where the 2D tip is, G within 2 % of the 2D tip's [0.13 %]; the
same with each increment opening over 30 us (-gimp_crack_growth_release) [0.1 %], where the
release moves the 3D front's G by at least 5 % [31.7 %]; and under in-plane shear the first
point to grow would kink by 70.5 degrees, so the crack stops there, not grown, with one warning.
And the slab's finest box following the front (-gimp_level2_follow crack0_front) against a
fixed finest box over the whole path: the same increments at the same checks and places, K_I
within 1 % [0.73 %], fewer particles, moves that keep mass and momentum to round-off (and with
-gimp_follow_merge false the energy exactly); the same with the 30 us release, the box moving
while advances are still opening [K_I within 0.25 %]."""
import argparse
import math
import os
import shutil
import sys

import compare3d
import gimptest
from restart_files import run_with_dump, same_bits

pre = argparse.ArgumentParser(add_help=False)
pre.add_argument("--physics", action="store_true")
# The quick part in two tests that ctest can pack (tests/CMakeLists.txt): "one", the 1-rank run,
# its checks and the restart (1 processor), and "ranks", the 2-rank run against the 1-rank run
# of --one (that test's run directory); "all" (the default) both in one.
pre.add_argument("--part", choices=("all", "one", "ranks"), default="all")
pre.add_argument("--one", default=None)
mine, rest = pre.parse_known_args()
sys.argv = sys.argv[:1] + rest
args = gimptest.parse_args()
c = gimptest.Checks()


def mirrored(xs, key):
    """Largest |v_i - mirror(v_{n-1-i})| over a list of points mirrored about x = y."""
    n, worst = len(xs), 0.0
    for i in range(n):
        p, q = xs[i][key], xs[n - 1 - i][key]
        worst = max(worst, abs(p[0] - q[1]), abs(p[1] - q[0]), abs(p[2] - q[2]))
    return worst


if mine.physics:
    E, nu, sigma = 2.3e9, 0.3, 1e6
    Ep = E / (1 - nu * nu)
    a0, grow, step = 0.008, 0.002, 0.001
    out = gimptest.run(args, "options/penny3d.opts",
                       ["-gimp_scene", "penny_grown3d", "-gimp_crack0_disk", "0,0,0,0,0,1,0.008",
                        "-gimp_crack_growth", "mts", "-gimp_Gc", "1",
                        "-gimp_crack_growth_length", str(grow),
                        "-gimp_crack_growth_interval", "100"])
    s = gimptest.summary(out)
    crack = s["cracks"][0]
    front, records = crack["front"], crack["growth"]
    checks = sorted({g["t"] for g in records})
    a1 = a0 + grow / math.cos(math.pi / 52)
    K0 = 2 * sigma * math.sqrt(a1 / math.pi)
    c.check("grown twice", len(checks) == 2 and len(records) == 2 * len(front),
            "%d growth checks advanced the front, %d records for %d front points" %
            (len(checks), len(records), len(front)))
    radii = [math.hypot(f["x"][0], f["x"][1]) for f in front]
    want = a1 * math.cos(math.pi / 52)  # the edges' midpoints
    c.check("grown front", all(abs(r - want) < 1e-9 for r in radii),
            "front points at radius %.6f .. %.6f mm (the 52-gon of radius %.6f mm: %.6f)" %
            (1e3 * min(radii), 1e3 * max(radii), 1e3 * a1, 1e3 * want))
    worstG = worstI = mixed = agree = meanG = 0.0
    for f in front:
        ang = math.degrees(math.atan2(f["x"][1], f["x"][0]))
        eG = math.sqrt(max(f["G"], 0.0) * Ep) / K0 - 1
        eI = f["KI"] / K0 - 1
        print("  %5.1f deg  K(G) %+6.2f %%  K_I %+6.2f %%  K_II %+.1e  K_III %+.1e" %
              (ang, 100 * eG, 100 * eI, f["KII"] / K0, f["KIII"] / K0))
        worstG, worstI = max(worstG, abs(eG)), max(worstI, abs(eI))
        mixed = max(mixed, abs(f["KII"]) / K0, abs(f["KIII"]) / K0)
        agree = max(agree, abs(f["KI"] / math.sqrt(max(f["G"], 0.0) * Ep) - 1))
        meanG += eG / len(front)
    c.check("K from G on the grown crack", worstG <= 0.05 and abs(meanG) <= 0.035,
            "worst %.2f %% (tol 5 %%), mean %+.2f %% (tol 3.5 %%) against 2 sigma sqrt(a'/pi), "
            "a' = %.4f mm" % (100 * worstG, 100 * meanG, 1e3 * a1))
    c.check("K_I on the grown crack", worstI <= 0.05, "worst %.2f %% (tol 5 %%)" % (100 * worstI))
    c.check("K_I = K from G", agree <= 0.01, "largest |K_I / sqrt(G E') - 1| %.2f %% (tol 1 %%)"
            % (100 * agree))
    c.check("K_II and K_III", mixed <= 0.02, "max %.1e of K_I (tol 2 %%)" % mixed)
    k = gimptest.history(out)["crack0_KI_mean"]
    change = abs(k[-1] / k[-3] - 1)
    c.check("at rest", s["status"] == "completed" and change <= 2e-3,
            "status %s, mean K_I changed by %.1e over the last 400 steps" % (s["status"], change))
    # Growth until the front runs out of room: options/penny_growth3d.opts with a growth length
    # of 20 mm. The crack may only stop when its front comes within 2 cells (of level 0, 2 mm,
    # where it has grown to) of the block's faces at 16 mm: its ends slide along the symmetry
    # planes all the way.
    far = gimptest.run(args, "options/penny_growth3d.opts",
                       ["-gimp_crack_growth_length", "0.02", "-ts_max_steps", "400"],
                       outdir=os.path.join(args.work, "far"), expect_ok=False)
    sf = gimptest.summary(os.path.join(args.work, "far"))
    radii = [math.hypot(f["x"][0], f["x"][1]) for f in sf["cracks"][0]["front"]]
    stop = [l for l in (far.stdout + far.stderr).splitlines() if "stops growing" in l]
    c.check("grows until the faces stop it", far.returncode == 0 and len(stop) == 1 and
            "no tube fits" in stop[0] and min(radii) >= 0.012,
            "front from %.2f to %.2f mm; %s" % (1e3 * min(radii), 1e3 * max(radii),
                                              stop[0] if stop else "no stop line"))
    # A crack through a slab in plane strain grows as its 2D twin (options/through_crack3d.opts
    # and through_crack2d.opts; toughness 20 J/m^2, below the G the load brings, 8 mm of growth
    # checked every 50 steps): the same increments at the same checks, every front point of the
    # slab where the 2D tip is, and G within 2 % of the 2D tip's at each (the through-crack
    # tolerance).
    grow = ["-gimp_crack_growth", "mts", "-gimp_Gc", "20", "-gimp_crack_growth_length", "8e-3",
            "-gimp_crack_growth_interval", "50", "-ts_max_time", "3e-4"]

    def twins(extra, tag):
        """The 2D tip's and the 3D front's increments of the through crack, each run with extra."""
        g2 = [g for k in gimptest.summary(gimptest.run(
            args, "options/through_crack2d.opts", grow + extra,
            outdir=os.path.join(args.work, "tc2" + tag)))["cracks"] for g in k.get("growth", [])]
        g3 = gimptest.summary(gimptest.run(args, "options/through_crack3d.opts", grow + extra,
                                           outdir=os.path.join(args.work, "tc3" + tag))
                              )["cracks"][0]["growth"]
        times = sorted({g["t"] for g in g3})
        same, dG = len(times) == len(g2) and len(g2) >= 5, 0.0
        for t, tip in zip(times, g2):
            at = [g for g in g3 if g["t"] == t]
            same = same and t == tip["t"] and all(abs(g["x"][0] - tip["x"][0]) <= 1e-12 and
                                                  abs(g["x"][1] - tip["x"][1]) <= 1e-12
                                                  for g in at)
            dG = max([dG] + [abs(g["G"] / tip["G"] - 1) for g in at])
        return g2, g3, times, same, dG

    release = ["-gimp_crack_growth_release", "3e-5"]  # (three checks)
    runs = {}
    for extra, tag, what in (([], "", ""), (release, "_release", " with a release of 30 us")):
        g2, g3, times, same, dG = twins(extra, tag)
        c.check("through crack grows as its 2D twin" + what, same and dG <= 0.02,
                "%d increments in 2D, %d checks advanced the 3D front (%d records), %s places "
                "and times; G within %.2f %% (tol 2 %%)" %
                (len(g2), len(times), len(g3), "the same" if same else "DIFFERENT", 100 * dG))
        runs[tag] = g3
    # Each increment opens over three growth checks: the G that grows the next one falls (the
    # 3D front's release is the 2D tip's, not a crack that opens at once).
    moved = max(abs(b["G"] / a["G"] - 1) for a, b in zip(runs[""], runs["_release"]))
    c.check("the release moves G", moved >= 0.05,
            "G at the increments by up to %.1f %% from the crack that opens at once (at least 5 %%)"
            % (100 * moved))
    # A fine box that follows the front: the slab's finest box (4 .. 16 mm along x, the front
    # starting at 10 mm) follows crack0's front (-gimp_level2_follow crack0_front) instead of a
    # fixed finest box over the whole path (4 .. 24 mm): the same increments at the same checks
    # and places, K_I within 1 % of the covering box's at each (the target issue 37 sets a
    # following box in 2D), fewer particles; each move keeps mass and momentum to round-off.
    # With -gimp_follow_merge false the moves keep the energy exactly too.
    # With the release the box moves while an advance is still opening: the bonds follow the
    # regrid (the same increments at the same places as the covering box's).
    for extra, tag, merges in (([], "", ("true", "false")), (release, "_release", ("true",))):
        cover = gimptest.summary(gimptest.run(
            args, "options/through_crack3d.opts",
            grow + extra + ["-gimp_level2_box", "0.004,0.034,0,0.024,0.046,0.004"],
            outdir=os.path.join(args.work, "cover" + tag)))
        gc = cover["cracks"][0]["growth"]
        for merge in merges:
            fol = gimptest.summary(gimptest.run(
                args, "options/through_crack3d.opts",
                grow + extra + ["-gimp_level2_follow", "crack0_front", "-gimp_follow_merge", merge],
                outdir=os.path.join(args.work, "follow_" + merge + tag)))
            gf, moves = fol["cracks"][0]["growth"], fol["measures"]["regrids"]
            same = len(gf) == len(gc) and all(a["t"] == b["t"] and a["x"] == b["x"]
                                              for a, b in zip(gc, gf))
            dK = max(abs(b["KI"] / a["KI"] - 1) for a, b in zip(gc, gf)) if same else 1.0
            dm = max(abs(r["after"]["mass"] / r["before"]["mass"] - 1) for r in moves) \
                if moves else 1
            dp = max(max(abs(u - v) for u, v in zip(r["after"]["momentum"],
                                                    r["before"]["momentum"]))
                     / math.sqrt(2 * r["before"]["mass"] * r["before"]["energy"])
                     for r in moves) if moves else 1
            de = max(abs(r["after"]["energy"] / r["before"]["energy"] - 1) for r in moves) \
                if moves else 1
            n_f, n_c = fol["particles"], cover["particles"]
            c.check("following box (merge %s)%s" % (merge, " with a release" if extra else ""),
                    same and dK <= 0.01 and moves and dm <= 1e-14 and dp <= 1e-12 and
                    (de <= 1e-12 if merge == "false" else True),
                    "%d moves; increments %s as the covering box's, K_I within %.2f %% (tol 1 %%);"
                    " %d particles against %d; a move changes mass by %.1e, momentum by %.1e of "
                    "sqrt(2 m E), energy by %.1e" % (len(moves), "the same" if same else "NOT",
                                                     100 * dK, n_f, n_c, dm, dp, de))
    # The same slab under in-plane shear (mode II): the first point to grow would kink by 70
    # degrees, out of the crack's plane, so the crack stops there, with one line, not grown.
    shear = gimptest.run(args, "options/through_crack3d.opts",
                         grow[:3] + ["0.01"] + grow[4:] +
                         ["-gimp_tractions", "4", "-gimp_traction0_side", "top",
                          "-gimp_traction1_side", "bottom", "-gimp_traction2_side", "right",
                          "-gimp_traction3_side", "left", "-gimp_traction0_value", "1e6,0,0",
                          "-gimp_traction1_value", "-1e6,0,0", "-gimp_traction2_value",
                          "0,1e6,0", "-gimp_traction3_value", "0,-1e6,0"],
                         outdir=os.path.join(args.work, "shear"), expect_ok=False)
    lines = [l for l in (shear.stdout + shear.stderr).splitlines() if "stops growing" in l]
    n = len(gimptest.summary(os.path.join(args.work, "shear"))["cracks"][0]["growth"])
    c.check("mode II stops growth in the plane", shear.returncode == 0 and len(lines) == 1 and
            "would kink by 70.5" in lines[0] and n == 0,
            "%d increments; %s" % (n, lines[0] if lines else "no stop line"))
    c.done()
    sys.exit(0)

# Each advance opens over 2 us, two growth checks (-gimp_crack_growth_release; the scene without
# it is a regression reference): the 2-rank run and the restart, taken at a check while two
# advances are still opening, carry the bonds too.
RELEASE = ["-gimp_crack_growth_release", "2e-6"]
SCENE = ("options/penny_growth3d.opts", ["-ts_max_steps", "150"] + RELEASE)
GROWTH_STEP, LENGTH = 5e-4, 2e-3
# (its checkpoint of step 100 is the restart's below: output only, the run is the same)
if mine.part == "ranks":
    one = os.path.abspath(mine.one or os.path.join(args.work, "np1"))
    if not os.path.exists(os.path.join(one, "summary.json")):
        sys.exit("check_growth3d.py --part ranks: no 1-rank run in %s (run --part one first)" % one)
else:
    one = run_with_dump(args, SCENE, "np1", ["-gimp_checkpoint_interval", "100"])
s1 = gimptest.summary(one)
crack = s1["cracks"][0]
records, front = crack["growth"], crack["front"]
checks = sorted({g["t"] for g in records})
h = gimptest.history(one)
adv_mean, adv_max = h["crack0_advance_mean"][-1], h["crack0_advance_max"][-1]


def check_one(one):
    """The 1-rank run: the front grows, in its plane, ahead of the crack, symmetric."""
    c.check("the front grows", len(checks) >= 3 and adv_mean > 0 and
            LENGTH - GROWTH_STEP <= adv_max <= 1.01 * LENGTH,
            "%d growth checks advanced it (%d increments); advanced %.3f mm on average, %.3f mm at "
            "most (growth length %.1f mm)" % (len(checks), len(records), 1e3 * adv_mean,
                                             1e3 * adv_max, 1e3 * LENGTH))
    c.check("in the crack's plane", all(abs(g["x"][2]) < 1e-12 for g in records) and
            all(abs(f["x"][2]) < 1e-12 for f in front),
            "largest |z| of the increments %.1e" % max(abs(g["x"][2]) for g in records))
    # Each increment is one growth step ahead of the front as it was: its radius grows by at most
    # a step and at least the step's projection on the radius (a polygon's pieces advance along
    # their own normals).
    r_prev = {}
    ok = True
    for t in checks:
        for g in (g for g in records if g["t"] == t):
            r = math.hypot(g["x"][0], g["x"][1])
            ok = ok and 5e-3 + GROWTH_STEP * 0.9 <= r <= 5e-3 + LENGTH * 1.01
    c.check("increments ahead of the crack", ok, "every record beyond the initial radius by 0.45 "
            "mm and within the growth length")
    sym = max(mirrored(front, "x"), max(mirrored([g for g in records if g["t"] == t], "x")
                                         for t in checks))
    c.check("symmetric about x = y", sym <= 1e-9,
            "front points and each check's increments mirrored within %.1e m" % sym)


def check_ranks(one):
    """2 ranks split at the crack's plane give the 1-rank run."""
    two = run_with_dump(args, SCENE, "np2", ["-da_processors_x", "1", "-da_processors_y", "1",
                                             "-da_processors_z", "2", "-gimp_balance", "false"], 2)
    s2 = gimptest.summary(two)
    rec2, front2 = s2["cracks"][0]["growth"], s2["cracks"][0]["front"]
    same_path = len(rec2) == len(records) and all(
        p["t"] == q["t"] and p["point"] == q["point"] and
        max(abs(u - v) for u, v in zip(p["x"], q["x"])) <= 1e-15 for p, q in zip(records, rec2))
    scale = max(abs(f["G"]) for f in front)
    dG = max(abs(p["G"] - q["G"]) / scale for p, q in zip(front, front2)) if front2 else 1.0
    a = compare3d.read_dump(os.path.join(one, "particles.csv"))[1]
    b = compare3d.read_dump(os.path.join(two, "particles.csv"))[1]
    dd, group = compare3d.dump_diff(a, b)
    c.check("2 ranks = 1 rank", same_path and len(front2) == len(front) and dG <= 1e-10 and
            dd <= 1e-10,
            "%d increments %s; front G within %.1e; particles within %.1e of their group's scale "
            "(%s)" % (len(rec2), "the same" if same_path else "DIFFER", dG, dd, group))


def check_restart(one):
    """A restart from the 1-rank run's checkpoint of step 100 gives its answer bit for bit."""
    ckpt = os.path.join(args.work, "step100.h5")
    shutil.copy(os.path.join(one, "checkpoint.h5"), ckpt)
    t100 = h["time"][h["step"].index(100)]
    grown = [g for g in records if g["t"] <= t100]
    opening = {g["t"] for g in grown if t100 - g["t"] < 2e-6}
    c.check("checkpoint after growth, advances opening", len(grown) > 0 and len(opening) >= 2,
            "%d increments before step 100, of %d checks still opening" % (len(grown), len(opening)))
    fresh = run_with_dump(args, SCENE, "fresh", ["-gimp_restart", ckpt])
    same_bits(c, "restart after growth", one, fresh, False)


if mine.part != "ranks":
    check_one(one)
if mine.part != "one":
    check_ranks(one)
if mine.part != "ranks":
    check_restart(one)
c.done()

