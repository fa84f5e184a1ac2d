#!/usr/bin/python3
"""Colliding disks (options/disks.opts): kinetic, strain and total energy against time on one
level and with a finer level around the contact zone, and the rebound velocities; the figure
docs/img/disks_energy.png and the table of docs/validation.md, section "Colliding disks".

Usage: /usr/bin/python3 runs/study_disks.py --gimp build/gimp --work WORK [--no-run]
"""
import argparse
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))
import gimptest  # noqa: E402

RUNS = [("one level, h = 0.05", []),
        ("two levels, 0.05 / 0.025 on [0.3, 0.7]^2",
         ["-gimp_levels", "2", "-gimp_level1_box", "0.3,0.3,0.7,0.7"]),
        ("one level, h = 0.025", ["-gimp_h", "0.025"]),
        ("one level, APIC", ["-gimp_transfer", "apic"]),
        ("one level, linear (Jaumann)", ["-gimp_material", "linear"])]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gimp", default=os.path.join(ROOT, "build", "gimp"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "WORK_disks"))
    ap.add_argument("--no-run", action="store_true")
    a = ap.parse_args()
    a.gimp, a.work, a.root, a.extra = os.path.abspath(a.gimp), os.path.abspath(a.work), ROOT, ""
    os.makedirs(a.work, exist_ok=True)
    results = []
    for i, (name, extra) in enumerate(RUNS):
        out, dump = os.path.join(a.work, "run%d" % i), os.path.join(a.work, "run%d.csv" % i)
        if not a.no_run:
            gimptest.run(a, "options/disks.opts", extra + ["-gimp_particle_dump", dump], outdir=out)
        h, s, rows = gimptest.history(out), gimptest.summary(out), gimptest.read_csv(dump)
        e = [k + w for k, w in zip(h["kinetic"], h["strain"])]
        sel = [j for j, (x, y) in enumerate(zip(rows["x"], rows["y"])) if x + y > 1]
        v = sum(rows["V"][j] for j in sel)
        vx = sum(rows["V"][j] * rows["vx"][j] for j in sel) / v
        results.append((name, h, e, s, vx))
    print("| run | particles | steps | wall [s] | max \\|E / E0 - 1\\| | E(end) / E0 - 1 | "
          "rebound velocity of the upper disk (x) [m/s] |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for name, h, e, s, vx in results:
        print("| %s | %d | %d | %.1f | %.4f | %+.4f | %.5f |" % (
            name, s["particles"], s["steps"], s["wall_seconds"],
            max(abs(x / e[0] - 1) for x in e), e[-1] / e[0] - 1, vx))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.2))
    name, h, e, _, _ = results[0]
    axs[0].plot(h["time"], [k / e[0] for k in h["kinetic"]], label="kinetic")
    axs[0].plot(h["time"], [w / e[0] for w in h["strain"]], label="strain")
    axs[0].plot(h["time"], [x / e[0] for x in e], "k", label="total")
    axs[0].set_title("Energies / E0, " + name)
    axs[0].set_xlabel("t [s]")
    axs[0].legend()
    axs[0].grid(alpha=0.3)
    for name, h, e, _, _ in results:
        axs[1].plot(h["time"], [x / e[0] - 1 for x in e], label=name)
    axs[1].set_title("Total energy E / E0 - 1")
    axs[1].set_xlabel("t [s]")
    axs[1].set_ylim(-0.16, 0.03)
    axs[1].legend(fontsize=8)
    axs[1].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "img", "disks_energy.png"), dpi=120)


if __name__ == "__main__":
    main()
