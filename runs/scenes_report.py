#!/usr/bin/python3
"""Tables and figures of docs/scenes.md from the runs made by runs/scenes_report.sh.

Usage: scenes_report.py RUNDIR IMGDIR
RUNDIR holds one output directory per run (ind_a, ind_b, ind_c at 20 ns; ind_a50, ind_b50,
ind_c50, ind_d at 50 ns; plate_u1, plate_u05, plate_u025, plate_ml; slab_h1, slab_h05,
slab_h025). Missing runs are skipped. Tables are printed as Markdown on stdout.
"""
import csv
import json
import math
import os
import sys

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection
import numpy as np

RUN, IMG = sys.argv[1], sys.argv[2]
os.makedirs(IMG, exist_ok=True)


def path(*p):
    return os.path.join(RUN, *p)


def have(name):
    return os.path.isfile(path(name, "summary.json"))


def summary(name):
    with open(path(name, "summary.json")) as f:
        return json.load(f)


def history(name):
    with open(path(name, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def last_frame(name):
    f = h5py.File(path(name, "fields.h5"), "r")
    g = f["particles"]
    key = sorted(g.keys())[-1]
    d = {k: g[key][k][()] for k in g[key]}
    d["step"] = int(key.split("_")[1])
    f.close()
    return d


# ---------------------------------------------------------------- indentation
def indentation():
    names = [n for n in ("ind_a", "ind_b", "ind_c") if have(n)]
    if not names:
        return
    frames = {n: last_frame(n) for n in names}
    sums = {n: summary(n) for n in names}
    print("### Indentation at 20 ns\n")
    print("| run | grid | dt [ps] | steps | t [ns] | particles | wall [s] | probe u_y [um] |")
    print("|---|---|---|---|---|---|---|---|")
    grids = {"ind_a": "uniform 1 um", "ind_b": "2 levels 2/1 um", "ind_c": "3 levels 4/2/1 um"}
    for n in names:
        s = sums[n]
        print(f"| {n[-1]} | {grids[n]} | {s['dt']*1e12:.0f} | {s['steps']} | {s['time']*1e9:.1f} | "
              f"{s['particles']} | {s['wall_seconds']:.1f} | {s['probes']['top']['u'][1]*1e6:.4f} |")
    print()
    # sigma_yy on common particles (same initial position within 1e-9 m)
    ref = frames[names[0]]
    key = {tuple(np.rint(x * 1e9).astype(int)): i for i, x in enumerate(ref["X0"])}
    print("sigma_yy on particles common with (a) (initial positions within 1e-9 m), "
          "relative to the 60 GPa load:\n")
    print("| pair | common particles | max abs diff [GPa] | max / 60 GPa | RMS diff [GPa] | RMS / 60 GPa |")
    print("|---|---|---|---|---|---|")
    def compare(n1, n2, label):
        r1, r2 = last_frame(n1), last_frame(n2)
        k1 = {tuple(np.rint(x * 1e9).astype(int)): i for i, x in enumerate(r1["X0"])}
        ia, ib = [], []
        for j, x in enumerate(r2["X0"]):
            i = k1.get(tuple(np.rint(x * 1e9).astype(int)))
            if i is not None and np.max(np.abs(r1["X0"][i] - x)) < 1e-9:
                ia.append(i)
                ib.append(j)
        d = r2["stress"][ib, 3] - r1["stress"][ia, 3]  # syy: stress is row-major xx, xy, yx, yy
        mx, rms = np.max(np.abs(d)), math.sqrt(np.mean(d * d))
        print(f"| {label} | {len(ia)} | {mx/1e9:.3f} | {mx/60e9:.4f} | {rms/1e9:.3f} | {rms/60e9:.4f} |")

    for n1, n2, lab in (("ind_a", "ind_b", "a vs b"), ("ind_a", "ind_c", "a vs c"),
                        ("ind_b", "ind_c", "b vs c"),
                        ("ind_a", "ind_bx", "a vs b' (fine box from x = -2 um)"),
                        ("ind_a", "ind_cx", "a vs c' (boxes from x = -4 / -2 um)")):
        if have(n1) and have(n2):
            compare(n1, n2, lab)
    print()

    # Fig. 10: probe displacement history
    fig, ax = plt.subplots(figsize=(6, 4))
    for n, st in (("ind_a50", "-"), ("ind_b50", "--"), ("ind_c50", ":"), ("ind_d", "-."),
                  ("ind_cx50", "-")):
        if have(n):
            h = history(n)
            ax.plot(h["time"] * 1e9, h["top_uy"] * 1e6, st, label={"ind_a50": "(a) uniform 1 um",
                    "ind_b50": "(b) 2 levels", "ind_c50": "(c) 3 levels",
                    "ind_d": "(d) 3 levels, no tracking",
                    "ind_cx50": "(c') 3 levels, boxes past x = 0"}[n], **({"lw": 0.8, "color": "k"} if n == "ind_cx50" else {}))
    if not any(have(n) for n in ("ind_a50", "ind_b50", "ind_c50")):
        for n, st in zip(names, ("-", "--", ":")):
            h = history(n)
            ax.plot(h["time"] * 1e9, h["top_uy"] * 1e6, st, label=n)
    ax.axvline(20, color="0.7", lw=0.8)
    ax.set_xlabel("t [ns]")
    ax.set_ylabel("probe u_y [um]")
    ax.set_title("Indentation: top particle on the symmetry line (cf. paper Fig. 10)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "indentation_probe_history.png"), dpi=120)
    plt.close(fig)

    # Fig. 9: sigma_yy maps with tracked particle outlines
    def polys(fr):
        if "corners" in fr:
            return fr["corners"].reshape(-1, 4, 2) * 1e6
        x, l = fr["x"], fr["l"]  # l is the half-size (GIMP semi-length)
        sx = np.array([-1, 1, 1, -1])
        sy = np.array([-1, -1, 1, 1])
        return np.stack([x[:, None, 0] + sx * l[:, None, 0], x[:, None, 1] + sy * l[:, None, 1]],
                        axis=2) * 1e6

    def maps(runs, titles, fname, suptitle, xl=(-1, 29), yl=(-1, 42)):
        fig, axs = plt.subplots(1, len(runs), figsize=(4.2 * len(runs), 5.2), squeeze=False)
        vmin, vmax = -40, 10
        for ax, n, t in zip(axs[0], runs, titles):
            fr = last_frame(n)
            pc = PolyCollection(polys(fr), array=fr["stress"][:, 3] / 1e9, cmap="jet",
                                edgecolors="k", linewidths=0.1)
            pc.set_clim(vmin, vmax)
            ax.add_collection(pc)
            ax.set_xlim(*xl)
            ax.set_ylim(*yl)
            ax.set_aspect("equal")
            s = summary(n)
            ax.set_title(f"{t}, t = {s['time']*1e9:.0f} ns", fontsize=9)
            ax.set_xlabel("x [um]")
        axs[0][0].set_ylabel("y [um]")
        fig.colorbar(pc, ax=axs[0].tolist(), label="sigma_yy [GPa]", shrink=0.8)
        fig.suptitle(suptitle, fontsize=10)
        fig.savefig(os.path.join(IMG, fname), dpi=130)
        plt.close(fig)

    maps(names, [grids[n] for n in names], "indentation_syy_20ns.png",
         "Indentation, sigma_yy, particles as tracked quadrilaterals (cf. paper Fig. 9)")
    maps(names, [grids[n] for n in names], "indentation_syy_20ns_zoom.png",
         "Indentation, sigma_yy near the load, 20 ns", xl=(-0.5, 10), yl=(30, 40.5))
    if have("ind_c50") and have("ind_d"):
        maps(["ind_c50", "ind_d"], ["(c) tracked corners", "(d) no tracking"],
             "indentation_syy_50ns_cd.png", "Indentation at 50 ns, with and without particle tracking")
        print("### Indentation to 50 ns, tracking (c) vs none (d)\n")
        print("| run | tracking | separation_strain | max_separation | max_strain | probe u_y [um] | wall [s] |")
        print("|---|---|---|---|---|---|---|")
        for n, tr in (("ind_c50", "corners"), ("ind_d", "none")):
            s = summary(n)
            m = s["measures"]
            ss = "never" if m["separation_strain"] is None else f"{m['separation_strain']:.4g}"
            print(f"| {n.replace('ind_', '').replace('50', '')} | {tr} | {ss} | {m['max_separation']:.3g} | "
                  f"{m['max_strain']:.4g} | {s['probes']['top']['u'][1]*1e6:.4f} | {s['wall_seconds']:.1f} |")
        h = history("ind_d")
        thr = 0.05
        idx = np.nonzero(h["separation"] > thr)[0]
        if len(idx):
            print(f"\nIn (d) the history column `separation` first exceeds {thr} at t = "
                  f"{h['time'][idx[0]]*1e9:.1f} ns.")
        print()


# ---------------------------------------------------------------- speed vs error
def speed_error(runs, labels, qty, exact_fn, title, fname, ylabel):
    rows = []
    for n, lab in zip(runs, labels):
        if have(n):
            s = summary(n)
            rows.append((n, lab, s, qty(s)))
    return rows


def richardson(h, v):
    """Three values on h, h/2, h/4: observed order and extrapolated value."""
    if any(x is None for x in v):
        return None, None
    d1, d2 = v[0] - v[1], v[1] - v[2]
    if d1 * d2 <= 0 or abs(d2) == 0:
        return None, None
    p = math.log(d1 / d2) / math.log(2)
    return p, v[2] - d2 / (2 ** p - 1)


def loglog_interp(w, e, e0):
    """Wall time at error e0 on the uniform series (log-log linear interpolation)."""
    lw, le = np.log(w), np.log(e)
    order = np.argsort(le)
    return float(np.exp(np.interp(math.log(e0), le[order], lw[order])))


def plate():
    uni = [("plate_u1", 1.0), ("plate_u05", 0.5), ("plate_u025", 0.25)]
    if not all(have(n) for n, _ in uni):
        return
    S = {n: summary(n) for n, _ in uni}
    kt = [S[n]["measures"]["kt"] for n, _ in uni]
    kte = [S[n]["measures"]["kt_edge"] for n, _ in uni]
    p, kinf = richardson([1, .5, .25], kt)
    pe, ktinf_edge = richardson([1, .5, .25], kte)
    # Kirsch at the probe particle radius (from hoop.csv: 90 deg row nearest to the edge)
    print("### Plate with a hole: static kt (damping 3e5 1/s, 20000 steps of 10 ns)\n")
    ml = "plate_ml" if have("plate_ml") else None
    runs = uni + ([(ml, None)] if ml else [])
    print("| grid | particles | wall [s] | final kinetic / strain energy | kt | kt_edge | "
          "Kirsch at probe r (x finite-width) | err vs Richardson kt | err vs Kirsch(r) |")
    print("|---|---|---|---|---|---|---|---|---|")
    # Heywood finite-width factor: net-section Kt 2 + (1 - d/W)^3, gross = net / (1 - d/W); / 3
    fw = (2 + (1 - 4 / 60) ** 3) / (1 - 4 / 60) / 3.0
    out = []
    for n, h in runs:
        s = summary(n)
        k = s["measures"]["kt"]
        # radius of the probe particle: the 90-degree row of hoop.csv closest to the edge
        with open(path(n, "hoop.csv")) as f:
            hr = [r for r in csv.DictReader(f)]
        # the probe particle is the hoop.csv row nearest to 90 degrees (its hoop_over_p is kt);
        # its kirsch column is the infinite-plate value at its own radius and angle
        row = min(hr, key=lambda r: abs(float(r["angle_deg"]) - 90))
        r0, kir = float(row["r"]), float(row["kirsch"])
        kirw = kir * fw
        e_r = abs(k - kinf) / kinf
        e_k = abs(k - kirw) / kirw
        g = "uniform %.2f mm" % h if h else "3 levels 1.0/0.5/0.25 mm"
        en = s["energy"]
        print(f"| {g} | {s['particles']} | {s['wall_seconds']:.1f} | {en['kinetic']/max(en['strain'],1e-300):.1e} | "
              f"{k:.4f} | {s['measures']['kt_edge'] if s['measures']['kt_edge'] is None else round(s['measures']['kt_edge'], 4)} | {kirw:.4f} (r = {r0*1e3:.3f} mm, {float(row['angle_deg']):.1f} deg) | "
              f"{e_r*100:.2f} % | {e_k*100:.2f} % |")
        out.append((g, s["wall_seconds"], e_r, e_k, h))
    print(f"\nRichardson on the uniform kt series (1, 0.5, 0.25 mm): observed order p = "
          f"{p if p is None else round(p, 2)}, extrapolated kt = {kinf if kinf is None else round(kinf, 4)}"
          f"; on kt_edge: p = {pe if pe is None else round(pe, 2)}, extrapolated "
          f"{ktinf_edge if ktinf_edge is None else round(ktinf_edge, 4)}. "
          f"Finite-width factor (Heywood, d/W = 1/15) {fw:.4f}.\n")
    fig, ax = plt.subplots(figsize=(5.5, 4))
    wu = np.array([o[1] for o in out if o[4]])
    eu = np.array([o[2] for o in out if o[4]])
    ax.loglog(wu, eu, "o-", label="uniform 1.0 / 0.5 / 0.25 mm, vs Richardson")
    ax.loglog(wu, [o[3] for o in out if o[4]], "o--", mfc="none", color="C0", lw=0.8,
              label="uniform, vs Kirsch at probe r (x finite width)")
    for o in out:
        if o[4]:
            ax.annotate(f"{o[4]} mm", (o[1], o[2]), textcoords="offset points", xytext=(5, 5), fontsize=8)
    if ml:
        o = out[-1]
        ax.loglog([o[1]], [o[2]], "s", color="C3", ms=8, label="3 levels 1.0/0.5/0.25 mm, vs Richardson")
        ax.loglog([o[1]], [o[3]], "s", color="C3", mfc="none", ms=8, label="3 levels, vs Kirsch at probe r")
        tw = loglog_interp(wu, eu, o[2])
        print(f"Equal error: the uniform series reaches the 3-level error {o[2]*100:.2f} % "
              f"(vs Richardson) at about {tw:.1f} s (log-log interpolation) against "
              f"{o[1]:.1f} s for the 3-level grid, a speed-up of {tw/o[1]:.1f}x; against the "
              f"uniform 0.25 mm run ({out[2][1]:.1f} s, error {out[2][2]*100:.2f} %) "
              f"the ratio of wall times is {out[2][1]/o[1]:.1f}x.")
        ek = np.array([q[3] for q in out if q[4]])
        tk = loglog_interp(wu, ek, o[3])
        print(f"Against Kirsch at the probe radius: the 3-level error is {o[3]*100:.2f} %, reached by "
              f"the uniform series at about {tk:.1f} s, a speed-up of {tk/o[1]:.1f}x.\n")
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("relative error of kt")
    ax.set_title("Plate with a hole: error vs wall time")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "speed_error_plate.png"), dpi=120)
    plt.close(fig)


def slab():
    runs = [("slab_h1", 1.0), ("slab_h05", 0.5), ("slab_h025", 0.25)]
    runs = [(n, h) for n, h in runs if have(n)]
    if not runs:
        return
    exact = 0.5e-3 * 2.625e-3 / 10e-3
    print("### Slab: probe u_x vs delta x / L (0.13125 mm)\n")
    print("| h [mm] | dt [ns] | steps | particles | wall [s] | probe X0 [mm] | u_x [mm] | exact at X0 [mm] | error |")
    print("|---|---|---|---|---|---|---|---|---|")
    pts = []
    for n, h in runs:
        s = summary(n)
        pr = s["probes"]["probe"]
        ex = 0.5e-3 * pr["x0"][0] / 10e-3
        e = abs(pr["u"][0] - ex) / ex
        print(f"| {h} | {s['dt']*1e9:.3g} | {s['steps']} | {s['particles']} | {s['wall_seconds']:.1f} | "
              f"({pr['x0'][0]*1e3:.4g}, {pr['x0'][1]*1e3:.4g}) | {pr['u'][0]*1e3:.5f} | {ex*1e3:.5f} | {e*100:.3f} % |")
        pts.append((s["wall_seconds"], e, h))
    print()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label="uniform")
    for p in pts:
        ax.annotate(f"{p[2]} mm", (p[0], p[1]), textcoords="offset points", xytext=(5, 5), fontsize=8)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("|u_x - delta X/L| / (delta X/L) at the probe")
    ax.set_title("Slab: probe error vs wall time")
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "speed_error_slab.png"), dpi=120)
    plt.close(fig)


indentation()
plate()
slab()
