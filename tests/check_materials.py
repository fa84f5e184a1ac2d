"""A material per body (docs/validation.md "Materials per body").

Bimaterial bar (options/bimaterial.opts): two bodies in series, E = 100 and 300 Pa, rho = 1 and
2, pulled to rest: every particle's displacement within 1e-5 of the exact piecewise-linear
field (relative to its largest value) and every stress within 1e-5 of the traction; 2 ranks
give the 1-rank particles to round-off.

Disk on a block (options/disk_on_block.opts): a disk (E = 0.2 MPa, nu = 0.25, rho = 3000) dropped
on a block (E = 1 MPa, nu = 0.3, rho = 1000) under gravity comes to rest, and the vertical force
the block carries across the grid line y = 0.2 m, less the block's own weight above it, is the
disk's weight within 1e-3. The force across a grid line is the one the nodes see: for each
particle the derivative of its weights summed over the nodes at and below the line, times its
V sigma_yy; the block's weight above the line is likewise its particles' mass times the weights
summed over the nodes above it.

Bad input: a body's E, nu or rho out of range, one line each."""
import math
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()


def run(opts, name, extra=(), ranks=1):
    out, dump = os.path.join(args.work, name), os.path.join(args.work, name + ".csv")
    s = gimptest.summary(gimptest.run(args, opts, list(extra) + ["-gimp_particle_dump", dump],
                                      ranks=ranks, outdir=out))
    return s, gimptest.read_csv(dump)


# 1. Bimaterial bar.
T, E0, E1 = 1e-4, 100.0, 300.0
_, start = run("options/bimaterial.opts", "bi_start", ["-ts_max_steps", "0"])
s, end = run("options/bimaterial.opts", "bi")
c.check("bimaterial: at rest", s["status"] == "at_rest", "status %s" % s["status"])


def exact(X):
    return T * X / E0 if X <= 4 else T * 4 / E0 + T * (X - 4) / E1


umax = exact(8.0)
du = max(max(abs(x1 - x0 - exact(x0)), abs(y1 - y0)) / umax
         for x0, y0, x1, y1 in zip(start["x"], start["y"], end["x"], end["y"]))
ds = max(max(abs(a - T), abs(b), abs(d)) / T for a, b, d in zip(end["sxx"], end["syy"], end["sxy"]))
c.check("bimaterial: displacements", du <= 1e-5,
        "worst particle %.2e of the largest displacement (tol 1e-5; E_1 = E_0 would be %.0e off)"
        % (du, abs(exact(8.0) - T * 8 / E0) / umax))
c.check("bimaterial: stresses", ds <= 1e-5, "worst particle %.2e of t (tol 1e-5)" % ds)
_, two = run("options/bimaterial.opts", "bi_np2", ranks=2)
worst = max(abs(a - b) for k in ("x", "y", "sxx", "syy") for a, b in zip(end[k], two[k]))
c.check("bimaterial: 2 ranks equal 1 rank", worst < 1e-12 * max(1.0, umax),
        "largest difference %.1e" % worst)

# 2. Disk on a block.
H, LINE, G, RHO_B, RHO_D, R = 0.05, 0.2, 10.0, 1000.0, 3000.0, 0.1
s, rows = run("options/disk_on_block.opts", "disk_on_block")
c.check("disk on block: at rest", s["status"] == "at_rest", "status %s" % s["status"])


def below(x):  # the weights of the nodes at and below the line, summed: 1, then a ramp to 0
    return 1.0 if x <= LINE else (0.0 if x >= LINE + H else 1.0 - (x - LINE) / H)


def below_avg(y, l):  # the same averaged over the particle's domain [y - l, y + l]
    pts = sorted({y - l, y + l} | {p for p in (LINE, LINE + H) if y - l < p < y + l})
    return sum((b - a) * (below(a) + below(b)) / 2 for a, b in zip(pts, pts[1:])) / (2 * l)


d = H / 2  # the block's particles are whole squares of side h / 2
force = block = 0.0
for y, l, V, syy in zip(rows["y"], rows["ly"], rows["V"], rows["syy"]):
    force -= V * syy * (below(y - l) - below(y + l)) / (2 * l)
    if y < 0.4:  # a block particle (the disk lies wholly above the line's reach)
        block += RHO_B * d * d * G * (1.0 - below_avg(y, l))
weight = RHO_D * G * math.pi * R * R
err = (force - block) / weight - 1
c.check("disk on block: the block carries the disk's weight", abs(err) <= 1e-3,
        "force across y = %.1f m less the block above it: %.3f N against rho_d g pi r^2 = %.3f N "
        "(%+.1e, tol 1e-3)" % (LINE, force - block, weight, err))

# 3. Bad input.
for name, extra, needle in (
        ("negative E", ["-gimp_body1_E", "-5"], "-gimp_body1_E -5: must be > 0"),
        ("nu 0.5", ["-gimp_body1_nu", "0.5"], "-gimp_body1_nu 0.5: must lie in (-1, 0.5)"),
        ("zero rho", ["-gimp_body1_rho", "0"], "-gimp_body1_rho 0: must be > 0"),
        ("NaN E", ["-gimp_body1_E", "nan"], "-gimp_body1_E"),
        ("neo-Hookean in plane stress", ["-gimp_plane", "stress", "-gimp_body1_material",
                                         "neohookean"], "-gimp_body1_material neohookean")):
    p = gimptest.run(args, "options/bimaterial.opts", extra + ["-ts_max_steps", "1"],
                     expect_ok=False, outdir=os.path.join(args.work, "bad"))
    lines = [ln for ln in p.stderr.splitlines() if "error" in ln]
    c.check("bad input: " + name, p.returncode != 0 and len(lines) == 1 and needle in lines[0],
            "exit %d: %s" % (p.returncode, lines[0] if lines else p.stderr.strip()[-200:]))
# A body with no material: neither the scene's -gimp_E, -gimp_rho nor its own.
with open(os.path.join(args.root, "options", "bimaterial.opts")) as f:
    lines = [ln for ln in f if not ln.startswith(("-gimp_E ", "-gimp_rho "))]
noscene = os.path.join(args.work, "no_scene_material.opts")
with open(noscene, "w") as f:
    f.writelines(lines)
p = gimptest.run(args, noscene, ["-ts_max_steps", "1"], expect_ok=False,
                 outdir=os.path.join(args.work, "bad"))
lines = [ln for ln in p.stderr.splitlines() if "error" in ln]
c.check("bad input: a body with no material", p.returncode != 0 and len(lines) == 1 and
        "-gimp_body0_E (missing): the body has no Young's modulus" in lines[0],
        "exit %d: %s" % (p.returncode, lines[0] if lines else p.stderr.strip()[-200:]))
s, ok = run(noscene, "bodies_only", ["-gimp_body0_E", "100", "-gimp_body0_rho", "1"])
same = max(abs(a - b) for k in ("x", "y", "sxx") for a, b in zip(ok[k], end[k]))
c.check("every body its own material, no scene material", s["status"] == "at_rest" and same == 0,
        "status %s; largest difference from the bar with the scene's material %.1e"
        % (s["status"], same))
c.done()
