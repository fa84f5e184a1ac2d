#!/usr/bin/env python3
"""Instructions per particle-step of each phase of the step, 2D against 3D (callgrind).

Runs the benchmark blocks under callgrind, counting only the stepping loop (Solver::advance):
bench/block.opts (2D, 65,536 particles, one level), bench/block3d.opts (3D, 110,592 particles,
one level) and bench/block3d_levels.opts (3D, 90,112 particles, three levels), and prints for each
phase the instructions per particle-step and the 3D / 2D ratio, next to the ratio of the work
the phase's formulas ask for (the node values it reads or writes, products counted once):

  P2G          2D 9 nodes x (2 + 1) values, 3D 27 x (3 + 1): 4.0
  force, grad  2D 9 nodes x 2 x 2 products, 3D 27 x 3 x 3: 6.75
  G2P          (APIC: v and B, then the re-projection) 2D 9 x (2 + 4 + 2), 3D 27 x (3 + 9 + 3): 5.6
               (FLIP: v and a, then the re-projection) 2D 9 x (2 + 2 + 2), 3D 27 x (3 + 3 + 3): 4.5
  stress       F += dt L F and the Jaumann rate: 2D 8 + 12, 3D 27 + 36 products: about 3

Usage: bench/kernel_counts.py [--transfer apic|flip] [--steps 4] [--build DIR] [--no-lanes]
Needs valgrind; takes a few minutes. A scene whose run fails under valgrind is reported as not
counted (a build from before lanes::set3, whose 3D lane kernels held an instruction valgrind
cannot decode); --no-lanes runs every scene with -gimp_lanes false (the scalar kernels).
"""
import argparse
import os
import re
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PHASES = [  # (phase, pattern of the function names callgrind reports)
    ("stencils", r"buildStencils|blockRun|blockLanes|appendNodes|appendThreeNodeBlock|forEachIndex"),
    ("P2G", r"particlesToGrid"),
    ("internal force", r"internalForce"),
    ("G2P", r"gridToParticles"),
    ("velocity gradient", r"velocityGradient"),
    ("stress update", r"updateDeformation|jaumannUpdate|updateDomain|neoHookean"),
    ("checks", r"::checks|checkParticles"),
]
WORK = {"P2G": 4.0, "internal force": 6.75, "velocity gradient": 6.75, "G2P": 5.6,
        "stress update": 3.0}
# FLIP's G2P reads v and a and re-projects m v: 2D 9 x (2 + 2 + 2), 3D 27 x (3 + 3 + 3)
WORK_FLIP = dict(WORK, G2P=4.5)
SCENES = [("2D", "block.opts", 2, 65536), ("3D", "block3d.opts", 3, 110592),
          ("3D, 3 levels", "block3d_levels.opts", 3, 90112)]


def count(build, opts, dim, particles, transfer, steps, tmp, lanes):
    """Instructions per particle-step by phase, or None when the run fails under valgrind."""
    out = os.path.join(tmp, opts + ".cg")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    run = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out,
                          "--toggle-collect=gimp::Solver<%d>::advance()" % dim,
                          os.path.join(build, "gimp"), "-options_file",
                          os.path.join(ROOT, "bench", opts), "-ts_max_steps", str(steps),
                          "-gimp_transfer", transfer, "-gimp_lanes", "true" if lanes else "false",
                          "-gimp_output_dir", os.path.join(tmp, opts)],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    if run.returncode != 0:
        return None
    text = subprocess.run(["callgrind_annotate", "--threshold=100", out], check=True,
                          capture_output=True, text=True).stdout
    per = {p: 0.0 for p, _ in PHASES}
    per["other"] = 0.0
    total = 0.0
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)", line)
        if not m:
            continue
        n = float(m.group(1).replace(",", ""))
        if "PROGRAM TOTALS" in m.group(2):
            total = n
            continue
        phase = next((p for p, pat in PHASES if re.search(pat, m.group(2))), "other")
        per[phase] += n
    ps = particles * steps
    per = {k: v / ps for k, v in per.items()}
    per["total"] = total / ps
    return per


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--transfer", default="apic", choices=["apic", "flip"])
    ap.add_argument("--steps", type=int, default=4)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--no-lanes", action="store_true", help="run with -gimp_lanes false")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        res = [count(a.build, o, d, n, a.transfer, a.steps, tmp, not a.no_lanes)
               for _, o, d, n in SCENES]
    print("instructions per particle-step, %s, %d steps (callgrind, Solver::advance)%s"
          % (a.transfer.upper(), a.steps, ", -gimp_lanes false" if a.no_lanes else ""))
    failed = [name for (name, _, _, _), r in zip(SCENES, res) if r is None]
    if failed:
        print("not counted (the run failed under valgrind; see --no-lanes): " + ", ".join(failed))
    if res[0] is None:
        return
    empty = {k: float("nan") for k in res[0]}
    res = [r if r is not None else empty for r in res]
    print("| phase | 2D | 3D | 3D / 2D | work 3D / 2D | 3D, 3 levels |")
    print("| --- | --- | --- | --- | --- | --- |")
    for p in [p for p, _ in PHASES] + ["other", "total"]:
        two, three, lev = res[0][p], res[1][p], res[2][p]
        ratio = "%.1f" % (three / two) if two > 0.5 else "-"
        table = WORK_FLIP if a.transfer == "flip" else WORK
        work = "%.2f" % table[p] if p in table else ""
        print("| %s | %.0f | %.0f | %s | %s | %.0f |" % (p, two, three, ratio, work, lev))


if __name__ == "__main__":
    main()
