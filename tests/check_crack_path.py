"""A crack that curves toward a hole (options/crack_hole_path.opts): an edge crack from the left
edge of a 60 x 120 mm plate to (12, 52) mm, a hole of radius 5 mm at (28, 59) mm above its
line, tension along y held at 95 % of 1 MPa while the damped plate settles, then raised slowly;
toughness 33 J/m^2 (G by J reaches it near the full load). The tip grows by the maximum hoop
stress criterion one finest cell at a time, every 50 steps of 0.2 us at h = 1 mm (a crack speed
of about 100 m/s, 0.14 of the Rayleigh speed: J's static form holds), until it comes within two
cells of the hole, where no J domain fits any more and it stops with a warning line.

The same scene with every cell halved (-gimp_h 2e-3: finest 0.5 mm, increments of 0.5 mm,
checks every 25 steps, so the crack advances at the same speed) must give the same path.

Checked (measured in brackets): both paths rise toward the hole by more than 0.5 mm over their
growth [h: 0.67 mm; h/2: 1.24 mm, which grows 1.4 mm further before its tip comes within two of
its cells of the hole]; over the stretch both grew, the h/2 path's y at each increment of the h
path within two finest cells of h (2 mm) [0.10 mm], the bound of path stability; both tips stop
with the line naming the missing J domain, after at least 10 mm of growth [14.0 and 15.5 mm].
The paths are written to <work>/paths.csv; runs/crack_path.py plots them
(docs/img/crack_hole_path.png).
"""
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
HOLE = (0.028, 0.059, 0.005)
runs = {"h": [], "h/2": ["-gimp_h", "2e-3", "-gimp_crack_growth_interval", "25"]}
paths, lines = {}, {}
for name, extra in runs.items():
    out = os.path.join(args.work, name.replace("/", "_"))
    p = gimptest.run(args, "options/crack_hole_path.opts", extra, outdir=out, expect_ok=False)
    if p.returncode != 0:
        raise SystemExit("gimp failed on %s: %s" % (name, p.stderr.strip()))
    tip = gimptest.summary(out)["cracks"][0]
    paths[name] = [(0.012, 0.052)] + [tuple(r["x"]) for r in tip.get("growth", [])]
    lines[name] = [l for l in (p.stdout + p.stderr).splitlines() if "stops growing" in l]


def y_at(path, x):
    """The path's y at x, linear between its points (None outside its x range)."""
    for (x0, y0), (x1, y1) in zip(path, path[1:]):
        if min(x0, x1) <= x <= max(x0, x1) and x1 != x0:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return None


with open(os.path.join(args.work, "paths.csv"), "w") as f:
    f.write("run,x,y\n")
    for name, path in paths.items():
        for x, y in path:
            f.write("%s,%.9g,%.9g\n" % (name, x, y))
for name, path in paths.items():
    rise = path[-1][1] - path[0][1]
    grown = sum(((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2) ** 0.5 for a, b in zip(path, path[1:]))
    c.check("%s: toward the hole" % name, rise > 0.5e-3,
            "the tip rose %.2f mm over %d increments (%.1f mm of growth), to (%.2f, %.2f) mm" %
            (1e3 * rise, len(path) - 1, 1e3 * grown, 1e3 * path[-1][0], 1e3 * path[-1][1]))
    said = [l for l in lines[name] if "no J-integral domain fits" in l]
    c.check("%s: stops at the hole" % name, grown >= 10e-3 and len(said) == 1,
            said[0].strip() if said else "no stop line: %s" % lines[name])
diffs = [abs(y_at(paths["h/2"], x) - y) for x, y in paths["h"][1:] if y_at(paths["h/2"], x) is not None]
c.check("the same path at h/2", diffs and max(diffs) <= 2e-3,
        "largest |y(h/2) - y(h)| at the %d increments of h where both grew: %.3f mm (bound two "
        "finest cells of h, 2 mm)" % (len(diffs), 1e3 * max(diffs) if diffs else float("nan")))
c.done()
