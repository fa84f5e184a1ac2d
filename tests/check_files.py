"""Files and names, as processes, serial and on 2 ranks (the in-process cases are in
tests/bad_input/*.tsv).

- A long scene (about 500 kB: polygon bodies of 200 vertices and many probes) runs on one rank
  and under mpiexec alike, with the same summary; an option after the file still overrides it,
  one before it does not; a scene with more options than PETSc's database holds is one line.
- A relative particle-file path in an options file is read beside that file; a UTF-8
  byte-order mark is accepted; a file whose particles are all there twice is one line.
- A scene name that is not a plain file name is one line, and nothing is written.
- Every path the run writes is checked at setup, in 2D and 3D: one line naming the option, the
  path and the reason, before any step (no run that is lost at the end)."""
import math
import os
import shutil
import subprocess
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
PATCH = os.path.join(args.root, "options", "patch.opts")
PATCH3D = os.path.join(args.root, "options", "patch3d.opts")


def gimp(opts, ranks=1, cwd=W, timeout=120):
    """(exit code or None on timeout, stderr) of gimp with the options."""
    cmd = [args.gimp] + opts
    if ranks > 1:
        cmd = [args.mpiexec, "-n", str(ranks)] + cmd
    try:
        p = subprocess.run(cmd, cwd=cwd, env=ENV, capture_output=True, text=True,
                           timeout=timeout)
        return p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        return None, "(hung: killed after %d s)" % timeout


def one_line(name, opts, needle, ranks=(1, 2), cwd=W):
    """Exit 2 and exactly one line, `gimp: error:` holding needle, on each rank count."""
    for n in ranks:
        rc, err = gimp(opts, n, cwd)
        lines = [l for l in err.splitlines() if l.startswith("gimp:") or "PETSC" in l or
                 "MPI_ABORT" in l or "An error occurred" in l]
        c.check("%s (%d rank%s)" % (name, n, "s" if n > 1 else ""),
                rc == 2 and len(lines) == 1 and lines[0].startswith("gimp: error: ") and
                needle in lines[0],
                "exit %s: %s" % (rc, " | ".join(lines)[:400] if lines else err.strip()[-300:]))


def runs(name, opts, out, ranks=1, cwd=W):
    """Run to the end into out; the summary, or None (with a failed check)."""
    shutil.rmtree(out, ignore_errors=True)
    rc, err = gimp(opts + ["-gimp_output_dir", out], ranks, cwd)
    if rc != 0:
        c.check(name, False, "exit %s: %s" % (rc, err.strip()[-400:]))
        return None
    return gimptest.summary(out)


