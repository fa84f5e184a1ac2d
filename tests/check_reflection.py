"""Wave reflection at the coarse-to-fine and fine-to-coarse interfaces of a refined grid
(options/wave_interface.opts, docs/validation.md "Wave reflection at level interfaces").

A traction on the left end of a strip launches one right-going raised-cosine pulse of width
W = 1 m (wavenumber k = 2 pi / W) through level 1 (ratio 2 unless --ratio) on 4.5 <= x <= 7.
At t = 0.085 s the pulse has crossed both interfaces and no wave has reached an end of the
strip. Each resolution h0 = W / n runs three grids with the same time step:

  uniform  one level of h0 (the scene file without its -gimp_level* lines),
  box      the scene: level 1 on 4.5 <= x <= 7,
  open     level 1 from x = 4.5 to the right end of the domain (no fine-to-coarse interface).

Particles left of an interface are seeded identically in the grids compared, and there the two
runs differ only by what the interface sends back (at h0 = W / 8 and t = 0.03 s, before the
pulse reaches x = 4.5, the difference is exactly zero on x < 2.4). The particle-by-particle
difference of velocity and stress is then the reflected wave alone, without the dispersion
tail of the incident pulse that both runs carry (the strain amplitude, 1e-5, keeps the
response linear). Its kinetic + strain energy, divided by the pulse
energy (kinetic + strain energy of all particles of the box run), is the reflected fraction:

  coarse -> fine: (box - uniform) on x < 4.5,
  fine -> coarse: (box - open) on 4.5 <= x < 7.

The raw energy of the box run on the incoming side and that of the reference run (the
background: the dispersion tail of the incident pulse) are printed too. The script prints a
table with the observed orders in h0, writes it to <work>/reflection.csv and asserts that both
fractions decrease with h0, that their least-squares order is at least 3 (measured: 4, an
amplitude reflection coefficient of order (k h)^2), that they are below 1e-6 at the finest of
the default resolutions (W / 64), and that every run keeps its energy within 1 % of the work
of the traction.

One wavenumber. The amplitude reflection coefficient |R| at 10 and 20 coarse cells per
wavelength is the ratio of the spectra (sum of V vx exp(-i k x) over the particles) of the
reflected wave (the differences above) and of the incident pulse (the whole reference run), at
the resolutions where that k lies within the pulse's main lobe (k < 0.85 * 4 pi / W: W/16 for
both, W/32 for 20 cells). The script computes the lumped-mass 1D chain's |R| for the same jump
(spacing h0, then h0 / ratio; masses rho * spacing, springs E / spacing, the interface node
with half a cell of each side; a plane wave on each side and the interface node's equation)
and asserts gimp's is no larger than 1.02 times it. Measured with APIC (the default): W/16,
10 cells: 1.915e-2 (chain 1.905e-2) coarse->fine, 1.838e-2 (1.956e-2) fine->coarse; 20 cells:
4.661e-3 (4.660e-3), 4.685e-3 (4.689e-3). With FLIP (-gimp_transfer flip) it is 1.6 to 1.9
times the chain's: FLIP's grid-invisible modes carry part of the wave at the interface.

Extra options (besides those of gimptest.parse_args):
  --levels 16,32,64   cells of h0 per pulse width W (the default takes about 11 s on one core)
  --ratio 2           refinement ratio of level 1 (the time step follows the fine cell h0 / r)
  --multirate         every grid with -gimp_multirate true: level 0 steps with ratio x dt (the
                      step count is rounded up to a multiple of the ratio); the same bounds hold
"""
import argparse
import csv
import math
import os
import sys
import time

import gimptest

OPTS = "options/wave_interface.opts"
E, RHO = 1e4, 1.0
C = math.sqrt(E / RHO)  # nu = 0: uniaxial strain, c = 100 m/s
W = 1.0                 # pulse width c * Tp [m]
K = 2.0 * math.pi / W   # wavenumber of the raised cosine [1/m]
L = 10.0                # strip length [m]
XA, XB = 4.5, 7.0       # coarse-to-fine and fine-to-coarse interfaces [m]
T = 0.085               # measurement time [s]
CFL = 0.3               # dt <= CFL * (h0 / r) / c, the same for all three grids
MAX_FINEST = 1e-6       # bound on both fractions at the finest resolution
MIN_ORDER = 3.0
ENERGY_TOL = 1e-2
# |R| at one wavenumber is measured from spectra of finite windows: the same coefficient (20
# coarse cells per wavelength) measured from the W/16 and W/32 runs differs by 0.5 %, so a
# bound 2 % above the chain's allows for the measurement and no more (FLIP's 1.8 x fails it).
CHAIN_TOL = 0.02

