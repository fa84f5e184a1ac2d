"""Bodies from particle files (-gimp_bodyK_shape file; docs/options.md, docs/validation.md
"Bodies from particle files").

The colliding disks written as two particle files (the particles gimp seeds for
options/disks.opts, from its particle dump) run exactly as the disks described by circles,
through the impact, on 1 and 2 ranks; a file with V but no half-sizes gives square domains of
that area; and every kind of bad file stops the run with one line naming the option, the file
and what is wrong.

In 3D the same: a sphere (cut cells) thrown at a spinning box with a traction on its right face,
on two levels (SCENE3D below), written as two particle files from its particle dump, runs as the
shapes do through the impact (300 steps) on 1 and 2 ranks; a file with V alone gives cubes of
that volume; bad 3D files and the options a file body refuses stop the run with one line."""
import csv
import math
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work


def disks_file_opts(f0, f1, name):
    """options/disks.opts with its two circles replaced by the particle files f0, f1."""
    with open(os.path.join(args.root, "options", "disks.opts")) as f:
        keep = [ln for ln in f if not ln.startswith(("-gimp_body0_shape", "-gimp_body1_shape",
                                                      "-gimp_body0_circle", "-gimp_body1_circle",
                                                      "-gimp_body0_velocity",
                                                      "-gimp_body1_velocity"))]
    path = os.path.join(W, name)
    with open(path, "w") as f:
        f.writelines(keep)
        f.write("-gimp_body0_shape file\n-gimp_body0_file %s\n" % f0)
        f.write("-gimp_body1_shape file\n-gimp_body1_file %s\n" % f1)
    return path


def dump_run(opts, name, extra=(), ranks=1):
    dump = os.path.join(W, name + ".csv")
    gimptest.run(args, opts, list(extra) + ["-gimp_particle_dump", dump], ranks=ranks,
                 outdir=os.path.join(W, name))
    with open(dump) as f:
        return list(csv.DictReader(f))


# The disks' particles as seeded (with their velocities), one file per disk.
seed = dump_run("options/disks.opts", "seed", ["-ts_max_steps", "0"])
files = []
for k, below in enumerate((True, False)):
    path = os.path.join(W, "disk%d.csv" % k)
    with open(path, "w") as f:
        w = csv.writer(f)
        w.writerow(list(seed[0].keys()))
        for r in seed:
            if (float(r["x"]) + float(r["y"]) < 1) == below:
                w.writerow(list(r.values()))
    files.append(path)
opts = disks_file_opts(files[0], files[1], "disks_file.opts")


def key(r):
    return tuple(float(r[k]) for k in ("x", "y", "z") if k in r)


def worst(a, b):
    """The largest difference of each quantity relative to its largest value."""
    a, b = sorted(a, key=key), sorted(b, key=key)
    if len(a) != len(b):
        return float("inf")
    out = 0.0
    names = ("x", "y", "vx", "vy", "sxx", "syy", "sxy", "V", "lx", "ly")
    if "z" in a[0]:
        names += ("z", "vz", "szz", "syz", "sxz", "lz")
    for k in names:
        scale = max(abs(float(p[k])) for p in a) or 1.0
        out = max(out, max(abs(float(p[k]) - float(q[k])) for p, q in zip(a, b)) / scale)
    return out


steps = ["-ts_max_steps", "400"]  # t = 1.7 s: into the impact
circles, from_file = gimptest.concurrently([
    lambda: dump_run("options/disks.opts", "circles", steps),
    lambda: dump_run(opts, "from_file", steps)])
d = worst(circles, from_file)
c.check("disks from files = disks from circles", d <= 1e-12,
        "%d particles; largest difference of x, y, v, stress, V, l after 400 steps, relative to "
        "the largest value of each: %.1e"
        % (len(from_file), d))
two = dump_run(opts, "from_file_np2", steps, ranks=2)
d2 = worst(from_file, two)
c.check("2 ranks equal 1 rank", d2 <= 1e-12, "largest relative difference %.1e" % d2)

# Volumes only: square domains of the particle's area.
vonly = os.path.join(W, "vonly.csv")
with open(vonly, "w") as f:
    f.write("x,y,V\n0.5,0.5,0.0004\n0.52,0.5,0.0001\n")
bodyopts = os.path.join(W, "vonly.opts")
with open(bodyopts, "w") as f:
    f.write("-gimp_E 1000\n-gimp_rho 1000\n-gimp_h 0.05\n-gimp_domain 0,0,1,1\n"
            "-gimp_body0_shape file\n-gimp_body0_file %s\n-ts_max_steps 0\n" % vonly)
rows = dump_run(bodyopts, "vonly_dump")
ok = len(rows) == 2 and all(abs(float(r["lx"]) - math.sqrt(float(r["V"])) / 2) < 1e-15 and
                            float(r["lx"]) == float(r["ly"]) for r in rows)
