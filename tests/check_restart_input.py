"""Bad restarts (docs/output.md, "Checkpoint and restart"): each is refused with exactly one
`gimp: error:` line, exit 2 and no signal, serial and on 2 ranks, and leaves the output it would
have continued (an earlier run's fields.h5, history.csv, summary.json, XDMF files and
checkpoint.h5) and the checkpoint it was given byte for byte as they were.

A changed scene: every state-defining option that differs (material, body, particle file content,
grid, scheme, damping, tracking, crack, load, dimension) names itself and the checkpoint's value;
options a restart may change (output intervals, the same value written otherwise) are accepted.
A damaged checkpoint (copies of a real one damaged with h5py): each dataset and attribute deleted
in turn, a dataset cut short or of another type, a stored count changed, NaN or inf in positions,
velocities, stresses, masses, time and dt, a non-integer id, the file truncated, a text file and
an empty file named .h5: one line naming the file and the field."""
import hashlib
import os
import shutil
import subprocess

import h5py
import numpy as np

import gimptest
from restart_files import ENV

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
CRACK = ["-options_file", os.path.join(args.root, "options", "crack_closure.opts"),
         "-gimp_tracking", "corners"]


launcher = subprocess.run([args.mpiexec, "--version"], capture_output=True, text=True)
QUIET = ["-q"] if "Open MPI" in launcher.stdout + launcher.stderr or \
    "OpenRTE" in launcher.stdout + launcher.stderr else []


def gimp(opts, ranks=1):
    cmd = [args.gimp] + opts
    if ranks > 1:  # (-q: Open MPI's launcher adds no lines of its own)
        cmd = [args.mpiexec] + QUIET + ["-n", str(ranks)] + cmd
    return subprocess.run(cmd, cwd=W, env=ENV, capture_output=True, text=True, errors="replace",
                          timeout=120)


def tree_hashes(paths):
    """sha256 of every file under the paths (files or directories)."""
    h = {}
    for p in paths:
        files = [p] if os.path.isfile(p) else [os.path.join(r, f) for r, _, fs in os.walk(p)
                                                 for f in fs]
        for f in files:
            with open(f, "rb") as fh:
                h[f] = hashlib.sha256(fh.read()).hexdigest()
    return h


def refused(name, scene, ckpt, needles, ranks=1, steps=40):
    """A restart of scene from ckpt, continued in PREV's copy: one line with every needle."""
    out = os.path.join(W, "prev_np%d" % ranks)
    before = tree_hashes([out, ckpt])
    p = gimp(scene + ["-ts_max_steps", str(steps), "-gimp_restart", ckpt, "-gimp_output_dir", out],
             ranks)
    after = tree_hashes([out, ckpt])
    err = [l for l in p.stderr.splitlines() if l.strip()]
    errors = [l for l in (p.stdout + p.stderr).splitlines() if "error" in l.lower()]
    ok = (p.returncode == 2 and len(err) == 1 and err[0].startswith("gimp: error: ") and
          len(errors) == 1 and all(n in err[0] for n in needles))
    c.check("%s%s" % (name, " (2 ranks)" if ranks > 1 else ""), ok and before == after,
            "exit %d, %s; files %s" % (p.returncode, " | ".join(err[:3])[:300] or "(no message)",
                                       "unchanged" if before == after else "CHANGED"))


def accepted(name, scene, ckpt, ranks=1):
    out = os.path.join(W, "accepted")
    shutil.rmtree(out, ignore_errors=True)
    p = gimp(scene + ["-ts_max_steps", "30", "-gimp_restart", ckpt, "-gimp_output_dir", out],
             ranks)
    c.check("accepted: " + name, p.returncode == 0 and "gimp: restart from" in p.stdout,
            "exit %d %s" % (p.returncode, p.stderr.strip()[:200]))


# A real checkpoint of step 20 (the cracked block with corner tracking, on 1 and 2 ranks), and an
# earlier run's whole output beside it, which the refused restarts must leave alone.
ckpts = {}
for ranks in (1, 2):
    src = os.path.join(W, "src_np%d" % ranks)
    shutil.rmtree(src, ignore_errors=True)
    p = gimp(CRACK + ["-ts_max_steps", "20", "-gimp_checkpoint_interval", "10",
                      "-gimp_output_interval", "10", "-gimp_output_dir", src], ranks)
    assert p.returncode == 0, p.stderr
    ckpts[ranks] = os.path.join(W, "crack_np%d.h5" % ranks)
    shutil.copy(os.path.join(src, "checkpoint.h5"), ckpts[ranks])
    shutil.rmtree(os.path.join(W, "prev_np%d" % ranks), ignore_errors=True)
    shutil.copytree(src, os.path.join(W, "prev_np%d" % ranks))