pre = argparse.ArgumentParser(add_help=False)
pre.add_argument("--levels", default="16,32,64")
pre.add_argument("--ratio", type=int, default=2)
pre.add_argument("--multirate", action="store_true")
mine, rest = pre.parse_known_args()
sys.argv = sys.argv[:1] + rest
args = gimptest.parse_args()
levels = [int(s) for s in mine.levels.split(",")]
ratio = mine.ratio

# The uniform grid: the scene without its level options.
uniform_opts = os.path.join(args.work, "wave_uniform.opts")
with open(os.path.join(args.root, OPTS)) as f:
    lines = [ln for ln in f if not ln.startswith("-gimp_level")]
with open(uniform_opts, "w") as f:
    f.writelines(lines)


def read_particles(path, h):
    with open(path) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    # Rows of particles (y does not change: rollers), each sorted by x.
    rows.sort(key=lambda r: (round(r["y"] / h * 64), r["x"]))
    return rows


def energy(V, vx, vy, sxx, syy, sxy, szz):
    """Kinetic + strain energy of one particle (linear elastic, the solver's formula)."""
    return (0.5 * RHO * V * (vx * vx + vy * vy) +
            V * ((sxx * sxx + syy * syy + szz * szz) / (2 * E) + sxy * sxy / E))


def particle_energy(r):
    return energy(r["V"], r["vx"], r["vy"], r["sxx"], r["syy"], r["sxy"], r["szz"])


def window(P, lo, hi):
    return [r for r in P if lo <= r["x"] < hi]


def window_energy(P, lo, hi):
    return sum(particle_energy(r) for r in window(P, lo, hi))


def difference_energy(P, Q, lo, hi, h):
    """Energy of the particle-by-particle difference of two runs on lo <= x < hi, and the
    largest position mismatch of the matched particles."""
    a, b = window(P, lo, hi), window(Q, lo, hi)
    if len(a) != len(b):
        raise SystemExit("particle sets differ on [%g, %g): %d and %d" % (lo, hi, len(a), len(b)))
    tot, mis = 0.0, 0.0
    for p, q in zip(a, b):
        mis = max(mis, abs(p["x"] - q["x"]) / h, abs(p["y"] - q["y"]) / h)
        tot += energy(p["V"], p["vx"] - q["vx"], p["vy"] - q["vy"], p["sxx"] - q["sxx"],
                      p["syy"] - q["syy"], p["sxy"] - q["sxy"], p["szz"] - q["szz"])
    return tot, mis


def spectrum(P, k, lo, hi, Q=None):
    """|sum over the particles on lo <= x < hi of V vx exp(-i k x)|: the amplitude of the
    wavenumber k in the velocity field (of the difference P - Q when Q is given)."""
    a = window(P, lo, hi)
    b = window(Q, lo, hi) if Q is not None else [None] * len(a)
    re = im = 0.0
    for p, q in zip(a, b):
        v = p["vx"] - (q["vx"] if q is not None else 0.0)
        re += p["V"] * v * math.cos(k * p["x"])
        im -= p["V"] * v * math.sin(k * p["x"])
    return math.hypot(re, im)


def chain_reflection(kh, r):
    """Amplitude reflection coefficient of a lumped-mass 1D chain (spacing h, then h / r, the
    same material: masses rho * spacing, springs E / spacing, the interface node carrying half
    a cell of each side) for an incident wave of wavenumber k on the side of spacing h (kh = k h;
    r < 1 for a wave from the fine side into the coarse one, spacing h then h / r > h)."""
    hL, hR = 1.0, 1.0 / r  # in units of h (E = rho = 1: c = 1)
    mL, mR, m0 = hL, hR, 0.5 * (hL + hR)
    sL, sR = 1.0 / hL, 1.0 / hR
    w2 = 4 * sL / mL * math.sin(kh / 2) ** 2
    s = math.sqrt(w2 * mR / (4 * sR))
    if s >= 1:
        raise ValueError("the frequency does not propagate on the other side")
    kR = 2 * math.asin(s) / hR
    eL, eR = complex(math.cos(kh * hL), -math.sin(kh * hL)), complex(math.cos(kR * hR),
                                                                     math.sin(kR * hR))
    # u_j = e^{i k x_j} + R e^{-i k x_j} (j <= 0), T e^{i kR x_j} (j >= 0), T = 1 + R;
    # node 0: -w^2 m0 u0 = sL (u_-1 - u0) + sR (u_1 - u0).
    # (1 + R)(-w2 m0 + sL + sR - sR eR) = sL (eL + R / eL)
    a = -w2 * m0 + sL + sR - sR * eR
    R = (sL * eL - a) / (a - sL / eL)
    return abs(R)


