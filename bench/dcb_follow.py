#!/usr/bin/env python3
"""Crack growth in the DCB with a fine box that follows the tip, against a fixed fine box over
the whole path and a uniform fine grid (docs/performance.md, *A fine box that follows the tip*).

The scene is options/dcb_growth.opts (2 mm cells, 1 mm cells in a 16 x 16 mm box that follows
the tip with a margin of 4 mm). The grids:
  - follow:       the scene as it is (the parts a moved box leaves merge back);
  - follow, keep: the same with -gimp_follow_merge false (the parts are kept);
  - fixed:        a fixed 1 mm box from x = 40 to 84 mm, y = 2 to 22 mm, that holds the whole 22 mm
                  of growth with its J domains;
  - uniform:      1 mm cells everywhere (the level-1 box over the whole beam).
With --scene dcb_growth3 (options/dcb_growth3.opts: a third level, 0.5 mm cells in an 8 x 8 mm box
that follows the tip inside the 1 mm box; XPIC, and the opening rising half as fast) the grids are
the same three levels following, kept,
fixed (1 mm from x = 40 to 84 mm, y = 2 to 22 mm; 0.5 mm from x = 44 to 78 mm, y = 6 to 18 mm,
which holds the tip's 5 mm J domain all along the path) and uniform 0.5 mm.
Each run is timed (summary.json: cpu_seconds, wall_seconds) with its particle count at the end,
and its P(a) (the load at which a crack of length a starts to grow, as tests/check_dcb_growth.py
reads it) is compared with corrected beam theory and with the uniform grid's, and its tip path
with the uniform grid's. One run at a time, on one rank; the machine line is printed first.

    /usr/bin/python3 bench/dcb_follow.py [--scene dcb_growth|dcb_growth3] [--transfer pic|xpic|apic]
                                         [--gimp build/gimp] [--work /tmp/dcb_follow] [--reuse]

--transfer runs every grid with that transfer instead of the scene's (dcb_growth: PIC, that is
-gimp_transfer flip -gimp_flip 0; dcb_growth3: XPIC). It writes docs/img/dcb_follow.png
(dcb_follow3.png with dcb_growth3, a suffix _pic, _xpic or _apic with --transfer: P(a) of each
grid against corrected beam theory).
"""
import argparse
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))
import gimptest  # noqa: E402
from check_dcb_growth import SCENES, beam, growth_points  # noqa: E402

# Per scene its grids, each (options, whether the boxes follow the tip: the fixed grids drop the
# scene's follow options); the scene's finest cell is the check's (check_dcb_growth.SCENES).
BEAM = "0,0,0.1,0.024"
GRIDS = {
    "dcb_growth": {
        "follow": ([], True),
        "keep": (["-gimp_follow_merge", "false"], True),
        "fixed": (["-gimp_level1_box", "0.040,0.002,0.084,0.022"], False),
        "uniform": (["-gimp_level1_box", BEAM], False),
    },
    "dcb_growth3": {
        "follow": ([], True),
        "keep": (["-gimp_follow_merge", "false"], True),
        "fixed": (["-gimp_level1_box", "0.040,0.002,0.084,0.022",
                   "-gimp_level2_box", "0.044,0.006,0.078,0.018"], False),
        "uniform": (["-gimp_level1_box", BEAM, "-gimp_level2_box", BEAM], False),
    },
}


def scene_file(work, scene, follows, transfer):
    """The scene, or a copy without its follow options (fixed grids) and with another transfer
    than its own (in place of its -gimp_transfer and -gimp_flip lines: -gimp_transfer TRANSFER,
    or for pic -gimp_transfer flip -gimp_flip 0)."""
    src = os.path.join(ROOT, "options", scene + ".opts")
    if follows and not transfer:
        return src
    os.makedirs(work, exist_ok=True)
    dst = os.path.join(work, scene + ("" if follows else "_fixed") + ".opts")
    with open(src) as f, open(dst, "w") as g:
        for l in f:
            if not follows and l.startswith("-gimp_level") and "_follow" in l:
                continue
            if transfer and l.split()[:1] in (["-gimp_transfer"], ["-gimp_flip"]):
                continue
            g.write(l)
        if transfer == "pic":
            g.write("-gimp_transfer flip\n-gimp_flip 0\n")
        elif transfer:
            g.write("-gimp_transfer %s\n" % transfer)
    return dst