c.check("V only: square domains", ok, "; ".join("V %s lx %s ly %s" % (r["V"], r["lx"], r["ly"])
                                                 for r in rows))


# 3D: a sphere and a box as seeded, then as two particle files.
SCENE3D = """-gimp_dim 3
-gimp_h 0.1
-gimp_domain 0,0,0,1.4,0.6,0.6
-gimp_E 1e6
-gimp_nu 0.3
-gimp_rho 1000
-gimp_bodies 2
-gimp_levels 2
-gimp_level1_box 0.2,0.1,0.1,0.9,0.5,0.5
-gimp_level1_ratio 2
-gimp_tractions 1
-gimp_traction0_body 1
-gimp_traction0_side right
-gimp_traction0_value 2e3,0,0
-ts_max_steps 300
"""
SHAPES3D = """-gimp_body0_shape sphere
-gimp_body0_sphere 0.35,0.3,0.3,0.12
-gimp_body0_velocity 4,1,0.5
-gimp_body1_box 0.7,0.2,0.2,0.9,0.4,0.4
-gimp_body1_spin 0,0,3
"""


def write(name, text):
    path = os.path.join(W, name)
    with open(path, "w") as f:
        f.write(text)
    return path


shapes3d = write("shapes3d.opts", SCENE3D + SHAPES3D)
seed3d = dump_run(shapes3d, "seed3d", ["-ts_max_steps", "0"])
files3d = []
for k in (0, 1):  # a body's ids start at k 2^40
    rows3d = [r for r in seed3d if int(r["id"]) >> 40 == k]
    files3d.append(write("body%d_3d.csv" % k, ",".join(seed3d[0].keys()) + "\n" +
                         "".join(",".join(r.values()) + "\n" for r in rows3d)))
from_files3d = write("files3d.opts", SCENE3D + "".join(
    "-gimp_body%d_shape file\n-gimp_body%d_file %s\n" % (k, k, f) for k, f in enumerate(files3d)))
shapes_run, files_run = gimptest.concurrently([
    lambda: dump_run(shapes3d, "shapes3d_run"),
    lambda: dump_run(from_files3d, "files3d_run")])
files_np2 = dump_run(from_files3d, "files3d_np2", ranks=2)
d = worst(shapes_run, files_run)
c.check("3D: sphere and box from files = from shapes", d <= 1e-12 and len(files_run) > 1000,
        "%d particles; largest difference of x, v, stress, V, l after 300 steps, relative to the "
        "largest value of each: %.1e" % (len(files_run), d))
d2 = worst(files_run, files_np2)
c.check("3D: 2 ranks equal 1 rank", d2 <= 1e-12, "largest relative difference %.1e" % d2)
vonly3d = write("vonly3d.csv", "x,y,z,V\n0.5,0.5,0.5,8e-6\n0.52,0.5,0.5,1e-6\n")
rows = dump_run(write("vonly3d.opts", "-gimp_dim 3\n-gimp_E 1000\n-gimp_rho 1000\n-gimp_h 0.05\n"
                      "-gimp_domain 0,0,0,1,1,1\n-gimp_body0_shape file\n-gimp_body0_file %s\n"
                      "-ts_max_steps 0\n" % vonly3d), "vonly3d_dump")
ok = len(rows) == 2 and all(abs(float(r["lx"]) - float(r["V"]) ** (1 / 3) / 2) < 1e-15 and
                            float(r["lx"]) == float(r["ly"]) == float(r["lz"]) for r in rows)
c.check("3D, V only: cubes", ok, "; ".join("V %s l %s,%s,%s" % (r["V"], r["lx"], r["ly"], r["lz"])
                                           for r in rows))


# Bad files: each one line naming the option, the file and what is wrong (two at a time).
def check_bad_file(name, text, needle, extra=(), dim=2, opt="-gimp_body0_file"):
    path = os.path.join(W, name.replace(" ", "_") + ".csv")
    if text is not None:
        with open(path, "w") as f:
            f.write(text)
    o = os.path.join(W, name.replace(" ", "_") + ".opts")
    with open(o, "w") as f:
        if dim == 3:
            f.write("-gimp_dim 3\n-gimp_domain 0,0,0,1,1,1\n")
        else:
            f.write("-gimp_domain 0,0,1,1\n")
        f.write("-gimp_E 1000\n-gimp_rho 1000\n-gimp_h 0.05\n"
                "-gimp_body0_shape file\n-gimp_body0_file %s\n-ts_max_steps 1\n" % path)
    p = gimptest.run(args, o, list(extra), expect_ok=False,
                     outdir=os.path.join(W, "bad_" + name.replace(" ", "_")))
    lines = [ln for ln in p.stderr.splitlines() if "error" in ln]
    if extra and opt == "-gimp_body0_file":
        opt = "-gimp_body0_velocity"
    c.check("bad file: " + name, p.returncode != 0 and len(lines) == 1 and
            opt in lines[0] and needle in lines[0],
            "exit %d: %s" % (p.returncode, lines[0] if lines else p.stderr.strip()[-200:]))


