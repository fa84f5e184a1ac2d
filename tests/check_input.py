"""Bad input stops the run before step 1 with one line naming the option, the value and
what is valid, and a non-zero exit code; nothing is written as if the run had happened."""
import os
import subprocess
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
# Every bad-input case of the scene reader and the setup runs in one process in test_bad_input
# (tests/bad_input/cases2d.tsv, the same cases, in-process). A few of them run here as processes:
# exit code 2 and exactly one line on stderr.
cases = [
    ('unknown option', ['-gimp_dampnig', '10'],
     '-gimp_dampnig'),
    ('negative E', ['-gimp_E', '-1'],
     '-gimp_E -1'),
    ('traction loads nothing', ['-gimp_traction0_range', '5,6'],
     '-gimp_traction0_side right'),
    ('not a number', ['-gimp_E', 'abc'],
     '-gimp_E abc'),
    # a bad viewer that PETSc would read at exit, behind an error the setup meets first
    ('bad -log_view behind another error', ['-log_view', 'nan', '-gimp_E', '-1'],
     '-gimp_E -1'),
    # (read in main, before the scene: a value is read as the flag's)
    ('markdown flag with a value', ['-gimp_options_markdown', 'nan'],
     '-gimp_options_markdown nan: Unknown logical value'),
]
# The cases run two at a time (gimptest.concurrently) once they are all listed.
later = []


def bad_option(name, extra, needle):
    p = gimptest.run(args, "options/patch.opts", extra + ["-ts_max_steps", "1"], expect_ok=False,
                     outdir=os.path.join(args.work, "bad_" + name.replace(" ", "_")))
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    ok = p.returncode != 0 and len(lines) >= 1 and needle in lines[0] and \
        lines[0].startswith(("gimp: error: option", "[0]PETSC ERROR"))
    one_line = len([l for l in lines if "error" in l.lower()]) == 1
    c.check(name, ok and one_line and lines[0].startswith("gimp: error:"),
            "exit %d: %s" % (p.returncode, lines[0] if lines else "(no message)"))


for case in cases:
    later.append(lambda case=case: bad_option(*case))

# Valid cracks (a mouth outside the body, kinked; one wholly inside) are read and their options
# used: the run goes on.
p = gimptest.run(args, "options/patch.opts",
                 ["-ts_max_steps", "1", "-gimp_cracks", "2", "-gimp_crack0_points",
                  "-0.1,0.2,0.3,0.2,0.45,0.25", "-gimp_crack1_points", "0.8,0.1,0.8,0.3"],
                 expect_ok=False, outdir=os.path.join(args.work, "cracks_ok"))
c.check("valid cracks accepted", p.returncode == 0,
        "exit %d: %s" % (p.returncode, p.stderr.strip()[-200:]))

# -gimp_options_markdown false runs the scene (the flag's value is read, not only its name).
p = gimptest.run(args, "options/patch.opts", ["-ts_max_steps", "1", "-gimp_options_markdown",
                                              "false"], expect_ok=False,
                 outdir=os.path.join(args.work, "markdown_false"))
ran = p.returncode == 0 and os.path.exists(os.path.join(args.work, "markdown_false",
                                                        "summary.json"))
c.check("-gimp_options_markdown false runs the scene", ran and "| option |" not in p.stdout,
        "exit %d, summary.json written: %s" % (p.returncode, ran))

# -options_file errors are found before PETSc starts: one line, exit 2, no PETSc trace; under
# mpiexec every rank finds the same error and only rank 0 prints it.
opts = os.path.join(args.work, "opts")
os.makedirs(os.path.join(opts, "dir.opts"), exist_ok=True)
with open(os.path.join(opts, "self.opts"), "w") as f:
    f.write("-gimp_damping 10\n-options_file self.opts\n")
file_cases = [
    # (name, options after patch.opts, text the error line must contain)
    ("options file missing", ["-options_file", "does_not_exist.opts"],
     "option -options_file does_not_exist.opts: cannot open the file"),
    ("options file is a directory", ["-options_file", os.path.join(opts, "dir.opts")],
     "is a directory"),
    ("options file includes itself", ["-options_file", os.path.join(opts, "self.opts")],
     "includes itself: %s -> %s" % ((os.path.join(opts, "self.opts"),) * 2)),
    ("options file without a name", ["-ts_max_steps", "1", "-options_file"],
     "option -options_file: missing the file name"),
]


def bad_file(name, extra, needle, ranks):
    p = gimptest.run(args, "options/patch.opts", extra, ranks=ranks, expect_ok=False,
                     outdir=os.path.join(args.work,
                                         "bad_%s_np%d" % (name.replace(" ", "_"), ranks)))
    lines = [l for l in p.stderr.splitlines() if l.startswith("gimp:") or "PETSC" in l or
             "MPI_ABORT" in l]
    c.check("%s (%d rank%s)" % (name, ranks, "s" if ranks > 1 else ""),
            p.returncode != 0 and len(lines) == 1 and lines[0].startswith("gimp: error:") and
            needle in lines[0],
            "exit %d: %s" % (p.returncode, " | ".join(lines) if lines else "(no message)"))


