#!/usr/bin/python3
"""Dispersion on one level: the phase speed of longitudinal standing waves against the number
of cells per wavelength (docs/validation.md "Dispersion", docs/img/dispersion.png).

Usage: /usr/bin/python3 runs/study_dispersion.py --gimp build/gimp --root . --work WORK
       [--extra '-gimp_transfer flip'] [--tag NAME]

A strip [0, 1] x [0, h] (E = 1e4 Pa, rho = 1, nu = 0: c0 = 100 m/s; h = 1/40; 2 x 2 particles
per cell; rollers on y = 0 and y = h, fixed nodes on x = 0 and x = 1) starts with the velocity
1e-3 sin(k x), k = n pi, the n-th fixed-fixed mode: 80 / n cells per wavelength, n = 2 ... 26.
Its kinetic energy oscillates as cos^2(omega t); omega comes from the zero crossings of the
kinetic energy minus its mean over three periods, and the phase speed is omega / k. The lumped-
mass chain's phase speed on the same grid is c0 sin(k h / 2) / (k h / 2); GIMP with one particle
size fixed filters the stiffness further. Writes WORK/dispersion<tag>.csv and the plot (with
--plot CSV,... to combine runs of several transfers)."""
import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import gimptest  # noqa: E402

C0, N = 100.0, 40
H = 1.0 / N


def frequency(t, ke):
    """omega from the zero crossings of ke - mean(ke): they are pi / (2 omega) apart."""
    m = sum(ke) / len(ke)
    z = []
    for i in range(1, len(ke)):
        a, b = ke[i - 1] - m, ke[i] - m
        if a == 0 or a * b < 0:
            z.append(t[i - 1] + (t[i] - t[i - 1]) * a / (a - b))
    if len(z) < 3:
        return float("nan")
    return math.pi / 2 / ((z[-1] - z[0]) / (len(z) - 1))


def run(args, n):
    k = n * math.pi
    dt = 0.1 * H / C0
    steps = int(math.ceil(3 * 2 * math.pi / (C0 * k) / dt))
    opts = os.path.join(args.work, "strip.opts")
    with open(opts, "w") as f:
        f.write("\n".join([
            "-gimp_scene dispersion", "-gimp_E 1e4", "-gimp_nu 0", "-gimp_rho 1",
            "-gimp_h %r" % H, "-gimp_bodies 1", "-gimp_body0_box 0,0,1,%r" % H,
            "-gimp_body0_ppc 4", "-gimp_bcs 4", "-gimp_bc0_y 0", "-gimp_bc0_type roller",
            "-gimp_bc1_y %r" % H, "-gimp_bc1_type roller", "-gimp_bc2_x 0", "-gimp_bc3_x 1",
            "-gimp_history_interval 1", "-gimp_output_interval 0"]) + "\n")
    out = gimptest.run(args, opts, ["-gimp_body0_velocity", "1e-3,0",
                                    "-gimp_body0_velocity_profile", "sine_x",
                                    "-gimp_body0_wavenumber", repr(k), "-ts_dt", repr(dt),
                                    "-ts_max_steps", str(steps)],
                       outdir=os.path.join(args.work, "n%d" % n))
    hist = gimptest.history(out)
    w = frequency(hist["time"], hist["kinetic"])
    kh = k * H
    return {"n": n, "cells_per_wavelength": 2 * N / n, "kh": kh, "c_over_c0": w / k / C0,
            "chain": math.sin(kh / 2) / (kh / 2),
            "energy_end_over_start": (hist["kinetic"][-1] + hist["strain"][-1]) /
            (hist["kinetic"][0] + hist["strain"][0])}


def plot(root, paths):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    xs = [3 + 0.05 * i for i in range(760)]
    ax.plot(xs, [math.sin(math.pi / x) / (math.pi / x) for x in xs], "k-",
            label="lumped-mass chain")
    for p in paths:
        rows = gimptest.read_csv(p)
        ax.plot(rows["cells_per_wavelength"], rows["c_over_c0"], "o-", ms=4,
                label=os.path.basename(p)[len("dispersion"):-4].strip("_") or "gimp")
    ax.set_xscale("log")
    ax.set_xlabel("cells per wavelength")
    ax.set_ylabel("phase speed / c0")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(root, "docs", "img", "dispersion.png"), dpi=110)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gimp")
    ap.add_argument("--root", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--extra", default="")
    ap.add_argument("--tag", default="")
    ap.add_argument("--plot", default="", help="CSV files to plot together (no runs)")
    args = ap.parse_args()
    args.root, args.work = os.path.abspath(args.root), os.path.abspath(args.work)
    os.makedirs(args.work, exist_ok=True)
    if args.plot:
        plot(args.root, args.plot.split(","))
        return
    args.gimp = os.path.abspath(args.gimp)
    rows = [run(args, n) for n in (2, 4, 8, 10, 12, 16, 20, 24, 26)]
    path = os.path.join(args.work, "dispersion%s.csv" % (("_" + args.tag) if args.tag else ""))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("| cells per wavelength | k h | c / c0 | chain | energy after three periods |")
    print("| --- | --- | --- | --- | --- |")
    for r in rows:
        print("| %.2f | %.3f | %.4f | %.4f | %.3f |" % (r["cells_per_wavelength"], r["kh"],
                                                       r["c_over_c0"], r["chain"],
                                                       r["energy_end_over_start"]))
    print("wrote " + path)


if __name__ == "__main__":
    main()