ck = ckpts[1]

# Class 1: a changed scene. The option's value as given now, then the checkpoint's.
SCENE = [("-gimp_E", "2e7", "1e7"), ("-gimp_rho", "2000", "1000"), ("-gimp_nu", "0.25", "0.3"),
         ("-gimp_material", "neohookean", None), ("-gimp_plane", "stress", "strain"),
         ("-gimp_body0_box", "0,0,1,0.55", "0,0,1,0.5"), ("-gimp_body0_ppc", "9", "4"),
         ("-gimp_body0_velocity", "0.1,0", None), ("-gimp_body0_E", "2e7", None),
         ("-gimp_h", "0.025", "0.05"), ("-gimp_domain", "-0.2,-0.2,1.2,0.7", None),
         ("-gimp_update", "usl", None), ("-gimp_transfer", "flip", None),
         ("-gimp_damping", "0", "400"), ("-gimp_tracking", "stretch", "corners"),
         ("-gimp_crack0_points", "-0.1,0.3,1.1,0.3", "-0.1,0.25,1.1,0.25"),
         ("-gimp_traction0_value", "0,-2e4", "0,-1e4"), ("-gimp_gravity", "0,-9.81", None),
         ("-gimp_cut_cells", "false", None), ("-gimp_half_step_start", "false", None)]
for opt, value, was in SCENE:
    needles = ["option %s %s: the checkpoint %s was written " % (opt, value, ck),
               "with %s %s;" % (opt, was) if was else "without it",
               "a restart must use the scene it was written with"]
    extra = ["-ts_dt", "1e-4"] if opt in ("-gimp_h", "-gimp_body0_ppc") else []
    refused("scene: %s %s" % (opt, value), CRACK + [opt, value] + extra, ck, needles)
refused("scene: -gimp_E 2e7", CRACK + ["-gimp_E", "2e7"], ckpts[2],
        ["option -gimp_E 2e7: the checkpoint %s was written with -gimp_E 1e7;" % ckpts[2]], 2)
accepted("the same E written otherwise, other output intervals",
         CRACK + ["-gimp_E", "10000000.0", "-gimp_history_interval", "5",
                  "-gimp_output_interval", "3", "-gimp_monitor_interval", "7"], ck)

# The dimension: a 3D checkpoint given to a 2D scene, and a 2D one to a 3D scene.
d3 = os.path.join(W, "bar3d")
shutil.rmtree(d3, ignore_errors=True)
BAR3 = ["-options_file", os.path.join(args.root, "options", "bar3d.opts")]
BAR2 = ["-options_file", os.path.join(args.root, "options", "bar.opts")]
assert gimp(BAR3 + ["-ts_max_steps", "10", "-gimp_checkpoint_interval", "10",
                    "-gimp_output_dir", d3]).returncode == 0
ck3 = os.path.join(W, "bar3d.h5")
shutil.copy(os.path.join(d3, "checkpoint.h5"), ck3)
refused("a 3D checkpoint in a 2D scene", BAR2, ck3,
        ["option -gimp_dim 2 (the default): the checkpoint %s was written with -gimp_dim 3;" % ck3])
refused("a 2D checkpoint in a 3D scene", BAR3, ck,
        ["option -gimp_dim 3: the checkpoint %s was written without it (the default 2)" % ck])

# A particle file: another file, and the same file with another content.
seed = os.path.join(W, "seed.csv")
assert gimp(BAR2 + ["-ts_max_steps", "0", "-gimp_particle_dump", seed, "-gimp_output_dir",
                    os.path.join(W, "seed")]).returncode == 0
with open(os.path.join(args.root, "options", "bar.opts")) as f:
    # (a file body takes no box, velocity profile or particles per cell)
    kept = [l for l in f if not l.startswith(("-gimp_body0_box", "-gimp_body0_velocity",
                                              "-gimp_body0_wavenumber", "-gimp_body0_ppc"))]
barfile = os.path.join(W, "barfile.opts")
with open(barfile, "w") as f:
    f.writelines(kept + ["-gimp_body0_shape file\n", "-gimp_body0_file %s\n" % seed])
