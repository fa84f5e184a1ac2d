"""Body shapes (docs/validation.md "Shapes").

- Seeding keeps each shape's area: an ellipse body with an elliptic hole and a polygon body with
  a polygonal hole, their particle volumes add up to the exact areas to 1e-12.
- A rectangle described as a polygon, with a circular hole inside it, runs as the same
  rectangle given by -gimp_body0_box: the particles coincide, and after 300 steps they agree to
  round-off.
- The V-notched bar (options/notched_bar.opts, a polygon whose slanted flanks cut the particle
  squares) comes to rest, and the force across the grid lines x = 1, 2, 4 (through the notch
  roots) and 6 m equals the applied t H within 1e-6; the peak stress at the notch roots is
  reported."""
import csv
import math
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work


def dump_run(opts, name, extra=(), ranks=1):
    dump = os.path.join(W, name + ".csv")
    s = gimptest.summary(gimptest.run(args, opts, list(extra) + ["-gimp_particle_dump", dump],
                                      ranks=ranks, outdir=os.path.join(W, name)))
    with open(dump) as f:
        return s, list(csv.DictReader(f))


def scene(name, lines):
    path = os.path.join(W, name + ".opts")
    with open(path, "w") as f:
        f.write("-gimp_E 100\n-gimp_nu 0.3\n-gimp_rho 1\n-gimp_plane strain\n" + lines)
    return path


# 1. Areas.
el = scene("ellipse", "-gimp_h 0.1\n-gimp_body0_shape ellipse\n-gimp_body0_ellipse 1.03,0.77,0.61,0.37\n"
           "-gimp_body0_hole_ellipses 1.1,0.8,0.2,0.1\n-ts_max_steps 0\n")
_, rows = dump_run(el, "ellipse")
exact = math.pi * (0.61 * 0.37 - 0.2 * 0.1)
err = sum(float(r["V"]) for r in rows) / exact - 1
c.check("ellipse minus ellipse: area", abs(err) <= 1e-12,
        "particle volumes / (pi a b - pi a' b') - 1 = %.1e (tol 1e-12), %d particles"
        % (err, len(rows)))
star = [(1 + (0.6 if k % 2 == 0 else 0.25) * math.cos(math.pi * k / 5),
         1 + (0.6 if k % 2 == 0 else 0.25) * math.sin(math.pi * k / 5)) for k in range(10)]
tri = [(0.95, 0.95), (1.1, 0.97), (1.0, 1.08)]


def area(p):
    return 0.5 * abs(sum(p[i][0] * p[(i + 1) % len(p)][1] - p[(i + 1) % len(p)][0] * p[i][1]
                         for i in range(len(p))))


def flat(p):
    return ",".join("%.17g,%.17g" % q for q in p)


po = scene("star", "-gimp_h 0.1\n-gimp_body0_shape polygon\n-gimp_body0_polygon %s\n"
           "-gimp_body0_hole_polygons 1\n-gimp_body0_hole_polygon0 %s\n-ts_max_steps 0\n"
           % (flat(star), flat(tri)))
_, rows = dump_run(po, "star")
exact = area(star) - area(tri)
err = sum(float(r["V"]) for r in rows) / exact - 1
c.check("star minus triangle: area", abs(err) <= 1e-12,
        "particle volumes / polygon areas - 1 = %.1e (tol 1e-12), %d particles" % (err, len(rows)))

# Unions (-gimp_bodyK_add_*): exact areas by inclusion-exclusion.
unions = [
    ("stadium: rectangle + two circles",
     "-gimp_body0_box 0.5,0.5,1.5,1.0\n-gimp_body0_add_circles 0.5,0.75,0.25,1.5,0.75,0.25\n",
     0.5 + math.pi * 0.0625),
    ("T: two overlapping rectangles",
     "-gimp_body0_box 0,0,1,0.2\n-gimp_body0_add_boxes 0.4,0.1,0.6,0.8\n", 0.32),
    ("notched square + convex polygon",
     "-gimp_body0_shape polygon\n-gimp_body0_polygon 0,0,1,0,1,1,0.5,0.5,0,1\n"
     "-gimp_body0_add_polygons 1\n-gimp_body0_add_polygon0 0.3,0.3,0.7,0.3,0.7,1.4,0.3,1.4\n",
     0.75 + 0.44 - 0.12),
]
for k, (name, lines, exact) in enumerate(unions):
    _, rows = dump_run(scene("union%d" % k, "-gimp_h 0.05\n-gimp_domain -0.5,-0.5,2.5,2\n"
                             "-ts_max_steps 0\n" + lines), "union%d" % k)
    err = sum(float(r["V"]) for r in rows) / exact - 1
    c.check("union: " + name, abs(err) <= 1e-12,
            "particle volumes / exact area - 1 = %.1e (tol 1e-12), %d particles"
            % (err, len(rows)))