for name, extra, needle in file_cases:
    for ranks in (1, 2):
        later.append(lambda a=(name, extra, needle, ranks): bad_file(*a))

# Failures found on one rank (rank 0 creates the output directory and writes the files) end
# every rank with the same one line: no rank waits forever in a collective call.
blocker = os.path.join(args.work, "a_file")
with open(blocker, "w") as f:
    f.write("not a directory\n")
rank0_cases = [
    ("output directory under a file", ["-gimp_output_dir", os.path.join(blocker, "out")],
     "option -gimp_output_dir %s: cannot create it" % os.path.join(blocker, "out")),
    ("particle dump under a file", ["-gimp_particle_dump", os.path.join(blocker, "p.csv")],
     "option -gimp_particle_dump %s: " % os.path.join(blocker, "p.csv")),
    ("grid dump under a file", ["-gimp_grid_dump", os.path.join(blocker, "g.csv")],
     "option -gimp_grid_dump %s: %s is not a directory that exists"
     % (os.path.join(blocker, "g.csv"), blocker)),
]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def rank0_failure(name, extra, needle, ranks):
    cmd = [args.gimp, "-options_file", os.path.join(args.root, "options", "patch.opts"),
           "-ts_max_steps", "2"]
    if "-gimp_output_dir" not in extra:
        cmd += ["-gimp_output_dir",
                os.path.join(args.work, "rank0_ok_%s_np%d" % (name.replace(" ", "_"), ranks))]
    cmd += extra
    if ranks > 1:
        cmd = [args.mpiexec, "-n", str(ranks)] + cmd
    try:
        p = subprocess.run(cmd, cwd=args.work, capture_output=True, text=True, env=env,
                           timeout=120)
        rc, err = p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        rc, err = None, "(hung: killed after 120 s)"
    lines = [l for l in err.splitlines() if l.startswith("gimp:") or "PETSC" in l]
    c.check("%s (%d rank%s)" % (name, ranks, "s" if ranks > 1 else ""),
            rc == 2 and len(lines) == 1 and needle in lines[0],
            "exit %s: %s" % (rc, " | ".join(lines) if lines else err.strip()[-200:]))


for name, extra, needle in rank0_cases:
    for ranks in (1, 2):
        later.append(lambda a=(name, extra, needle, ranks): rank0_failure(*a))
gimptest.concurrently(later)

# A scene that includes another (plate_static.opts includes plate.opts) runs from any working
# directory: here the work directory, the scene named by an absolute and a relative path.
out = os.path.join(args.work, "plate_static_abs")
s = gimptest.summary(gimptest.run(args, "options/plate_static.opts", ["-ts_max_steps", "1"],
                                  outdir=out))
c.check("nested options file, absolute name", s["scene"] == "plate_static" and s["steps"] == 1,
        "scene %s, %d steps" % (s["scene"], s["steps"]))
rel = os.path.relpath(os.path.join(args.root, "options", "plate_static.opts"), args.work)
out = os.path.join(args.work, "plate_static_rel")
p = subprocess.run([args.mpiexec, "-n", "2", args.gimp, "-options_file", rel, "-ts_max_steps",
                    "1", "-gimp_output_dir", out], cwd=args.work, capture_output=True, text=True,
                   env=dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1",
                            OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1"))
s = gimptest.summary(out) if p.returncode == 0 else {"scene": p.stderr.strip()[-200:], "steps": 0}
c.check("nested options file, relative name, 2 ranks",
        p.returncode == 0 and s["scene"] == "plate_static" and s["steps"] == 1,
        "%s from %s: exit %d, scene %s, %d steps" % (rel, args.work, p.returncode, s["scene"],
                                                     s["steps"]))

# A run that fails mid-way (a particle leaves the grid) stops, says where and when, exits
# non-zero and keeps what it wrote.
out = os.path.join(args.work, "leaves")
p = gimptest.run(args, "options/drift.opts", ["-ts_max_steps", "3000"], expect_ok=False, outdir=out)
lines = [l for l in p.stderr.splitlines() if l.strip()]
c.check("particle leaves grid", p.returncode == 3 and len(lines) == 1 and "step" in lines[0] and
        "particle" in lines[0] and "left the grid" in lines[0],
        "exit %d: %s" % (p.returncode, lines[0] if lines else "(no message)"))
s = gimptest.summary(out)
h = gimptest.history(out)
c.check("outputs kept", s["status"] == "unstable" and len(h["time"]) > 10 and
        os.path.exists(os.path.join(out, "fields.h5")),
        "summary status %s, %d history rows" % (s["status"], len(h["time"])))
c.done()
