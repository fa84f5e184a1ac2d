"""Checkpoint and restart in 3D (-gimp_checkpoint_interval, -gimp_restart, SIGTERM; docs/output.md,
"Checkpoint and restart"), as tests/check_restart.py does in 2D.

A run restarted from the checkpoint of step k equals the uninterrupted run bit for bit on the same
rank count: the particle dump, history.csv, summary.json but its timing keys and every particle
field of the last frame of fields.h5 (and particles.xmf when it continues in the checkpoint's
directory). Cases: the 3D block on two levels thrown across the rank boundary
(options/migrate3d.opts, 300 steps, checkpoints every 75 steps, restart from step 150), 1 -> 1
and 2 -> 2 ranks, continued in place and into a fresh directory; 1 -> 2 ranks agrees to 1e-10
of each quantity's group (measured 2.7e-14). A checkpoint of another grid (-gimp_h 0.05 instead of
0.1) and a 3D checkpoint given to a 2D scene are refused in one line (exit 2).
SIGTERM (sent once history.csv shows progress) stops the 3D bar (options/bar3d.opts) after its
step: exit 143, status "interrupted", the line "gimp: interrupted by SIGTERM at step N", the
last frame of step N, a checkpoint of step N from which the restart to N + 200 equals the
uninterrupted run of N + 200 steps bit for bit; likewise SIGTERM to the ranks of mpiexec -n 2,
then a 2 -> 2 restart."""
import os
import shutil
import signal
import subprocess
import time

import h5py
import numpy as np

import compare3d
import gimptest
from restart_files import ENV, last_frame, run_with_dump, same_bits as same_bits_on

args = gimptest.parse_args()
c = gimptest.Checks()
BLOCK = ("options/migrate3d.opts", ["-gimp_history_interval", "10", "-gimp_output_interval", "50"])
BAR = ("options/bar3d.opts", ["-gimp_history_interval", "5"])


def same_bits(name, ref, got, same_dir=True):
    same_bits_on(c, name, ref, got, same_dir)


def out(name):
    return os.path.join(args.work, name)


def run(scene, name, extra=(), ranks=1, expect_ok=True):
    return run_with_dump(args, scene, name, extra, ranks, expect_ok)





def checkpoint_step(path):
    with h5py.File(path, "r") as f:
        return int(f["state"].attrs["step"])


