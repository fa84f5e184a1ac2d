"""A thin plate with a through-thickness hole in 3D against the 2D plane-stress run
(options/thin_plate3d.opts, options/thin_plate2d.opts): the same quarter plate (20 x 20 mm,
hole of radius 2 mm, 0.5 mm thick, p = 10 MPa along x), grid and in-plane particles, both with
cut cells (a particle cut by the hole takes the exact part in the body); the 3D plate has two
layers of particles through its thickness and free faces. Both are damped to rest.

Each 3D particle is compared with the 2D particle at the same in-plane position (the nearest;
their distance is checked). Checked (measured in brackets):
- the hole measure (-gimp_hole_measure, in 3D at mid-thickness; summary.json): kt_particle (the
  particle on the 90-degree ray nearest the edge) 3D against 2D within 1 % [3D 2.868, 2D 2.879:
  -0.41 %], and the fitted edge value kt within 5 % [3D 3.178, 2D 3.315: -4.1 %: at r / h = 4
  the fit at the symmetry plane x = 0 sees one side of it, hoop_max_error 0.37 in both];
- the stress concentration at the top of the hole, sigma_xx of the particles next to x = 0 and
  the hole (averaged through the thickness), 3D against 2D within 4 % [3D 2.883, 2D 2.975:
  -3.1 %: the column holds the sliver the hole cuts at its top];
- away from the hole's edge (r > r_hole + 2 h), every particle's in-plane stress against the 2D
  one within 5 % of p [2.1 %], and sigma_zz within 10 % of p [4.1 %: the free faces hold
  sigma_zz = 0 only weakly, one particle layer from each face];
- over all particles the RMS of the in-plane differences within 2 % of p [0.82 %] (the largest
  ones sit on the hole's edge);
- both runs at rest (kinetic below 1e-9 of the strain energy [5e-13]), and the strain energies
  (both of the 0.5 mm plate) equal within 1 % [0.016 %];
- on h = 0.25 mm (r / h = 8; the 3D plate two cells and four particle layers thick, its two
  middle layers measured), at rest after 4000 steps (kinetic / strain 4e-13): the fitted kt 3D
  against 2D within 1 % [3D 3.409, 2D 3.404: +0.15 %], kt_particle within 2 % [+0.79 %]. About
  50 s."""
import math
import os
import gimptest

args = gimptest.parse_args()
p, rh, h = 10e6, 2e-3, 0.5e-3
runs = {}
for dim in ("2d", "3d"):
    dump = os.path.join(args.work, "thin_plate%s.csv" % dim)
    # Both with cut cells (the 2D scene keeps whole squares for its regression answers) and the
    # hole measure (in 3D at mid-thickness).
    out = gimptest.run(args, "options/thin_plate%s.opts" % dim,
                       ["-gimp_particle_dump", dump, "-gimp_cut_cells", "true",
                        "-gimp_hole_measure", "0,0,%g" % rh, "-gimp_hole_measure_load", "%g" % p])
    runs[dim] = (gimptest.read_csv(dump), gimptest.history(out),
                 gimptest.summary(out)["measures"])
d2, h2, m2 = runs["2d"]
d3, h3, m3 = runs["3d"]
c = gimptest.Checks()

# The 2D particle at each 3D particle's in-plane position (a grid of the particle spacing).
spacing = h / 2
index = {}
for k, (x, y) in enumerate(zip(d2["x"], d2["y"])):
    index[(round(x / spacing - 0.5), round(y / spacing - 0.5))] = k
match, far = [], 0.0
for x, y in zip(d3["x"], d3["y"]):
    k = index.get((round(x / spacing - 0.5), round(y / spacing - 0.5)))
    match.append(k)
    if k is not None:
        far = max(far, math.hypot(d2["x"][k] - x, d2["y"][k] - y))
c.check("particles matched", None not in match and len(d3["x"]) == 2 * len(d2["x"]) and
        far < 0.01 * spacing, "%d 3D particles, %d 2D; largest in-plane distance %.1e m" %
        (len(d3["x"]), len(d2["x"]), far))

top3 = [s for x, y, s in zip(d3["x"], d3["y"], d3["sxx"]) if x < spacing and y < rh + spacing]
top2 = [s for x, y, s in zip(d2["x"], d2["y"], d2["sxx"]) if x < spacing and y < rh + spacing]
kt3, kt2 = sum(top3) / len(top3) / p, sum(top2) / len(top2) / p
c.check("kt at the top of the hole", abs(kt3 / kt2 - 1) <= 0.04,
        "3D %.3f (%d particles), 2D %.3f (%d): %.2f %%" %
        (kt3, len(top3), kt2, len(top2), 100 * (kt3 / kt2 - 1)))

for key, tol in (("kt_particle", 0.01), ("kt", 0.05)):
    c.check("hole measure " + key, abs(m3[key] / m2[key] - 1) <= tol,
            "3D %.4f, 2D %.4f: %+.2f %% (tol %g %%)" %
            (m3[key], m2[key], 100 * (m3[key] / m2[key] - 1), 100 * tol))

worst_far = worst_zz = 0.0
sq, n = 0.0, 0
for k3, k2 in enumerate(match):
    dif = [abs(d3[s][k3] - d2[s][k2]) / p for s in ("sxx", "syy", "sxy")]
    sq += sum(e * e for e in dif)
    n += 3
    if math.hypot(d3["x"][k3], d3["y"][k3]) > rh + 2 * h:
        worst_far = max(worst_far, max(dif))
        worst_zz = max(worst_zz, abs(d3["szz"][k3]) / p)
c.check("in-plane stress away from the hole", worst_far <= 0.05,
        "max |s3D - s2D| / p = %.2e over particles with r > r_hole + 2 h (tol 0.05)" % worst_far)
c.check("sigma_zz away from the hole", worst_zz <= 0.10,
        "max |szz| / p = %.2e (tol 0.10)" % worst_zz)
rms = math.sqrt(sq / n)
c.check("RMS of the in-plane differences", rms <= 0.02, "%.2e of p (tol 0.02)" % rms)
for dim, hist in (("2D", h2), ("3D", h3)):
    ratio = hist["kinetic"][-1] / hist["strain"][-1]
    c.check(dim + " at rest", ratio <= 1e-9, "kinetic / strain = %.1e" % ratio)
e = h3["strain"][-1] / h2["strain"][-1] - 1
c.check("strain energy", abs(e) <= 0.01, "3D / 2D - 1 = %.2e (both of the 0.5 mm plate)" % e)

# The same pair on h = 0.25 mm (r / h = 8, four particle layers through the thickness), at rest
# after 4000 steps: the hole measure only.
fine = {}
for dim in ("2d", "3d"):
    out = gimptest.run(args, "options/thin_plate%s.opts" % dim,
                       ["-gimp_h", "0.25e-3", "-ts_max_steps", "4000", "-gimp_cut_cells", "true",
                        "-gimp_hole_measure", "0,0,%g" % rh, "-gimp_hole_measure_load", "%g" % p],
                       outdir=os.path.join(args.work, "fine" + dim))
    fine[dim] = gimptest.summary(out)["measures"]
for key, tol in (("kt", 0.01), ("kt_particle", 0.02)):
    f3, f2 = fine["3d"][key], fine["2d"][key]
    c.check("h = 0.25 mm: hole measure " + key, abs(f3 / f2 - 1) <= tol,
            "3D %.4f, 2D %.4f: %+.2f %% (tol %g %%)" % (f3, f2, 100 * (f3 / f2 - 1), 100 * tol))
c.done()