FILE = ["-options_file", barfile]
dfile = os.path.join(W, "barfile")
shutil.rmtree(dfile, ignore_errors=True)
assert gimp(FILE + ["-ts_max_steps", "10", "-gimp_checkpoint_interval", "10",
                    "-gimp_output_dir", dfile]).returncode == 0
ckf = os.path.join(W, "barfile.h5")
shutil.copy(os.path.join(dfile, "checkpoint.h5"), ckf)
rows = open(seed).read().splitlines()
cells = rows[1].split(",")
cells[3] = repr(float(cells[3]) * 2)  # the first particle's vx
other = os.path.join(W, "seed_other.csv")
with open(other, "w") as f:
    f.write("\n".join([rows[0], ",".join(cells)] + rows[2:]) + "\n")
copy = os.path.join(W, "seed_copy.csv")
shutil.copy(seed, copy)
refused("scene: another particle file", FILE + ["-gimp_body0_file", other], ckf,
        ["option -gimp_body0_file %s: the checkpoint %s was written with -gimp_body0_file %s;"
         % (other, ckf, seed)], steps=20)
accepted("the particle file copied elsewhere", FILE + ["-gimp_body0_file", copy], ckf)
shutil.copy(other, seed)
refused("scene: the particle file's content changed", FILE, ckf,
        ["option -gimp_body0_file %s: the checkpoint %s was written with -gimp_body0_file %s "
         "(another content)" % (seed, ckf, seed)], steps=20)
shutil.copy(copy, seed)


# Class 2: damaged copies of the checkpoint.
def damaged(tag, change):
    path = os.path.join(W, "bad_%s.h5" % tag)
    shutil.copy(ck, path)
    with h5py.File(path, "r+") as f:
        change(f)
    return path


def replace(f, name, data):
    del f[name]
    f.create_dataset(name, data=data)


def setval(name, index, value):
    def change(f):
        a = np.array(f[name])
        a[index] = value
        replace(f, name, a)
    return change


def setattr_(name, value):
    def change(f):
        f["state"].attrs[name] = value
    return change


with h5py.File(ck, "r") as f:
    datasets = []
    f.visititems(lambda n, o: datasets.append(n) if isinstance(o, h5py.Dataset) else None)
    attrs = list(f["state"].attrs)
    nparticles = int(f["state"].attrs["particles"])
assert len(datasets) > 20 and len(attrs) > 15, (datasets, attrs)
cases = []
for d in datasets:
    cases.append(("dataset /%s deleted" % d, damaged("del_" + d.replace("/", "_"),
                                                      lambda f, d=d: f.__delitem__(d)),
                  ["the field /%s is missing" % d] if d != "state/scene" else
                  ["the field /state/scene is missing"]))
for a in attrs:
    cases.append(("attribute %s deleted" % a,
                  damaged("delattr_" + a, lambda f, a=a: f["state"].attrs.__delitem__(a)),
                  ["the attribute /state/%s is missing" % a]))