def restart_pair(ranks, ranks2=None, k=150, n=300):
    """Uninterrupted n steps; k steps with checkpoints every k/2; restart in place (same rank
    count) and into a fresh directory (on ranks2 ranks)."""
    ranks2 = ranks2 or ranks
    ref = run(BLOCK, "block_ref_np%d" % ranks, ["-ts_max_steps", str(n)], ranks)
    part = run(BLOCK, "block_part_np%d" % ranks,
               ["-ts_max_steps", str(k), "-gimp_checkpoint_interval", str(k // 2)], ranks)
    ckpt = out("block_np%d_step%d.h5" % (ranks, k))
    shutil.copy(os.path.join(part, "checkpoint.h5"), ckpt)
    step = checkpoint_step(ckpt)
    c.check("block np%d checkpoint step" % ranks, step == k, "step %d (expected %d)" % (step, k))
    if ranks2 == ranks:
        cont = run(BLOCK, "block_part_np%d" % ranks,
                   ["-ts_max_steps", str(n), "-gimp_restart", ckpt], ranks)
        same_bits("block %d -> %d continued in place" % (ranks, ranks), ref, cont)
    fresh = run(BLOCK, "block_fresh_np%d_%d" % (ranks, ranks2),
                ["-ts_max_steps", str(n), "-gimp_restart", ckpt], ranks2)
    mig = gimptest.summary(ref)["measures"]["particles_migrated"]
    return ref, fresh, ckpt, mig


ref1, fresh11, ckpt1, _ = restart_pair(1)
same_bits("block 1 -> 1 into a fresh directory", ref1, fresh11, False)
ref2, fresh22, _, mig = restart_pair(2)
same_bits("block 2 -> 2 into a fresh directory (%d particles migrated)" % mig, ref2, fresh22,
          False)
fresh12 = run(BLOCK, "block_fresh_np1_2", ["-ts_max_steps", "300", "-gimp_restart", ckpt1], 2)
a = compare3d.read_dump(os.path.join(ref1, "particles.csv"))[1]
b = compare3d.read_dump(os.path.join(fresh12, "particles.csv"))[1]
dd, group = compare3d.dump_diff(a, b)
hd, col = compare3d.history_diff(gimptest.history(ref1), gimptest.history(fresh12))
c.check("block 1 -> 2 against the 1-rank run", dd < 1e-10 and hd < 1e-10,
        "particles: largest difference %.1e of the group's scale (%s), history %.1e (%s); tol "
        "1e-10" % (dd, group, hd, col))

# Checkpoints that do not fit the scene are refused in one line.
for name, opts, extra, start in (
        ("another grid", BLOCK[0], ["-gimp_h", "0.05"], "option -gimp_h 0.05: "),
        ("a 3D checkpoint in a 2D scene", "options/bar.opts", [],
         "option -gimp_dim 2 (the default): the checkpoint %s was written with -gimp_dim 3"
         % ckpt1)):
    p = gimptest.run(args, opts, extra + ["-ts_max_steps", "300", "-gimp_restart", ckpt1],
                     outdir=out("refused"), expect_ok=False)
    lines = p.stderr.strip().splitlines()
    c.check("restart refused: " + name, p.returncode == 2 and len(lines) == 1 and
            lines[0].startswith("gimp: error: " + start),
            "exit %d: %s" % (p.returncode, p.stderr.strip()[:200]))


# SIGTERM.
def children(pid):
    r = subprocess.run(["ps", "-o", "pid=", "--ppid", str(pid)], capture_output=True, text=True)
    return [int(x) for x in r.stdout.split()]


def interrupted(name, ranks, timeout=60):
    """Run the bar for up to 100000 steps; SIGTERM once history.csv has 4 rows (to the process,
    or on 2 ranks to the ranks mpiexec started)."""
    d = out(name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    opts, base = BAR
    cmd = [args.gimp, "-options_file", os.path.join(args.root, opts), "-gimp_output_dir", d,
           "-ts_max_steps", "100000", "-gimp_particle_dump", os.path.join(d, "particles.csv")]
    cmd += base
    if ranks > 1:
        cmd = [args.mpiexec, "-n", str(ranks)] + cmd
    t0 = time.time()
    p = subprocess.Popen(cmd, cwd=args.work, env=ENV, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    hist = os.path.join(d, "history.csv")
    sent = False
    while p.poll() is None and time.time() - t0 < timeout:
        if os.path.exists(hist) and len(open(hist).read().splitlines()) > 4:
            targets = children(p.pid) if ranks > 1 else [p.pid]
            for pid in targets:
                os.kill(pid, signal.SIGTERM)
            sent = bool(targets)
            break
        time.sleep(0.01)
    try:
        so, se = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        so, se = p.communicate()
        c.check(name + " no hang", False, "still running after %d s" % timeout)
    return d, p.returncode, so + se, sent


def sigterm(tag, ranks):
    d, rc, text, sent = interrupted("bar_sigterm_np%d" % ranks, ranks)
    s = gimptest.summary(d)
    steps = s["steps"]
    line = "gimp: interrupted by SIGTERM at step %d " % steps
    c.check(tag + ": exit, status, message", sent and rc == 143 and s["status"] == "interrupted"
            and 0 < steps < 5000 and line in text,
            "signal sent %s; exit %s, status %s at step %d; %r" % (
                sent, rc, s["status"], steps,
                [ln for ln in text.splitlines() if "interrupted" in ln][:1]))
    g, f = last_frame(d)
    ck = checkpoint_step(os.path.join(d, "checkpoint.h5"))
    c.check(tag + ": last frame and checkpoint", g == "step_%08d" % steps and
            f["x"].shape == (s["particles"], 3) and np.isfinite(f["x"]).all() and ck == steps,
            "last frame %s with x %s, checkpoint at step %d" % (g, f["x"].shape, ck))
    n = str(steps + 200)
    ref = run(BAR, "bar_ref_np%d" % ranks, ["-ts_max_steps", n], ranks)
    res = run(BAR, "bar_sigterm_np%d" % ranks, ["-ts_max_steps", n, "-gimp_restart",
                                                 os.path.join(d, "checkpoint.h5")], ranks)
    same_bits(tag + ", then restart to step %s" % n, ref, res)


sigterm("SIGTERM np1", 1)
sigterm("SIGTERM to the ranks of mpiexec -n 2", 2)
c.done()