later = []


def bad_file(*a):
    later.append(lambda: check_bad_file(*a))


bad_file("missing", None, "cannot open the file")
os.makedirs(os.path.join(W, "a_directory.csv"), exist_ok=True)
bad_file("a_directory", None, "is a directory, not a file")
bad_file("empty", "", "the file is empty")
bad_file("no y", "x,lx,ly\n0.5,0.01,0.01\n", "needs the columns x and y")
bad_file("unknown column", "x,y,V,mass\n0.5,0.5,1e-4,1\n", "unknown column 'mass'")
bad_file("no size", "x,y,vx,vy\n0.5,0.5,0,0\n", "needs lx, ly (half-sizes) or V (volume)")
bad_file("half a pair", "x,y,lx,V\n0.5,0.5,0.01,1e-4\n", "needs both lx and ly")
bad_file("not a number", "x,y,V\n0.5,abc,1e-4\n", "line 2: 'abc' is not a number")
bad_file("NaN", "x,y,V\n0.5,0.5,1e-4\n0.5,nan,1e-4\n", "line 3: the values must be finite")
bad_file("short row", "x,y,V\n0.5,0.5\n", "line 2 has 2 values for 3 columns")
bad_file("zero half-size", "x,y,lx,ly\n0.5,0.5,0,0.01\n", "lx and ly must be > 0")
bad_file("subnormal half-size", "x,y,lx,ly\n0.5,0.5,1e-310,0.01\n",
         "line 2: the particle's size is too small to represent")
bad_file("subnormal volume", "x,y,V\n0.5,0.5,1e-320\n",
         "line 2: the particle's size is too small to represent")
bad_file("no particles", "x,y,V\n", "holds no particle")
bad_file("outside the grid", "x,y,V\n0.5,0.5,1e-4\n1.2,0.5,1e-4\n",
         "particle 1 (data row 2, at 1.2,0.5) is not inside the grid domain")
bad_file("larger than a cell", "x,y,lx,ly\n0.5,0.5,0.01,0.01\n0.3,0.5,0.06,0.01\n",
         "particle 1 (data row 2) has half-sizes 0.06,0.01 larger than the coarsest cell")
bad_file("velocity twice", "x,y,V,vx,vy\n0.5,0.5,1e-4,1,0\n",
         "gives each particle's velocity", ["-gimp_body0_velocity", "0,1"])
good3d = "x,y,z,V\n0.5,0.5,0.5,1e-6\n"
bad_file("3D no z", "x,y,lx,ly,lz\n0.5,0.5,0.01,0.01,0.01\n", "needs the columns x, y and z",
         (), 3)
bad_file("3D unknown column", "x,y,z,V,sxx,syz,mass\n0.5,0.5,0.5,1e-6,0,0,1\n",
         "unknown column 'mass' (columns: x, y, z, lx, ly, lz, V, vx, vy, vz)", (), 3)
bad_file("3D two half-sizes", "x,y,z,lx,ly\n0.5,0.5,0.5,0.01,0.01\n",
         "needs all of lx, ly and lz, or none", (), 3)
bad_file("3D zero half-size", "x,y,z,lx,ly,lz\n0.5,0.5,0.5,0.01,0.01,0\n",
         "lx, ly and lz must be > 0", (), 3)
bad_file("3D outside the grid", good3d + "0.5,0.5,1.2,1e-6\n",
         "particle 1 (data row 2, at 0.5,0.5,1.2) is not inside the grid domain", (), 3)
bad_file("3D larger than a cell", "x,y,z,lx,ly,lz\n0.5,0.5,0.5,0.01,0.01,0.06\n",
         "particle 0 (data row 1) has half-sizes 0.01,0.01,0.06 larger than the coarsest cell",
         (), 3)
bad_file("3D twice", good3d + "0.5,0.5,0.5,1e-6\n",
         "the particles of lines 2 and 3 (at 0.5,0.5,0.5 and 0.5,0.5,0.5) overlap", (), 3)
bad_file("3D velocity twice", "x,y,z,V,vx,vy,vz\n0.5,0.5,0.5,1e-6,1,0,0\n",
         "gives each particle's velocity (vx, vy, vz)", ["-gimp_body0_velocity", "0,1,0"], 3)
bad_file("3D holes", good3d, "a body of shape file has no holes",
         ["-gimp_body0_hole_spheres", "0.5,0.5,0.5,0.1"], 3, "-gimp_body0_hole_spheres")
bad_file("3D ppc", good3d, "does not apply to a body of shape file",
         ["-gimp_body0_ppc", "27"], 3, "-gimp_body0_ppc")
gimptest.concurrently(later)
c.done()