def spectral(P, n, res):
    """|R| at 10 and 20 coarse cells per wavelength (within the pulse's main lobe, k < 4 pi / W),
    from the spectra of the reflected and incident waves on the coarse and on the fine side."""
    h = W / n
    for cells in (10, 20):
        k = 2 * math.pi / (cells * h)
        if k >= 0.85 * 4 * math.pi / W:
            continue
        inc_c = spectrum(P["uniform"], k, -1.0, L + 1.0)
        inc_f = spectrum(P["open"], k, -1.0, L + 1.0)
        res["R_c2f_%d" % cells] = spectrum(P["box"], k, -1.0, XA, P["uniform"]) / inc_c
        res["R_f2c_%d" % cells] = spectrum(P["box"], k, XA, XB, P["open"]) / inc_f
        res["chain_c2f_%d" % cells] = chain_reflection(k * h, ratio)
        res["chain_f2c_%d" % cells] = chain_reflection(k * h / ratio, 1.0 / ratio)


def run(n):
    h = W / n
    steps = math.ceil(T / (CFL * h / ratio / C) - 1e-9)
    if mine.multirate:  # T must end a coarse step of `ratio` fine steps
        steps = ratio * math.ceil(steps / ratio)
    dt = T / steps
    common = ["-gimp_h", repr(h), "-ts_dt", repr(dt), "-gimp_body0_box", "0,0,%r,%r" % (L, h),
              "-gimp_bc1_y", repr(h)] + (["-gimp_multirate", "true"] if mine.multirate else [])
    ylo, yhi = -2 * h, 3 * h  # the default domain: the strip padded by 2 cells
    rr = ["-gimp_level1_ratio", str(ratio)]
    grids = {"uniform": (uniform_opts, []),
             "box": (OPTS, rr + ["-gimp_level1_box", "%r,%r,%r,%r" % (XA, ylo, XB, yhi)]),
             "open": (OPTS, rr + ["-gimp_level1_box", "%r,%r,%r,%r" % (XA, ylo, L + 2 * h, yhi)])}
    res = {"n": n, "h0": h, "kh0": K * h, "dt": dt, "steps": steps, "wall": 0.0, "ok": True,
           "energy_ratio": []}
    P = {}
    for name, (opts, extra) in grids.items():
        out = os.path.join(args.work, "%s_n%d" % (name, n))
        dump = out + "_particles.csv"
        t0 = time.time()
        gimptest.run(args, opts, common + extra + ["-gimp_particle_dump", dump], outdir=out)
        res["wall"] += time.time() - t0
        s = gimptest.summary(out)
        res["ok"] = res["ok"] and s["status"] == "completed" and abs(s["time"] - T) < 1e-9 * T \
            and s["steps"] == steps and len(s["levels"]) == (1 if name == "uniform" else 2)
        e = s["energy"]
        res["energy_ratio"].append((e["kinetic"] + e["strain"]) / e["external_work"])
        P[name] = read_particles(dump, h)
        res["particles_" + name] = len(P[name])
    Ep = sum(particle_energy(r) for r in P["box"])
    res["pulse_energy"] = Ep
    d, m1 = difference_energy(P["box"], P["uniform"], -1.0, XA, h)
    res["c2f"] = d / Ep
    d, m2 = difference_energy(P["box"], P["open"], XA, XB, h)
    res["f2c"] = d / Ep
    res["mismatch"] = max(m1, m2)
    res["c2f_raw"] = window_energy(P["box"], -1.0, XA) / Ep
    res["c2f_background"] = window_energy(P["uniform"], -1.0, XA) / Ep
    res["f2c_raw"] = window_energy(P["box"], XA, XB) / Ep
    res["f2c_background"] = window_energy(P["open"], XA, XB) / Ep
    spectral(P, n, res)
    return res



def orders(rows, key):
    return gimptest.orders(rows, key, "h0")



def fo(p):
    return gimptest.fmt_order(p, 5)


t_start = time.time()
rows = [run(n) for n in levels]
pc, fit_c = orders(rows, "c2f")
pf, fit_f = orders(rows, "f2c")

print("Reflected energy fraction at the level interfaces (%s, ratio %d), pulse width W = %g m, "
      "k = 2 pi / W, t = %g s" % (OPTS, ratio, W, T))
print("%9s %6s %10s %6s | %10s %5s %10s %10s | %10s %5s %10s %10s | %6s" %
      ("h0 [m]", "k h0", "dt [s]", "steps", "c->f", "order", "raw", "background",
       "f->c", "order", "raw", "background", "wall"))