# --- a long scene --------------------------------------------------------------------------
def long_scene(path, bodies=64, probes=200):
    """Polygon bodies of 200 vertices written to 17 decimals, and probes: about 500 kB."""
    lines = ["-gimp_E 1e7", "-gimp_nu 0.3", "-gimp_rho 1000", "-gimp_h 0.1", "-ts_dt 1e-4",
             "-ts_max_steps 3", "-gimp_history_interval 1", "-gimp_bodies %d" % bodies]
    for k in range(bodies):
        cx, cy = 0.5 + k % 8, 0.5 + k // 8
        xy = []
        for i in range(200):
            a = 2 * math.pi * i / 200
            xy += ["%.17f" % (cx + 0.3 * math.cos(a)), "%.17f" % (cy + 0.3 * math.sin(a))]
        lines += ["-gimp_body%d_shape polygon" % k, "-gimp_body%d_polygon %s" % (k, ",".join(xy)),
                  "-gimp_body%d_velocity %.1f,0" % (k, 0.1 * (k % 3))]
    lines.append("-gimp_probes %d" % probes)
    for k in range(probes):
        lines.append("-gimp_probe%d_x %.17f,%.17f" % (k, 0.5 + k % 8, 0.5 + (k // 8) % 8))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return os.path.getsize(path)


def differences(a, b, path=""):
    """Where two summaries differ beyond round-off (run facts that depend on ranks left out)."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return [path + " keys"]
        skip = ("ranks", "wall_seconds", "setup_seconds", "cpu_seconds",
                "particle_steps_per_second")
        return [d for k in a if k not in skip for d in differences(a[k], b[k], path + "/" + k)]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [path + " length"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, "%s[%d]" %
                                                                             (path, i))]
    if isinstance(a, float) or isinstance(b, float):
        ok = abs(a - b) <= 1e-9 * max(abs(a), abs(b)) + 1e-20
        return [] if ok else ["%s %r != %r" % (path, a, b)]
    return [] if a == b else ["%s %r != %r" % (path, a, b)]


big = os.path.join(W, "long.opts")
size = long_scene(big)
serial = runs("long scene, 1 rank", ["-options_file", big], os.path.join(W, "long1"))
two = runs("long scene, 2 ranks", ["-options_file", big], os.path.join(W, "long2"), ranks=2)
if serial and two:
    diff = differences(serial, two)
    c.check("long scene (%d kB): the same summary on 1 and 2 ranks" % (size // 1024),
            not diff and serial["steps"] == 3 and serial["particles"] > 0,
            "%d particles, %d probes, %d steps; %s" % (
                serial["particles"], len(serial["probes"]), serial["steps"],
                "; ".join(diff[:3]) if diff else "no difference beyond round-off"))
# The last occurrence wins: -gimp_history_interval 2 before the file is the file's 1; after it,
# 2 (history rows at steps 0, 1, 2, 3 against 0, 2, 3).
rows = []
for order in (["-gimp_history_interval", "2", "-options_file", big],
              ["-options_file", big, "-gimp_history_interval", "2"]):
    out = os.path.join(W, "long_order")
    s = runs("long scene, option order", order, out)
    rows.append(gimptest.history(out)["step"] if s else [])
c.check("an option after the file overrides it, one before does not",
        rows == [[0, 1, 2, 3], [0, 2, 3]], "history steps %s" % rows)
many = os.path.join(W, "many.opts")
long_scene(many, bodies=64, probes=600)
one_line("more options than PETSc holds", ["-options_file", many],
         "different options, more than PETSc's options database holds")

# --- particle files ------------------------------------------------------------------------
scenes = os.path.join(W, "scenes")
os.makedirs(scenes, exist_ok=True)
body = ("-gimp_E 1e7\n-gimp_nu 0.3\n-gimp_rho 1000\n-gimp_h 0.1\n-gimp_domain 0,0,1,1\n"
        "-gimp_body0_shape file\n-gimp_body0_file %s\n-ts_dt 1e-4\n-ts_max_steps 2\n")
rows = ["%.3f,%.3f,0.025,0.025" % (0.425 + 0.05 * i, 0.425 + 0.05 * j)
        for i in range(4) for j in range(4)]
with open(os.path.join(scenes, "disk.csv"), "w") as f:
    f.write("x,y,lx,ly\n" + "\n".join(rows) + "\n")
with open(os.path.join(scenes, "bom.csv"), "wb") as f:
    f.write(b"\xef\xbb\xbfx,y,lx,ly\n" + ("\n".join(rows) + "\n").encode())
with open(os.path.join(scenes, "twice.csv"), "w") as f:
    f.write("x,y,lx,ly\n" + "\n".join(rows + rows) + "\n")
for name in ("disk", "bom", "twice"):
    with open(os.path.join(scenes, name + ".opts"), "w") as f:
        f.write(body % (name + ".csv"))
elsewhere = os.path.join(W, "elsewhere")
os.makedirs(elsewhere, exist_ok=True)
for n in (1, 2):
    s = runs("particle file beside its options file (%d ranks)" % n,
             ["-options_file", "../scenes/disk.opts"], os.path.join(W, "beside"), n, elsewhere)
    if s:
        c.check("particle file beside its options file (%d ranks)" % n, s["particles"] == 16,
                "run from %s: %d particles" % (elsewhere, s["particles"]))
s = runs("UTF-8 byte-order mark", ["-options_file", os.path.join(scenes, "bom.opts")],
         os.path.join(W, "bom"))
if s:
    c.check("UTF-8 byte-order mark accepted", s["particles"] == 16, "%d particles" % s["particles"])
one_line("particle file appended to itself", ["-options_file", os.path.join(scenes, "twice.opts")],
         "option -gimp_body0_file %s: the particles of lines 2 and 18 (at 0.425,0.425 and "
         "0.425,0.425) overlap" % os.path.join(scenes, "twice.csv"))

# --- scene names ---------------------------------------------------------------------------
deep = os.path.join(W, "a", "b")
os.makedirs(deep, exist_ok=True)
shutil.rmtree(os.path.join(W, "a", "x"), ignore_errors=True)
for name in ("../../x", "a/b", ".."):
    one_line("scene name %s" % name, ["-options_file", PATCH, "-gimp_scene", name,
                                      "-ts_max_steps", "1"],
             "option -gimp_scene %s: a scene name is a plain file name" % name, cwd=deep)
c.check("no output outside output/", not os.path.exists(os.path.join(W, "a", "x")) and
        not os.path.exists(os.path.join(deep, "output")),
        "%s: %s" % (deep, sorted(os.listdir(deep))))

# --- output paths, checked at setup --------------------------------------------------------
blocker = os.path.join(W, "a_file")
with open(blocker, "w") as f:
    f.write("not a directory\n")
fifo = os.path.join(W, "fifo.csv")
if not os.path.exists(fifo):
    os.mkfifo(fifo)
out = os.path.join(W, "paths_out")
path_cases = [
    ("particle dump on a device", ["-gimp_particle_dump", "/dev/full"],
     "option -gimp_particle_dump /dev/full: is not a regular file"),
    ("particle dump on a pipe", ["-gimp_particle_dump", fifo],
     "option -gimp_particle_dump %s: is not a regular file" % fifo),
    ("grid dump on a device", ["-gimp_grid_dump", "/dev/full"],
     "option -gimp_grid_dump /dev/full: is not a regular file"),
    ("particle dump in no directory", ["-gimp_particle_dump", os.path.join(blocker, "p.csv")],
     "option -gimp_particle_dump %s: %s is not a directory that exists"
     % (os.path.join(blocker, "p.csv"), blocker)),
    ("particle dump is history.csv", ["-gimp_particle_dump", os.path.join(out, "history.csv")],
     "is the output directory's history.csv"),
    ("grid dump is the particle dump", ["-gimp_particle_dump", os.path.join(W, "d.csv"),
                                        "-gimp_grid_dump", os.path.join(W, ".", "d.csv")],
     "option -gimp_grid_dump %s: is the -gimp_particle_dump file too"
     % os.path.join(W, ".", "d.csv")),
    ("particle dump is the checkpoint read", ["-gimp_restart", os.path.join(W, "ck.h5"),
                                              "-gimp_particle_dump", os.path.join(W, "ck.h5")],
     "is the file -gimp_restart reads"),
    ("output directory under a file", ["-gimp_output_dir", os.path.join(blocker, "out")],
     "option -gimp_output_dir %s: cannot create it (%s is not a directory)"
     % (os.path.join(blocker, "out"), blocker)),
]
for scene, dim in ((PATCH, "2D"), (PATCH3D, "3D")):
    for name, extra, needle in path_cases:
        one_line("%s, %s" % (name, dim), ["-options_file", scene, "-ts_max_steps", "1",
                                          "-gimp_output_dir", out] + extra, needle)
c.done()
