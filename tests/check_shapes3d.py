"""3D bodies (-gimp_dim 3): boxes, spheres, cylinders (along y; a hole along x), and box, spherical and
cylindrical holes, seeded with n^3 particles per leaf cell, a cube that a curved surface cuts
cut to its part in the body (-gimp_cut_cells, the default). One step of each scene; from the
particle dump:
- every particle's centre inside its shape and outside every hole;
- the seeded volume against the exact one: a box with a box hole exactly (its faces on grid
  lines), curved shapes to 1e-10 at h / r = 1/8 .. 1/2 with 2^3 particles per cell (the cut
  cubes' exact volumes, two holes that cross each other too);
- on two levels (a ratio-2 box around a sphere's cap) the sphere's volume as well, with particles
  of two sizes;
- without cut cells (-gimp_cut_cells false: a cube kept whole when its centre is in the body) the
  sphere within 1.5 % [0.12 %: a staircase, whose particles centred on the surface count as
  inside]."""
import math
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
BASE = ["-gimp_dim", "3", "-gimp_E", "1e6", "-gimp_nu", "0.3", "-gimp_rho", "1000",
        "-ts_max_steps", "1", "-gimp_body0_ppc", "8"]
pi = math.pi
SCENES = [
    ("box with a box hole", ["-gimp_h", "0.1", "-gimp_body0_box", "0,0,0,1,0.6,0.4",
                             "-gimp_body0_hole_boxes", "0.2,0.1,0.1,0.5,0.4,0.3"],
     1 * 0.6 * 0.4 - 0.3 * 0.3 * 0.2, 0.0,
     lambda x, y, z: (0 <= x <= 1 and 0 <= y <= 0.6 and 0 <= z <= 0.4 and
                      not (0.2 < x < 0.5 and 0.1 < y < 0.4 and 0.1 < z < 0.3))),
    ("sphere", ["-gimp_h", "0.0625", "-gimp_body0_shape", "sphere",
                "-gimp_body0_sphere", "0.1,0.2,0.3,0.5"],
     4 / 3 * pi * 0.125, 1e-10,
     lambda x, y, z: (x - 0.1) ** 2 + (y - 0.2) ** 2 + (z - 0.3) ** 2 <= 0.25 + 1e-12),
    ("cylinder along y", ["-gimp_h", "0.0625", "-gimp_body0_shape", "cylinder",
                          "-gimp_body0_cylinder_axis", "y", "-gimp_body0_cylinder",
                          "0.5,0.5,0.5,0,1"],
     pi * 0.25 * 1.0, 1e-10,
     lambda x, y, z: (x - 0.5) ** 2 + (z - 0.5) ** 2 <= 0.25 + 1e-12 and 0 <= y <= 1),
    ("box with sphere and x-cylinder holes",
     ["-gimp_h", "0.0625", "-gimp_body0_box", "0,0,0,2,1,1", "-gimp_body0_hole_spheres",
      "1.5,0.5,0.5,0.25", "-gimp_body0_hole_cylinder_axis", "x", "-gimp_body0_hole_cylinders",
      "0.5,0.5,0.125"],
     # The cylinder runs through the ball: the part of it in the ball, 4 pi / 3 (R^3 -
     # (R^2 - a^2)^1.5), is removed once.
     2.0 - 4 / 3 * pi * 0.25 ** 3 - pi * 0.125 ** 2 * 2.0 +
     4 / 3 * pi * (0.25 ** 3 - (0.25 ** 2 - 0.125 ** 2) ** 1.5), 1e-10,
     lambda x, y, z: (0 <= x <= 2 and 0 <= y <= 1 and 0 <= z <= 1 and
                      (x - 1.5) ** 2 + (y - 0.5) ** 2 + (z - 0.5) ** 2 >= 0.0625 - 1e-12 and
                      (y - 0.5) ** 2 + (z - 0.5) ** 2 >= 0.125 ** 2 - 1e-12)),
    ("sphere on two levels", ["-gimp_h", "0.0625", "-gimp_body0_shape", "sphere",
                              "-gimp_body0_sphere", "0.5,0.5,0.5,0.5", "-gimp_domain",
                              "-0.125,-0.125,-0.125,1.125,1.125,1.125", "-gimp_levels", "2",
                              "-gimp_level1_box", "0.5,0.5,0.5,1.125,1.125,1.125"],
     4 / 3 * pi * 0.125, 1e-10,
     lambda x, y, z: (x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.5) ** 2 <= 0.25 + 1e-12),
    ("sphere without cut cells", ["-gimp_h", "0.0625", "-gimp_body0_shape", "sphere",
                                  "-gimp_body0_sphere", "0.1,0.2,0.3,0.5", "-gimp_cut_cells",
                                  "false"],
     4 / 3 * pi * 0.125, 0.015,
     lambda x, y, z: (x - 0.1) ** 2 + (y - 0.2) ** 2 + (z - 0.3) ** 2 <= 0.25 + 1e-12),
]
base = os.path.join(args.work, "shapes3d.opts")  # a body at rest, no load
with open(base, "w") as f:
    for k in range(0, len(BASE), 2):
        f.write("%s %s\n" % (BASE[k], BASE[k + 1]))
for name, opts, exact, tol, inside in SCENES:
    tag = name.replace(" ", "_")
    dump = os.path.join(args.work, tag + ".csv")
    gimptest.run(args, base, opts + ["-gimp_particle_dump", dump],
                 outdir=os.path.join(args.work, tag))
    d = gimptest.read_csv(dump)
    # The dump's positions are after one step of a body at rest: within 1e-12 m of the seeds.
    out = sum(1 for x, y, z in zip(d["x"], d["y"], d["z"]) if not inside(x, y, z))
    vol = sum(d["V"])
    err = vol / exact - 1
    c.check(name, out == 0 and abs(err) <= tol + 1e-12,
            "%d particles, %d outside the shape; volume %.12f m^3, exact %.12f: %.1e (tol %.2g)"
            % (len(d["V"]), out, vol, exact, err, tol))
c.done()
