"""Bad input and faults (docs/validation.md, "Bad input and faults"): every case ends with
exactly one line `gimp: error: ...` on stderr naming the option or file and the value, and
nothing else on stderr (no PETSc or HDF5 stack, no MPI abort text); a non-zero exit that is not
a signal; within the timeout (no rank waits forever). Cases found on one rank run under
mpiexec -n 2. Full-disk cases keep what was written before the failure valid, and a reused
output directory holds no file of an earlier run."""
import concurrent.futures
import json
import os
import re
import shutil
import subprocess
import sys
import time
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
PATCH = os.path.join(args.root, "options", "patch.opts")
PLATE = os.path.join(args.root, "options", "plate.opts")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
TIMEOUT = 30
t_start = time.time()
# Open MPI's launcher adds a notice of its own when a rank exits non-zero; -q keeps it quiet, so
# that stderr holds only what gimp wrote.
launcher = subprocess.run([args.mpiexec, "--version"], capture_output=True, text=True)
QUIET = ["-q"] if "Open MPI" in launcher.stdout + launcher.stderr or \
    "OpenRTE" in launcher.stdout + launcher.stderr else []
# A full disk: the file size limit applies to gimp only (not to the launcher), SIGXFSZ ignored
# so that a write past it fails with EFBIG; MPI's own shared-memory files are avoided so that
# only gimp's outputs meet the limit.
LIMITED = ("import os, resource, signal, sys\n"
           "signal.signal(signal.SIGXFSZ, signal.SIG_IGN)\n"
           "n = int(sys.argv[1])\n"
           "resource.setrlimit(resource.RLIMIT_FSIZE, (n, n))\n"
           "os.execv(sys.argv[2], sys.argv[2:])\n")
FULL_ENV = dict(ENV, PMIX_MCA_gds="hash", OMPI_MCA_btl="self,tcp")


def gimp(opts, ranks=1, fsize=None, outdir=None):
    """Run gimp with the options (under a file size limit of fsize bytes if given); return
    (returncode or None on timeout, stderr, seconds)."""
    cmd = [args.gimp] + opts
    if outdir is not None:
        cmd += ["-gimp_output_dir", outdir]
    if fsize is not None:  # under the launcher even on one rank: the limit is gimp's alone
        cmd = [sys.executable, "-c", LIMITED, str(fsize)] + cmd
    if ranks > 1 or fsize is not None:
        cmd = [args.mpiexec] + QUIET + ["-n", str(ranks)] + cmd
    t0 = time.time()
    try:
        p = subprocess.run(cmd, cwd=W, env=FULL_ENV if fsize is not None else ENV,
                           capture_output=True, text=True, timeout=TIMEOUT, errors="replace")
        return p.returncode, p.stderr, time.time() - t0
    except subprocess.TimeoutExpired:
        return None, "(hung: killed after %d s)" % TIMEOUT, time.time() - t0


def expect_one_line(name, opts, needles, ranks=1, fsize=None, outdir=None, result=None):
    """Exactly one non-empty stderr line, `gimp: error:` holding every needle; exit > 0."""
    rc, err, sec = result or gimp(opts, ranks, fsize, outdir if outdir else os.path.join(W, "bad"))
    lines = [l for l in err.splitlines() if l.strip()]
    ok = rc is not None and rc > 0 and len(lines) == 1 and lines[0].startswith("gimp: error: ")
    ok = ok and all(n in lines[0] for n in needles)
    shown = " | ".join(lines[:3]) if lines else "(no message)"
    c.check("%s%s" % (name, " (2 ranks)" if ranks > 1 else ""), ok,
            "exit %s, %.1f s: %s%s" % (rc, sec, shown[:300], " ..." if len(lines) > 3 else ""))
    return lines