for name, lines, needle in (
        ("two overlapping circles", "-gimp_body0_shape circle\n-gimp_body0_circle 1,1,0.4\n"
         "-gimp_body0_add_circles 1.5,1,0.4\n",
         "-gimp_body0_add_circles (shape 1 of the union): overlaps shape 0, and neither"),
        ("three shapes at a point", "-gimp_body0_box 0,0,1,0.2\n"
         "-gimp_body0_add_boxes 0.4,0.1,0.6,0.8,0.45,0,0.55,1\n", "three of the joined shapes")):
    o = scene("bad_union", "-gimp_h 0.05\n-gimp_domain -0.5,-0.5,2.5,2\n-ts_max_steps 0\n" + lines)
    p = gimptest.run(args, o, [], expect_ok=False, outdir=os.path.join(W, "bad"))
    errs = [ln for ln in p.stderr.splitlines() if "error" in ln]
    c.check("union refused: " + name, p.returncode != 0 and len(errs) == 1 and needle in errs[0],
            "exit %d: %s" % (p.returncode, errs[0] if errs else p.stderr.strip()[-200:]))

# 2. A rectangle as a polygon equals the rectangle.
common = ("-gimp_h 0.125\n-gimp_body0_holes 1,0.5,0.2\n-gimp_tractions 1\n"
          "-gimp_traction0_side right\n-gimp_traction0_value 1e-4,0\n-gimp_bcs 1\n-gimp_bc0_x 0\n"
          "-gimp_bc0_type roller\n-gimp_damping 4\n-ts_max_steps 300\n")
_, box = dump_run(scene("box", common + "-gimp_body0_box 0,0,2,1\n"), "box")
_, pol = dump_run(scene("poly", common + "-gimp_body0_shape polygon\n"
                        "-gimp_body0_polygon 0,0,2,0,2,1,0,1\n"), "poly")
same = len(box) == len(pol)
d = max(abs(float(a[k]) - float(b[k])) / max(abs(float(x[k])) for x in box)
        for a, b in zip(box, pol) for k in ("x", "y", "vx", "vy", "sxx", "V")) if same else 1
c.check("rectangle as a polygon = rectangle", same and d <= 1e-13,
        "%d and %d particles; largest relative difference after 300 steps %.1e"
        % (len(box), len(pol), d))

# 3. The notched bar.
s, rows = dump_run("options/notched_bar.opts", "notched_bar")
c.check("notched bar: at rest", s["status"] == "at_rest", "status %s at step %d"
        % (s["status"], s["steps"]))
H, T, h = 2.0, 1e-4, 0.125


def force_across(X):
    """The force the nodes see across the grid line x = X: for each particle, V sxx times the
    derivative of its weights summed over the nodes at and left of the line."""
    def left(x):
        return 1.0 if x <= X else (0.0 if x >= X + h else 1.0 - (x - X) / h)
    return sum(float(r["V"]) * float(r["sxx"]) * (left(float(r["x"]) - float(r["lx"])) -
                                                   left(float(r["x"]) + float(r["lx"])))
               / (2 * float(r["lx"])) for r in rows)


worst = max(abs(force_across(X) / (T * H) - 1) for X in (1.0, 2.0, 4.0, 6.0))
c.check("notched bar: force across sections", worst <= 1e-6,
        "largest |F / (t H) - 1| over x = 1, 2, 4, 6 m: %.1e (tol 1e-6)" % worst)
peak = max(float(r["sxx"]) for r in rows if abs(float(r["x"]) - 4) < 0.25)
print("notched bar: peak sxx near the notch roots %.4e = %.3f of the net-section stress t H / "
      "(H - 2 d)" % (peak, peak / (T * H / (H - 1.0))))
c.done()