for r, a, b in zip(rows, pc, pf):
    print("W/%-7d %6.3f %10.4e %6d | %10.3e %s %10.3e %10.3e | %10.3e %s %10.3e %10.3e | %6.1f" %
          (r["n"], r["kh0"], r["dt"], r["steps"], r["c2f"], fo(a), r["c2f_raw"],
           r["c2f_background"], r["f2c"], fo(b), r["f2c_raw"], r["f2c_background"], r["wall"]))
print("least-squares order in h0: coarse->fine %.3f, fine->coarse %.3f" % (fit_c, fit_f))
print("Amplitude reflection coefficient |R| at one wavenumber k (spectra of the reflected and the"
      " incident waves), against the lumped-mass 1D chain with the same jump:")
for r in rows:
    for cells in (10, 20):
        if "R_c2f_%d" % cells in r:
            print("  h0 = W/%d, %d coarse cells per wavelength: coarse->fine %.3e (chain %.3e), "
                  "fine->coarse %.3e (chain %.3e)" % (
                      r["n"], cells, r["R_c2f_%d" % cells], r["chain_c2f_%d" % cells],
                      r["R_f2c_%d" % cells], r["chain_f2c_%d" % cells]))
print("reflected = energy of (box - reference) on the incoming side; raw = energy of the box "
      "run there; background = energy of the reference run there (uniform / open)")

path = os.path.join(args.work, "reflection.csv")
with open(path, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["ratio", "n", "h0", "kh0", "dt", "steps", "particles_box", "pulse_energy",
                "c2f", "order_c2f", "c2f_raw", "c2f_background",
                "f2c", "order_f2c", "f2c_raw", "f2c_background",
                "energy_ratio_min", "energy_ratio_max", "wall_s"])
    for r, a, b in zip(rows, pc, pf):
        w.writerow([ratio, r["n"], repr(r["h0"]), "%.6f" % r["kh0"], "%.6e" % r["dt"], r["steps"],
                    r["particles_box"], "%.6e" % r["pulse_energy"],
                    "%.6e" % r["c2f"], "" if a is None else "%.4f" % a,
                    "%.6e" % r["c2f_raw"], "%.6e" % r["c2f_background"],
                    "%.6e" % r["f2c"], "" if b is None else "%.4f" % b,
                    "%.6e" % r["f2c_raw"], "%.6e" % r["f2c_background"],
                    "%.6f" % min(r["energy_ratio"]), "%.6f" % max(r["energy_ratio"]),
                    "%.2f" % r["wall"]])
print("wrote %s (%.1f s)" % (path, time.time() - t_start))

chk = gimptest.Checks()
chk.check("runs", all(r["ok"] for r in rows),
          "%d runs reached t = %g s in the expected number of steps" % (3 * len(rows), T))
chk.check("matching", all(r["mismatch"] < 1e-3 for r in rows),
          "compared particles coincide (largest offset %.1e h0)" % max(r["mismatch"] for r in rows))
chk.check("energy", all(abs(x - 1) < ENERGY_TOL for r in rows for x in r["energy_ratio"]),
          "(kinetic + strain) / traction work in [%.5f, %.5f]" %
          (min(x for r in rows for x in r["energy_ratio"]),
           max(x for r in rows for x in r["energy_ratio"])))
for key, name, fit in (("c2f", "coarse->fine", fit_c), ("f2c", "fine->coarse", fit_f)):
    vals = [r[key] for r in rows]
    chk.check("%s decreasing" % name, all(a > b for a, b in zip(vals, vals[1:])),
              "reflected fraction %s" % ", ".join("%.3e" % v for v in vals))
    chk.check("%s order" % name, len(rows) < 2 or fit >= MIN_ORDER,
              "least-squares order %.2f (>= %.1f)" % (fit, MIN_ORDER))
    if rows[-1]["n"] >= 64:
        chk.check("%s finest" % name, vals[-1] < MAX_FINEST,
                  "%.3e at h0 = W/%d (< %.0e)" % (vals[-1], rows[-1]["n"], MAX_FINEST))
# One wavenumber: |R| no larger than the lumped-mass chain's with the same jump, up to the
# measurement's own spread (CHAIN_TOL).
for r in rows:
    for cells in (10, 20):
        for key, name in (("c2f", "coarse->fine"), ("f2c", "fine->coarse")):
            got, ref = r.get("R_%s_%d" % (key, cells)), r.get("chain_%s_%d" % (key, cells))
            if got is None:
                continue
            chk.check("%s |R| at %d cells per wavelength, W/%d" % (name, cells, r["n"]),
                      got <= (1 + CHAIN_TOL) * ref,
                      "%.4e, chain %.4e (ratio %.3f, at most %.2f)" %
                      (got, ref, got / ref, 1 + CHAIN_TOL))
chk.done()
