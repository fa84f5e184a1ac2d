"""Bodies from particle files (-gimp_bodyK_shape file; docs/options.md, docs/validation.md
"Bodies from particle files").

The colliding disks written as two particle files (the particles gimp seeds for
options/disks.opts, from its particle dump) run exactly as the disks described by circles,
through the impact, on 1 and 2 ranks; a file with V but no half-sizes gives square domains of
that area; and every kind of bad file stops the run with one line naming the option, the file
and what is wrong."""
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
    return (float(r["x"]), float(r["y"]))


def worst(a, b):
    """The largest difference of each quantity relative to its largest value."""
    a, b = sorted(a, key=key), sorted(b, key=key)
    if len(a) != len(b):
        return float("inf")
    out = 0.0
    for k in ("x", "y", "vx", "vy", "sxx", "syy", "sxy", "V", "lx", "ly"):
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


# Bad files: each one line naming the option, the file and what is wrong (two at a time).
def check_bad_file(name, text, needle, extra=()):
    path = os.path.join(W, name.replace(" ", "_") + ".csv")
    if text is not None:
        with open(path, "w") as f:
            f.write(text)
    o = os.path.join(W, name.replace(" ", "_") + ".opts")
    with open(o, "w") as f:
        f.write("-gimp_E 1000\n-gimp_rho 1000\n-gimp_h 0.05\n-gimp_domain 0,0,1,1\n"
                "-gimp_body0_shape file\n-gimp_body0_file %s\n-ts_max_steps 1\n" % path)
    p = gimptest.run(args, o, list(extra), expect_ok=False,
                     outdir=os.path.join(W, "bad_" + name.replace(" ", "_")))
    lines = [ln for ln in p.stderr.splitlines() if "error" in ln]
    opt = "-gimp_body0_velocity" if extra else "-gimp_body0_file"
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
gimptest.concurrently(later)
c.done()