def expect_all(cases):
    """expect_one_line for serial cases (name, options, needles), two runs at a time, each in
    its own output directory (the cases fail before writing anything)."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        runs = [pool.submit(gimp, o, 1, None, os.path.join(W, "bad%d" % (i % 2)))
                for i, (_, o, _) in enumerate(cases)]
        for (name, o, needles), run in zip(cases, runs):
            expect_one_line(name, o, needles, result=run.result())


def patch(*extra):
    return ["-options_file", PATCH, "-ts_max_steps", "1"] + list(extra)


def plate(*extra):
    return ["-options_file", PLATE, "-ts_max_steps", "1"] + list(extra)


# --- values: NaN and inf in every kind of real option, extra or missing values -----------------
value_cases = [
    ("E inf (not -ts_dt)", patch("-gimp_E", "inf"), ["-gimp_E inf", "finite"]),
    ("nu nan", patch("-gimp_nu", "nan"), ["-gimp_nu nan"]),
    ("rho inf", patch("-gimp_rho", "inf"), ["-gimp_rho inf"]),
    ("thickness inf", patch("-gimp_thickness", "inf"), ["-gimp_thickness inf"]),
    ("damping nan", patch("-gimp_damping", "nan"), ["-gimp_damping nan"]),
    ("cfl nan", patch("-gimp_cfl", "nan"), ["-gimp_cfl nan"]),
    ("h inf", patch("-gimp_h", "inf"), ["-gimp_h inf"]),
    ("box nan", patch("-gimp_body0_box", "0,0,1,nan"), ["-gimp_body0_box 0,0,1,nan"]),
    ("box overflow to inf", patch("-gimp_body0_box", "0,0,1e999,0.4"),
     ["-gimp_body0_box 0,0,1e999,0.4"]),
    ("domain inf", patch("-gimp_domain", "-0.2,-0.2,inf,0.6"), ["-gimp_domain"]),
    ("hole with nan centre", patch("-gimp_body0_holes", "nan,0.2,0.1"),
     ["-gimp_body0_holes nan,0.2,0.1"]),
    ("velocity inf", patch("-gimp_body0_velocity", "inf,0"), ["-gimp_body0_velocity inf,0"]),
    ("probe at nan", patch("-gimp_probe0_x", "nan,0.2"), ["-gimp_probe0_x nan,0.2"]),
    ("traction nan", patch("-gimp_traction0_value", "nan,0"), ["-gimp_traction0_value nan,0"]),
    ("gravity inf", patch("-gimp_gravity", "0,-inf"), ["-gimp_gravity 0,-inf"]),
    ("penalty nan", patch("-gimp_penalty", "nan"), ["-gimp_penalty nan"]),
    ("ramp nan", patch("-gimp_traction0_ramp", "0,0,nan,1"), ["-gimp_traction0_ramp 0,0,nan,1"]),
    ("static min time nan", patch("-gimp_static_min_time", "nan"), ["-gimp_static_min_time nan"]),
    ("hole measure nan", patch("-gimp_hole_measure", "0.5,0.2,nan", "-gimp_hole_measure_load",
                               "1e4"), ["-gimp_hole_measure 0.5,0.2,nan"]),
    ("dt nan", patch("-ts_dt", "nan"), ["-ts_dt nan"]),
    ("max time nan", patch("-ts_max_time", "nan"), ["-ts_max_time nan"]),
    ("box with 5 values", patch("-gimp_body0_box", "0,0,1,0.4,7"),
     ["-gimp_body0_box 0,0,1,0.4,7", "4 values"]),
    ("gravity with 3 values", patch("-gimp_gravity", "0,-9.8,0"), ["-gimp_gravity 0,-9.8,0"]),
    ("probe with 3 values", patch("-gimp_probe0_x", "0.5,0.2,0"), ["-gimp_probe0_x 0.5,0.2,0"]),
    ("domain with 5 values", patch("-gimp_domain", "-0.2,-0.2,1.2,0.6,1"),
     ["-gimp_domain -0.2,-0.2,1.2,0.6,1"]),
    ("damping without value", patch("-gimp_damping"), ["-gimp_damping", "needs a value"]),
    ("E without value", patch("-gimp_E"), ["-gimp_E", "needs a value"]),
    ("box without value", patch("-gimp_body0_box"), ["-gimp_body0_box", "needs a value"]),
    ("dt without value", patch("-ts_dt"), ["-ts_dt", "needs a value"]),
    ("negative step count", patch("-ts_max_steps", "-5"), ["-ts_max_steps -5"]),
    ("ppc beyond PetscInt", patch("-gimp_body0_ppc", "99999999999"),
     ["-gimp_body0_ppc 99999999999"]),
    ("unstable dt names dt", patch("-ts_dt", "1"), ["-ts_dt 1", "stable limit"]),
    # options that would do nothing: refused, not dropped
    ("hole measure load without the measure", patch("-gimp_hole_measure_load", "1e4"),
     ["-gimp_hole_measure_load 10000", "no effect without -gimp_hole_measure"]),
    ("wavenumber without sine_x", patch("-gimp_body0_wavenumber", "3"),
     ["-gimp_body0_wavenumber 3", "no effect without -gimp_body0_velocity_profile sine_x"]),
    ("penalty without penalty conditions", patch("-gimp_penalty", "1e9"),
     ["-gimp_penalty 1e9", "acts only with penalty conditions"]),
    ("penalty traction without penalty conditions", patch("-gimp_penalty_traction", "false"),
     ["-gimp_penalty_traction false", "acts only with penalty conditions"]),
    ("a word in a box", patch("-gimp_body0_box", "0,0,abc,0.4"),
     ["-gimp_body0_box 0,0,abc,0.4", "element 3 (abc)"]),
    ("a word in gravity", patch("-gimp_gravity", "0,x"), ["-gimp_gravity 0,x", "element 2"]),
    ("a word in a level box", patch("-gimp_levels", "2", "-gimp_level1_box", "0,0,0.5,0.4x"),
     ["-gimp_level1_box 0,0,0.5,0.4x", "element 4"]),
    ("an empty element in a box", patch("-gimp_body0_box", "0,0,,1,0.4"),
     ["-gimp_body0_box 0,0,,1,0.4", "element 3 is empty"]),
    ("a trailing comma", patch("-gimp_body0_box", "0,0,1,0.4,"),
     ["-gimp_body0_box 0,0,1,0.4,", "element 5 is empty"]),
    ("gravity a comma", patch("-gimp_gravity", ","), ["-gimp_gravity ,", "element 1 is empty"]),
    ("interpolated final time", patch("-ts_exact_final_time", "interpolate", "-ts_max_time",
                                      "0.01"), ["-ts_exact_final_time interpolate", "matchstep"]),
    ("one file for both dumps", patch("-gimp_particle_dump", "d.csv", "-gimp_grid_dump", "d.csv"),
     ["-gimp_grid_dump d.csv", "-gimp_particle_dump"]),
]
expect_all(value_cases)

# --- problem size: estimated before anything is allocated ---------------------------------------
size_cases = [
    ("box typed 1e6 for 1", patch("-gimp_body0_box", "0,0,1e6,0.4"),
     ["-gimp_body0_box", "particles", "GB"]),
    ("h = 1e-9", patch("-gimp_h", "1e-9"), ["-gimp_h 1e-09", "nodes"]),
    ("pad of 1e9", patch("-gimp_pad", "1000000000"), ["-gimp_pad 1000000000", "nodes"]),
    ("ppc 4096 on the plate, 1 GB limit", plate("-gimp_body0_ppc", "4096",
                                                "-gimp_memory_limit", "1e9"),
     ["-gimp_body0_ppc 4096", "GB", "-gimp_memory_limit"]),
    ("memory limit nan", patch("-gimp_memory_limit", "nan"), ["-gimp_memory_limit nan"]),
]
expect_all(size_cases)

# --- options files ---------------------------------------------------------------------------
opts = os.path.join(W, "opts")
os.makedirs(os.path.join(opts, "dir.opts"), exist_ok=True)
files = {
    "self.opts": b"-gimp_damping 10\n-options_file self.opts\n",
    "binary.opts": b"-gimp_E 1e7\n\x00\x01\x02\xff\n",
    "bom.opts": b"\xef\xbb\xbf-gimp_damping 300\n",
    "commas.opts": b"-gimp_domain -0.2, -0.2, 1.2, 0.6\n",
    "nextline.opts": b"-gimp_damping\n300\n",
    "latin1.opts": b"-gimp_scene caf\xe9\n-gimp_damping 300\n",
}
for fname, content in files.items():
    with open(os.path.join(opts, fname), "wb") as f:
        f.write(content)
file_cases = [
    ("options file missing", ["-options_file", "nope.opts"],
     ["-options_file nope.opts", "cannot open"]),
    ("options file is a directory", ["-options_file", os.path.join(opts, "dir.opts")],
     ["dir.opts", "is a directory"]),
    ("options file binary", patch("-options_file", os.path.join(opts, "binary.opts")),
     ["binary.opts", "not a text file"]),
    ("options file includes itself", patch("-options_file", os.path.join(opts, "self.opts")),
     ["self.opts", "includes itself"]),
    ("options file without a name", patch("-options_file"), ["-options_file", "missing the file"]),
    ("spaces after commas", patch("-options_file", os.path.join(opts, "commas.opts")),
     ["commas.opts", "line 1", "-gimp_domain"]),
    ("value on the next line", patch("-options_file", os.path.join(opts, "nextline.opts")),
     ["nextline.opts", "line 2", "300"]),
]
expect_all(file_cases)
# A UTF-8 byte-order mark is skipped: the file's options apply.
bom_out = os.path.join(W, "bom")
rc, err, _ = gimp(patch("-options_file", os.path.join(opts, "bom.opts")), outdir=bom_out)
c.check("options file with a UTF-8 byte-order mark is read", rc == 0, "exit %s %s" % (rc, err[-200:]))

# --- failures found on one rank, under MPI ------------------------------------------------------
blocker = os.path.join(W, "a_file")
with open(blocker, "w") as f:
    f.write("not a directory\n")
a_dir = os.path.join(W, "a_dir")
os.makedirs(a_dir, exist_ok=True)
ok_out = os.path.join(W, "rank0_ok")
rank_cases = [
    ("output directory is a file", patch(), ["-gimp_output_dir " + blocker], blocker),
    ("output directory under a file", patch(), ["-gimp_output_dir " + blocker + "/out"],
     blocker + "/out"),
    ("particle dump under a file", patch("-gimp_particle_dump", blocker + "/p.csv"),
     ["-gimp_particle_dump " + blocker + "/p.csv"], ok_out),
    ("particle dump is a directory", patch("-gimp_particle_dump", a_dir),
     ["-gimp_particle_dump " + a_dir], ok_out),
    ("grid dump under a file", patch("-gimp_grid_dump", blocker + "/g.csv"),
     ["-gimp_grid_dump " + blocker + "/g.csv"], ok_out),
    ("grid dump is a directory", patch("-gimp_grid_dump", a_dir), ["-gimp_grid_dump " + a_dir],
     ok_out),
    ("particle dump on a device", patch("-gimp_particle_dump", "/dev/full"),
     ["-gimp_particle_dump /dev/full", "not a regular file"], ok_out),
    ("grid dump on a device", patch("-gimp_grid_dump", "/dev/full"),
     ["-gimp_grid_dump /dev/full", "not a regular file"], ok_out),
]
for name, o, needles, out in rank_cases:
    for ranks in (1, 2) if "full disk" in name else (2,):
        expect_one_line(name, o, needles, ranks=ranks, outdir=out)


# --- a full disk for the output directory: a file size limit (EFBIG) ---------------------------
for name, nbytes, needles in [
        ("history.csv on a full disk", 0, ["-gimp_output_dir", "history.csv"]),
        ("fields.h5 on a full disk", 1500000, ["-gimp_output_dir", "fields.h5"])]:
    for ranks in (1, 2):
        out = os.path.join(W, "full")
        shutil.rmtree(out, ignore_errors=True)
        expect_one_line(name, patch("-ts_max_steps", "200", "-gimp_output_interval", "20"),
                        needles, ranks=ranks, fsize=nbytes, outdir=out)
        if nbytes:
            h = gimptest.history(out)
            c.check("%s: history.csv before the failure is whole (%d ranks)" % (name, ranks),
                    len(h["step"]) >= 1 and h["step"] == sorted(h["step"]),
                    "%d rows" % len(h["step"]))
            c.check("%s: no summary.json (%d ranks)" % (name, ranks),
                    not os.path.exists(os.path.join(out, "summary.json")), "")
            # The frames before the failure: every one the XDMF file lists is in fields.h5.
            try:
                import h5py
                with h5py.File(os.path.join(out, "fields.h5"), "r") as h5:
                    groups = sorted(h5["particles"])
                    xmf = open(os.path.join(out, "particles.xmf")).read()
                    listed = sorted(set(re.findall(r"fields\.h5:/particles/(step_\d+)/", xmf)))
                    ok = len(groups) >= 1 and listed == groups and all(
                        h5["particles/%s/x" % g].shape[0] == 160 for g in groups)
                    detail = "%d frames, xmf lists %d" % (len(groups), len(listed))
            except (OSError, KeyError, ImportError) as e:
                ok, detail = False, str(e)
            c.check("%s: earlier frames readable (%d ranks)" % (name, ranks), ok, detail)

# A checkpoint that does not fit (it holds every particle field: about twice a frame) stops the
# run with one line before HDF5 writes it; the frames before stay, no checkpoint.h5.tmp is left.
for ranks in (1, 2):
    out = os.path.join(W, "full_ckpt")
    shutil.rmtree(out, ignore_errors=True)
    expect_one_line("checkpoint.h5 on a full disk",
                    patch("-gimp_body0_ppc", "256", "-ts_max_steps", "4",
                          "-gimp_checkpoint_interval", "2"),
                    ["-gimp_output_dir", "checkpoint.h5 at step 2"], ranks=ranks, fsize=6000000,
                    outdir=out)
    left = sorted(os.listdir(out)) if os.path.isdir(out) else []
    c.check("checkpoint.h5 on a full disk: fields.h5 kept, no checkpoint file (%d ranks)" % ranks,
            "fields.h5" in left and not any(f.startswith("checkpoint") for f in left),
            " ".join(left))

# --- summary.json: valid JSON, strings escaped; no stale files in a reused directory -----------
reuse = os.path.join(W, "reuse")
shutil.rmtree(reuse, ignore_errors=True)
probe = 'a\\b'
rc, err, _ = gimp(patch("-gimp_probe0_name", probe, "-gimp_hole_measure", "0.5,0.2,0.1",
                        "-gimp_hole_measure_load", "1e4"), outdir=reuse)
try:
    s = gimptest.summary(reuse)
    c.check("summary.json escapes strings", rc == 0 and list(s["probes"]) == [probe],
            "probes %r" % list(s["probes"]))
except (OSError, ValueError) as e:
    c.check("summary.json escapes strings", False, "exit %s: %s" % (rc, e))
stale = ["summary.json", "hoop.csv", "fields.h5", "particles.xmf", "grid.xmf"]
c.check("first run wrote its files", all(os.path.exists(os.path.join(reuse, f)) for f in stale),
        str(sorted(os.listdir(reuse))))
# The second run in the same directory writes history.csv, then fails on a full disk.
rc, err, _ = gimp(patch("-ts_max_steps", "200", "-gimp_output_interval", "20"),
                  fsize=1500000, outdir=reuse)
# Its own fields.h5 and XDMF (step 0) stay; nothing of the first run (step 1) may.
left = [f for f in ("summary.json", "hoop.csv") if os.path.exists(os.path.join(reuse, f))]
for f in ("particles.xmf", "grid.xmf"):
    path = os.path.join(reuse, f)
    if os.path.exists(path) and "step_00000001" in open(path).read():
        left.append(f)
try:
    import h5py
    with h5py.File(os.path.join(reuse, "fields.h5"), "r") as h5:
        if "particles/step_00000001" in h5:
            left.append("fields.h5")
except (OSError, KeyError):
    pass  # no readable fields.h5: nothing of the first run either
c.check("a failed run in a reused directory leaves no file of the earlier run",
        rc is not None and rc > 0 and not left, "exit %s, left: %s" % (rc, left))
# An unstable run: the summary is valid JSON (no NaN), status unstable.
unst = os.path.join(W, "unstable")
rc, err, _ = gimp(["-options_file", os.path.join(args.root, "options", "drift.opts"),
                   "-ts_max_steps", "3000"], outdir=unst)
try:
    with open(os.path.join(unst, "summary.json")) as f:
        s = json.load(f, parse_constant=lambda x: (_ for _ in ()).throw(ValueError(x)))
    c.check("summary.json of a failed run is strict JSON", rc == 3 and s["status"] == "unstable",
            "exit %s, status %s" % (rc, s["status"]))
except (OSError, ValueError) as e:
    c.check("summary.json of a failed run is strict JSON", False, "exit %s: %s" % (rc, e))

# A time step below h / c_p (accepted) but above the critical step of the patch test (7.87e-4 s
# with its damping, by -gimp_stability_check): the run blows up and damping freezes it in a wrong
# state with every value finite. The energy it created stops it, on one and on two ranks: one
# error line, exit 3, status unstable, the history up to the failure and a frame of it kept.
def expect_energy_stop(name, opts, out, ranks=1):
    rc, err, _ = gimp(opts, ranks=ranks, outdir=out)
    lines = [l for l in err.splitlines() if l.strip()]
    ok = rc == 3 and len(lines) == 1 and "energy balance" in lines[0] and "unstable" in lines[0]
    try:
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        rows = gimptest.history(out)["step"]
        ok = ok and s["status"] == "unstable" and s["steps"] < 3000 and rows[-1] == s["steps"]
        detail = "exit %s, status %s at step %s, history to step %s: %s" % (
            rc, s["status"], s["steps"], rows[-1], lines[0][:110] if lines else "(no line)")
    except (OSError, ValueError, KeyError) as e:
        ok, detail = False, "exit %s: %s" % (rc, e)
    c.check(name, ok, detail)


for ranks in (1, 2):
    expect_energy_stop(
        "a finite blow-up stops on its created energy (%d rank%s)" % (ranks, "s" * (ranks > 1)),
        ["-options_file", PATCH, "-ts_dt", "7.95e-4", "-ts_max_steps", "3000"],
        os.path.join(W, "unstable_dt_%d" % ranks), ranks)

# The same in 3D: the bar with damping 2 / s at dt = 0.0999 s, below h / c_p = 0.1 s but above
# the damped critical step (2 / omega) (sqrt(1 + xi^2) - xi) = 0.095 s (omega = 2 c_p / h,
# xi = d / (2 omega)).
expect_energy_stop("a finite blow-up stops on its created energy (3D)",
                   ["-options_file", os.path.join(args.root, "options", "bar3d.opts"), "-ts_dt",
                    "0.0999", "-gimp_damping", "2", "-ts_max_steps", "3000"],
                   os.path.join(W, "unstable_dt_3d"))
# ... and at dt = 0.09 s it runs to the end.
rc, err, _ = gimp(["-options_file", os.path.join(args.root, "options", "bar3d.opts"), "-ts_dt",
                   "0.09", "-gimp_damping", "2", "-ts_max_steps", "600"],
                  outdir=os.path.join(W, "stable_dt_3d"))
c.check("the damped 3D bar below its critical step completes", rc == 0, "exit %s: %s" % (rc, err[-200:]))



# Damping lowers the explicit step's limit to (h / c_p)(sqrt(1 + xi^2) - xi), xi = d h / (4 c_p):
# a -ts_dt above it (but below h / c_p) gets a warning before the run, one below it none.
def damped_warning(opts):
    p = subprocess.run([args.gimp] + opts + ["-ts_max_steps", "1", "-gimp_output_dir",
                                             os.path.join(W, "damped_warning")],
                       cwd=W, env=ENV, capture_output=True, text=True, timeout=TIMEOUT)
    return p.returncode, "stable limit of the damped step" in p.stdout


BAR3D = os.path.join(args.root, "options", "bar3d.opts")
for name, opts, expected in (
        ("3D bar, d = 2, dt 0.0999 (limit 0.0951)",
         ["-options_file", BAR3D, "-ts_dt", "0.0999", "-gimp_damping", "2"], True),
        ("3D bar, d = 2, dt 0.09", ["-options_file", BAR3D, "-ts_dt", "0.09", "-gimp_damping", "2"],
         False),
        ("patch, d = 400, dt 7.95e-4 (limit 7.91e-4)", ["-options_file", PATCH, "-ts_dt", "7.95e-4"],
         True),
        ("patch, d = 400, dt 7.8e-4", ["-options_file", PATCH, "-ts_dt", "7.8e-4"], False),
        ("patch, no damping, dt 7.95e-4",
         ["-options_file", PATCH, "-ts_dt", "7.95e-4", "-gimp_damping", "0"], False)):
    rc, warned = damped_warning(opts)
    c.check("damped step limit warning: %s" % name, rc == 0 and warned == expected,
            "exit %s, warned %s (expected %s)" % (rc, warned, expected))

# With -gimp_multirate the damping acts on every node at every sub-step of dt. Over a level's step
# of m dt its momentum is scaled by a^m (a = 1 - d dt), and the step's bound becomes
# (w m dt)^2 <= 2 u (1 + a^m) / (1 - a^m), u = d m dt, never tighter on dt than the finest
# level's (w_min dt)^2 <= 4 - 2 d dt: the finest level's damped bound (the warning's) binds.
# bench/block3.opts: h0 = 4 h_min, c_p = 1160.24 m/s, dt = 3.03e-6 s = 0.9 h_min / c_p.
BLOCK3 = os.path.join(args.root, "bench", "block3.opts")
coarse = os.path.join(W, "block3_coarse.opts") # the same block on its level 0 alone
with open(BLOCK3) as f, open(coarse, "w") as g:
    g.writelines(l for l in f if "level" not in l)
# d = 59404 / s: xi = d h / (4 c_p) is 0.05 on the finest level, 0.2 on the coarsest. The coarse
# level alone, stepping 4 dt, is above its damped bound (0.82 h0 / c_p) and blows up; under
# -gimp_multirate, where it also steps 4 dt, it does not, and no warning is given.
expect_energy_stop("damped level 0 alone at 4 dt, above its damped bound, blows up",
                   ["-options_file", coarse, "-gimp_damping", "59404", "-ts_dt", "1.212e-5",
                    "-ts_max_steps", "400", "-gimp_history_interval", "4"],
                   os.path.join(W, "damped_coarse"))
for d, stable in (("59404", True), ("237616", False)):
    out = os.path.join(W, "damped_multirate_" + d)
    p = subprocess.run([args.gimp, "-options_file", BLOCK3, "-gimp_multirate", "true",
                        "-gimp_damping", d, "-ts_dt", "3.03e-6", "-ts_max_steps", "400",
                        "-gimp_history_interval", "4", "-gimp_output_dir", out],
                       cwd=W, env=ENV, capture_output=True, text=True, timeout=TIMEOUT)
    warned = "stable limit of the damped step" in p.stdout
    try:
        with open(os.path.join(out, "summary.json")) as f:
            status = json.load(f)["status"]
    except (OSError, ValueError, KeyError) as e:
        status = "no summary (%s)" % e
    if stable: # finest xi 0.05: below the bound (0.951 h_min / c_p)
        ok = p.returncode == 0 and not warned and status == "completed"
    else: # finest xi 0.2: the bound is 0.82 h_min / c_p, below dt
        ok = p.returncode == 3 and warned and status == "unstable"
    c.check("multi-rate, d = %s / s: %s" % (d, "coarse level stable at 4 dt, no warning" if stable
                                             else "finest level's damped bound: warned, stops"),
            ok, "exit %s, warned %s, status %s" % (p.returncode, warned, status))

c.check("run time", True, "%.1f s" % (time.time() - t_start))
c.done()