cases += [
    ("/particles/x cut short", damaged("short_x", lambda f: replace(
        f, "particles/x", np.array(f["particles/x"])[:-1])),
     ["the field /particles/x holds %d values, not %d particles x 2" %
      (2 * nparticles - 2, nparticles)]),
    ("/particles/m as int32", damaged("int_m", lambda f: replace(
        f, "particles/m", np.array(f["particles/m"]).astype(np.int32))),
     ["the field /particles/m is not of type float64"]),
    ("/state/frames count changed", damaged("count_frames", setval("state/frames", 0, 7)),
     ["the field /state/frames records 7 values but holds"]),
    ("/state/history count huge", damaged("count_history", setval("state/history", 0, 1e18)),
     ["the field /state/history records 1e+18 values"]),
    ("/state/history byte count changed",
     damaged("bytes_history", setval("state/history", 1, 1e15)),
     ["the field /state/history records 1e+15 bytes"]),
    ("/state/grid count changed", damaged("count_grid", setval("state/grid", 0, 3)),
     ["the field /state/grid records 3 values but holds"]),
    ("/particles/local_sizes wrong", damaged("sizes", setval("particles/local_sizes", 1, 5)),
     ["the field /particles/local_sizes holds 1 ranks' counts summing to 5"]),
    ("particles count changed", damaged("count_particles", setattr_("particles", float(nparticles - 1))),
     ["/particles/local_sizes"]),
    ("ranks changed", damaged("count_ranks", setattr_("ranks", 3.0)),
     ["the field /particles/local_sizes holds 1 ranks' counts"]),
    ("NaN position", damaged("nan_x", setval("particles/x", (3, 0), np.nan)),
     ["the field /particles/x holds nan at particle 3"]),
    ("inf velocity", damaged("inf_v", setval("particles/v", (4, 1), np.inf)),
     ["the field /particles/v holds inf at particle 4"]),
    ("-inf stress", damaged("inf_stress", setval("particles/stress", (5, 2), -np.inf)),
     ["the field /particles/stress holds -inf at particle 5"]),
    ("NaN mass", damaged("nan_m", setval("particles/m", 7, np.nan)),
     ["the field /particles/m holds nan at particle 7"]),
    ("negative mass", damaged("neg_m", setval("particles/m", 9, -1.0)),
     ["the field /particles/m holds -1, not > 0, at particle 9"]),
    ("zero volume", damaged("zero_V", setval("particles/V", 10, 0.0)),
     ["the field /particles/V holds 0, not > 0, at particle 10"]),
    ("non-integer id", damaged("frac_id", setval("particles/id", 2, 0.5)),
     ["the field /particles/id holds 0.5, not an integer, at particle 2"]),
    ("NaN in /state/grid", damaged("nan_grid", setval("state/grid", 1, np.nan)),
     ["the field /state/grid holds nan at position 0"]),
    ("NaN time", damaged("nan_time", setattr_("time", np.nan)),
     ["the attribute /state/time is nan, not a finite number"]),
    ("inf dt", damaged("inf_dt", setattr_("dt", np.inf)),
     ["the attribute /state/dt is inf, not a finite number"]),
    ("dt 0", damaged("zero_dt", setattr_("dt", 0.0)), ["the attribute /state/dt is 0, not > 0"]),
    ("step 2.5", damaged("frac_step", setattr_("step", 2.5)),
     ["the attribute /state/step is 2.5, not a count"]),
    ("NaN mean particle mass", damaged("nan_mass", setattr_("mean_particle_mass", np.nan)),
     ["the attribute /state/mean_particle_mass is nan"]),
    ("a string format", damaged("str_format", setattr_("format", "6")),
     ["the attribute /state/format is not of type float64"]),
    ("layout version 4", damaged("format4", setattr_("format", 4.0)),
     ["its layout version 4 is not 7"]),
]
trunc = os.path.join(W, "bad_truncated.h5")
with open(ck, "rb") as f:
    data = f.read()
with open(trunc, "wb") as f:
    f.write(data[:len(data) // 2])
text = os.path.join(W, "bad_text.h5")
with open(text, "w") as f:
    f.write("step,time\n0,0\n")
empty = os.path.join(W, "bad_empty.h5")
open(empty, "w").close()
cases += [("the file truncated", trunc, ["the HDF5 file cannot be opened (truncated or damaged)"]),
          ("a text file named .h5", text, ["not a gimp checkpoint (no HDF5 file there)"]),
          ("an empty file", empty, ["not a gimp checkpoint"]),
          ("no file", os.path.join(W, "none.h5"), ["not a gimp checkpoint"])]
for name, path, needles in cases:
    refused("damaged: " + name, CRACK, path, ["option -gimp_restart %s: " % path] + needles)

# On 2 ranks: a damaged copy of the 2-rank checkpoint, found by rank 0, ends both ranks with the
# one line.
ck = ckpts[2]
for name, change, needle in (
        ("NaN stress", setval("particles/stress", (11, 0), np.nan),
         "the field /particles/stress holds nan at particle 11"),
        ("/particles/v deleted", lambda f: f.__delitem__("particles/v"),
         "the field /particles/v is missing"),
        ("/state/history count changed", setval("state/history", 0, 2.0),
         "the field /state/history records 2 values")):
    path = damaged("np2_" + name.split()[0].replace("/", "_"), change)
    refused("damaged: " + name, CRACK, path, ["option -gimp_restart %s: " % path, needle], 2)
refused("damaged: the file truncated", CRACK, trunc, ["cannot be opened"], 2)
# The undamaged checkpoints still restart.
accepted("the 2-rank checkpoint", CRACK, ckpts[2], 2)
accepted("the serial checkpoint", CRACK, ckpts[1])
c.done()