def plot(res, path):
    """P(a) / P_CBT(a) - 1 of every grid against a, its CPU time in the legend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for name, (s, pts) in res.items():
        a = [1e3 * x for _, x, _, _ in pts[1:]]
        e = [100 * (P / beam(x) - 1) for _, x, _, P in pts[1:]]
        ax.plot(a, e, "o-", ms=3, label="%s: %d particles at the end, %.0f s CPU" %
                (name, s["particles"], s["cpu_seconds"]))
    ax.set_xlabel("crack length a [mm]")
    ax.set_ylabel("P / P_CBT - 1 [%]")
    ax.set_title("DCB growth: load at each increment against corrected beam theory")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="dcb_growth", choices=sorted(GRIDS))
    ap.add_argument("--transfer", choices=["pic", "apic", "xpic"],
                    help="every grid with this transfer instead of the scene's")
    ap.add_argument("--gimp", default=os.path.join(ROOT, "build", "gimp"))
    ap.add_argument("--work", help="default /tmp/dcb_follow, /tmp/dcb_follow3 with dcb_growth3, "
                    "a suffix _pic, _xpic or _apic with --transfer")
    ap.add_argument("--plot", help="default docs/img/dcb_follow.png, with the --work suffixes")
    ap.add_argument("--reuse", action="store_true",
                    help="read the runs already in --work instead of running them")
    a = ap.parse_args()
    tag = ("" if a.scene == "dcb_growth" else a.scene[len("dcb_growth"):]) + \
        ("_" + a.transfer if a.transfer else "")
    a.work = a.work or "/tmp/dcb_follow" + tag
    a.plot = a.plot or os.path.join(ROOT, "docs", "img", "dcb_follow%s.png" % tag)
    cell, grids = SCENES[a.scene][0], GRIDS[a.scene]
    subprocess.run(["bash", os.path.join(ROOT, "bench", "machine.sh")])
    res = {}
    for name, (extra, follows) in grids.items():
        out = os.path.join(a.work, name)
        cmd = [a.gimp, "-options_file", scene_file(a.work, a.scene, follows, a.transfer),
               "-gimp_output_dir", out] + extra
        p = subprocess.run(cmd, capture_output=True, text=True) if not a.reuse else None
        if p is not None and p.returncode != 0:
            sys.stdout.write(p.stdout + p.stderr)
            raise SystemExit("gimp failed: " + " ".join(cmd))
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        res[name] = (s, growth_points(gimptest.history(out)))
    ref = {round(x * 1e4): (P, y) for _, x, y, P in res["uniform"][1]}
    print("%-8s %9s %9s %10s %8s %12s %14s %14s" % (
        "grid", "particles", "moves", "cpu [s]", "speed-up", "P/CBT-1", "P/uniform-1",
        "path [cells]"))
    for name, (s, pts) in res.items():
        grown = pts[1:]
        cbt = [P / beam(x) - 1 for _, x, _, P in grown]
        vs = [P / ref[round(x * 1e4)][0] - 1 for _, x, _, P in grown if round(x * 1e4) in ref]
        path = max(abs(y - ref[round(x * 1e4)][1]) for _, x, y, _ in grown if round(x * 1e4) in ref)
        moves = len(s["measures"].get("regrids", []))
        print("%-8s %9d %9d %10.1f %8.2f %+5.2f..%+5.2f%% %+5.2f..%+5.2f%% %14.2g" % (
            name, s["particles"], moves, s["cpu_seconds"],
            res["uniform"][0]["cpu_seconds"] / s["cpu_seconds"], 100 * min(cbt), 100 * max(cbt),
            100 * min(vs), 100 * max(vs), path / cell))
    plot(res, a.plot)
    print("P from %.0f to %.0f mm of crack (%d points); path: the largest |y - y_uniform| at the "
          "same a, in finest cells (%g mm)" % (1e3 * res["uniform"][1][1][1],
                                              1e3 * res["uniform"][1][-1][1],
                                              len(res["uniform"][1]) - 1, 1e3 * cell))


if __name__ == "__main__":
    main()
