"""Checkpoint, restart and interrupts (docs/output.md, "Checkpoint and restart").

A run restarted from the checkpoint of step k equals the uninterrupted run bit for bit on the same
rank count: every particle field of the last frame in fields.h5, history.csv, the particle dump and
summary.json but its timing keys; continued in the interrupted run's directory or in a fresh one.
Cases: a cracked block with contact and corner tracking, 1 -> 1 and 2 -> 2 ranks; a three-level
patch, 1 -> 1, with stretch and with cpdi2 tracking. On another rank count (1 -> 2) the answer matches to 1e-10 of each field's largest
value. SIGTERM (sent once history.csv shows progress) stops a run after its step: exit 143 (130
for SIGINT), status "interrupted", a valid summary.json, the last frame readable and listed in
particles.xmf, a checkpoint of that step from which the restart reaches the uninterrupted answer;
under mpiexec -n 2 too, within a timeout: SIGTERM to mpiexec (which passes it on after
odls_base_sigkill_timeout) and SIGTERM to the ranks (then restart 2 -> 2 bit for bit). A stale checkpoint.h5.tmp (a crash while writing) does
not spoil the checkpoint beside it. A checkpoint of another scene is refused in one line. An
unstable run names the particle's level and writes the frame of the state it failed in."""
import os
import re
import shutil
import signal
import subprocess
import time

import h5py
import numpy as np

import gimptest
from restart_files import ENV, last_frame, run_with_dump, same_bits as same_bits_on

args = gimptest.parse_args()
c = gimptest.Checks()
CRACK = ("options/crack_closure.opts", ["-gimp_tracking", "corners", "-gimp_history_interval",
                                        "10", "-gimp_output_interval", "20"])
PATCH = ("options/patch3.opts", ["-gimp_history_interval", "10", "-gimp_output_interval", "25"])


def same_bits(name, ref, got, same_dir=True):
    same_bits_on(c, name, ref, got, same_dir)


def out(name):
    return os.path.join(args.work, name)


def run(scene, name, extra=(), ranks=1, expect_ok=True):
    return run_with_dump(args, scene, name, extra, ranks, expect_ok)





def restart_pair(scene, tag, k, n, ranks, ranks2=None):
    """Uninterrupted n steps; k steps with checkpoints; restart in place and into a fresh dir."""
    ranks2 = ranks2 or ranks
    ref = run(scene, "%s_ref_np%d" % (tag, ranks), ["-ts_max_steps", str(n)], ranks)
    part = run(scene, "%s_part_np%d" % (tag, ranks),
               ["-ts_max_steps", str(k), "-gimp_checkpoint_interval", str(k // 2)], ranks)
    ckpt = os.path.join(args.work, "%s_np%d_step%d.h5" % (tag, ranks, k))
    shutil.copy(os.path.join(part, "checkpoint.h5"), ckpt)
    with h5py.File(ckpt, "r") as f:
        step = f["state"].attrs["step"]
    c.check("%s np%d checkpoint step" % (tag, ranks), step == k, "step %g (expected %d)" % (step, k))
    if ranks2 == ranks:
        cont = run(scene, "%s_part_np%d" % (tag, ranks),
                   ["-ts_max_steps", str(n), "-gimp_restart", ckpt], ranks)
        same_bits("%s %d -> %d continued in place" % (tag, ranks, ranks), ref, cont)
    fresh = run(scene, "%s_fresh_np%d_%d" % (tag, ranks, ranks2),
                ["-ts_max_steps", str(n), "-gimp_restart", ckpt], ranks2)
    return ref, fresh


def close_to(name, ref, got, tol=1e-10):
    """Particle dumps (sorted by id), history and summary numbers agree to tol of the largest."""
    a, b = gimptest.read_csv(os.path.join(ref, "particles.csv")), gimptest.read_csv(
        os.path.join(got, "particles.csv"))
    worst = 0.0
    for col in a:
        scale = max(max(abs(v) for v in a[col]), 1e-300)
        worst = max(worst, max(abs(u - v) for u, v in zip(a[col], b[col])) / scale)
    ha, hb = gimptest.history(ref), gimptest.history(got)
    # The momentum of a body at rest overall is round-off: measure it against the momentum of
    # the total mass at the run's largest kinetic energy, sqrt(2 M KE).
    mass = float(np.sum(last_frame(ref)[1]["m"]))
    pscale = (2.0 * mass * max(ha["kinetic"])) ** 0.5
    hworst = 0.0 if len(ha["step"]) == len(hb["step"]) else float("inf")
    for k in ha:
        scale = max(max(map(abs, ha[k])), pscale if k.startswith("momentum") else 1e-300)
        hworst = max(hworst, max(abs(u - v) for u, v in zip(ha[k], hb[k])) / scale)
    ok = worst < tol and hworst < tol and a["id"] == b["id"]
    c.check(name, ok, "particles max diff / max |value| %.2e, history %.2e (< %.0e)" % (
        worst, hworst, tol))


def children(pid):
    out = subprocess.run(["ps", "-o", "pid=", "--ppid", str(pid)], capture_output=True, text=True)
    return [int(x) for x in out.stdout.split()]


def interrupted(name, n, ranks, sig, stop_after_rows=3, timeout=120, to_ranks=False, env=None):
    """Run the crack scene for n steps; send sig once history.csv has stop_after_rows rows (to
    the process, or with to_ranks to the ranks mpiexec started); env adds to the environment."""
    d = out(name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    opts, base = CRACK
    cmd = [args.gimp, "-options_file", os.path.join(args.root, opts), "-gimp_output_dir", d,
           "-ts_max_steps", str(n), "-gimp_particle_dump", os.path.join(d, "particles.csv")] + base
    env = dict(ENV, **os.environ, **(env or {}))
    if ranks > 1:
        cmd = [args.mpiexec, "-n", str(ranks)] + cmd
    t0 = time.time()
    p = subprocess.Popen(cmd, cwd=args.work, env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    hist = os.path.join(d, "history.csv")
    while p.poll() is None and time.time() - t0 < timeout:
        if os.path.exists(hist) and len(open(hist).read().splitlines()) > stop_after_rows:
            for pid in children(p.pid) if to_ranks else [p.pid]:
                os.kill(pid, sig)
            break
        time.sleep(0.01)
    try:
        so, se = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        so, se = p.communicate()
        c.check(name + " no hang", False, "still running after %d s" % timeout)
    return d, p.returncode, so, se, time.time() - t0


def check_interrupted(name, d, rc, expect_rc, se, n, ref):
    s = gimptest.summary(d)  # fails if summary.json is not valid JSON
    steps = s["steps"]
    c.check(name + " exit and status", (rc == expect_rc or expect_rc is None) and
            s["status"] == "interrupted" and 0 < steps < n,
            "exit %s, status %s at step %d of %d; stderr %r" % (rc, s["status"], steps, n,
                                                                se.strip()[-200:]))
    g, f = last_frame(d)
    xmf = open(os.path.join(d, "particles.xmf")).read()
    c.check(name + " last frame", g == "step_%08d" % steps and f["x"].shape[0] == s["particles"]
            and np.isfinite(f["x"]).all() and ("fields.h5:/particles/%s/x" % g) in xmf,
            "%s with %d particles, listed in particles.xmf: %s" % (
                g, f["x"].shape[0], g in xmf))
    with h5py.File(os.path.join(d, "checkpoint.h5"), "r") as h:
        c.check(name + " checkpoint", h["state"].attrs["step"] == steps,
                "checkpoint at step %g" % h["state"].attrs["step"])
    return steps


# The groups of cases below share no output directory: they run two at a time
# (gimptest.concurrently). The crack's 1-rank group goes on from its checkpoint of step 30.
def crack_np1():
    # Bit for bit on the same rank count.
    crack1, crack12 = restart_pair(CRACK, "crack", 30, 60, 1, 2)
    same_bits("crack 1 -> 1 into a fresh directory", crack1, run(CRACK, "crack_fresh11", [
        "-ts_max_steps", "60", "-gimp_restart", os.path.join(args.work, "crack_np1_step30.h5")]),
              False)
    close_to("crack 1 -> 2 against the 1-rank run", crack1, crack12)
    # A stale checkpoint.h5.tmp (a crash while writing the next one) leaves the checkpoint whole,
    # and the next checkpoint replaces it.
    part = out("crack_part_np1")
    ckpt = os.path.join(part, "checkpoint.h5")
    shutil.copy(os.path.join(args.work, "crack_np1_step30.h5"), ckpt)
    with open(ckpt + ".tmp", "wb") as f:
        f.write(open(ckpt, "rb").read()[:1000])
    cont = run(CRACK, "crack_part_np1", ["-ts_max_steps", "60", "-gimp_restart", ckpt,
                                         "-gimp_checkpoint_interval", "20"])
    same_bits("crack restart beside a stale checkpoint.h5.tmp", crack1, cont)
    with h5py.File(ckpt, "r") as f:
        c.check("the next checkpoint replaces the stale one", f["state"].attrs["step"] == 60 and
                not os.path.exists(ckpt + ".tmp"), "checkpoint step %g, tmp left: %s" % (
                    f["state"].attrs["step"], os.path.exists(ckpt + ".tmp")))

    # A fresh run in the directory removes the earlier run's checkpoint (it would not match).
    run(CRACK, "crack_part_np1", ["-ts_max_steps", "2"])
    c.check("a fresh run removes an earlier checkpoint", not os.path.exists(ckpt), "%s left: %s" % (
        os.path.basename(ckpt), os.path.exists(ckpt)))

    # A checkpoint of another scene, and a file that is none, are refused in one line.
    for name, extra, start in (
            ("another grid", ["-gimp_h", "0.025", "-ts_dt", "1e-4"], "option -gimp_h 0.025: "),
            ("without corners", ["-gimp_tracking", "stretch"], "option -gimp_tracking stretch: "),
            ("not a checkpoint", ["-gimp_restart", os.path.join(part, "history.csv")],
             "option -gimp_restart")):
        r = ["-ts_max_steps", "60", "-gimp_restart", os.path.join(args.work, "crack_np1_step30.h5")]
        p = run(CRACK, "crack_refused", r + extra, expect_ok=False)
        lines = p.stderr.strip().splitlines()
        c.check("restart refused: " + name, p.returncode == 2 and len(lines) == 1 and
                lines[0].startswith("gimp: error: " + start),
                "exit %d: %s" % (p.returncode, p.stderr.strip()[:160]))
    # A restart that would do nothing (-ts_max_steps counts from step 0) is refused in one line.
    p = run(CRACK, "crack_refused", ["-ts_max_steps", "20", "-gimp_restart",
                                     os.path.join(args.work, "crack_np1_step30.h5")], expect_ok=False)
    lines = p.stderr.strip().splitlines()
    c.check("restart refused: -ts_max_steps below the checkpoint's step",
            p.returncode == 2 and len(lines) == 1 and "-ts_max_steps 20" in lines[0] and
            "at step 30" in lines[0], "exit %d: %s" % (p.returncode, p.stderr.strip()[:160]))


def crack_np2():
    crack2, fresh22 = restart_pair(CRACK, "crack", 20, 40, 2)
    same_bits("crack 2 -> 2 into a fresh directory", crack2, fresh22, False)


def patch3():
    patch1, fresh11 = restart_pair(PATCH, "patch3", 50, 100, 1)
    same_bits("patch3 1 -> 1 into a fresh directory", patch1, fresh11, False)
    # cpdi2 (the default tracking): the tracked corners are part of the restarted state
    cpdi2 = (PATCH[0], PATCH[1] + ["-gimp_tracking", "cpdi2"])
    cp1, cfresh = restart_pair(cpdi2, "patch3_cpdi2", 50, 100, 1)
    same_bits("patch3 with cpdi2 1 -> 1 into a fresh directory", cp1, cfresh, False)

    # An unstable run (pulled by 1e8 Pa, a block of E = 1e7 Pa tears apart): the error names step,
    # time, particle, position and the level whose leaf cell holds it; the frame of the failed state
    # is written and listed.
    p = run(PATCH, "patch3_unstable", ["-gimp_traction0_value", "1e8,0", "-gimp_traction1_value",
                                       "-1e8,0", "-gimp_pad", "20", "-ts_max_steps", "200"],
            expect_ok=False)
    d = out("patch3_unstable")
    err = [l for l in p.stderr.splitlines() if l.startswith("gimp: error")]
    s = gimptest.summary(d)
    m = re.match(r"gimp: error: step (\d+) t \S+ s: particle \d+ at \((\S+), (\S+)\) on level "
                 r"(\S+): ", err[0] if err else "")
    level = None
    if m:
        x, y = float(m.group(2)), float(m.group(3))
        level = max(k for k, L in enumerate(s["levels"])
                    if k == 0 or (L["box"][0] < x < L["box"][2] and L["box"][1] < y < L["box"][3]))
    c.check("unstable run: exit, message with step and level", p.returncode == 3 and m and
            s["status"] == "unstable" and int(m.group(1)) == s["steps"] and
            m.group(4) == str(level), "exit %d, status %s, expected level %s: %s" % (
                p.returncode, s["status"], level, err[0] if err else p.stderr[-200:]))
    g, f = last_frame(d)
    c.check("unstable run: last frame of the failed step", g == "step_%08d" % s["steps"] and
            ("/particles/%s/x" % g) in open(os.path.join(d, "particles.xmf")).read(),
            "%s (summary steps %d) listed in particles.xmf" % (g, s["steps"]))


def slab():
    # A restart from a checkpoint of the last step runs no step: its summary still reports the
    # penalty conditions' reactions and gaps of that step (the slab's two displacement conditions).
    SLAB = ("options/slab.opts", ["-gimp_history_interval", "10", "-gimp_output_interval", "25"])
    slab_ref = run(SLAB, "slab_ref", ["-ts_max_steps", "25"])
    slab_part = run(SLAB, "slab_part", ["-ts_max_steps", "25", "-gimp_checkpoint_interval", "25"])
    slab_ckpt = out("slab_step25.h5")
    shutil.copy(os.path.join(slab_part, "checkpoint.h5"), slab_ckpt)
    same_bits("slab restart that runs no step", slab_ref,
              run(SLAB, "slab_part", ["-ts_max_steps", "25", "-gimp_restart", slab_ckpt]))


def tension():
    # With the critical step re-checked during large deformation, summary.json's dt_critical is the
    # smallest of the whole run, re-checks before the checkpoint included (with SLEPc only).
    TENSION = ("options/tension.opts", ["-gimp_stability_check", "-gimp_stability_interval", "50",
                                        "-gimp_history_interval", "10", "-gimp_output_interval", "50"])
    probe = subprocess.run([args.gimp, "-options_file", os.path.join(args.root, TENSION[0]),
                            "-gimp_stability_check", "-ts_max_steps", "0", "-gimp_output_dir",
                            out("slepc_probe")], cwd=args.root, env=ENV, capture_output=True,
                           text=True)
    if probe.returncode == 0:
        tension1, tfresh = restart_pair(TENSION, "tension_stability", 150, 300, 1)
        same_bits("tension with stability re-checks 1 -> 1 into a fresh directory", tension1, tfresh,
                  False)
        # The case means something only when the re-checks before the checkpoint found a smaller
        # critical step than the start's.
        start = gimptest.summary(out("slepc_probe"))["dt_critical"]
        before = gimptest.summary(out("tension_stability_part_np1"))["dt_critical"]
        c.check("tension: re-checks before the checkpoint lowered dt_critical", before < start,
                "dt_critical at the start %.6e, by step 150 %.6e" % (start, before))


def signals_np1():
    N = 300
    ref300 = run(CRACK, "crack_ref300", ["-ts_max_steps", str(N)])
    d, rc, so, se, secs = interrupted("crack_sigterm", N, 1, signal.SIGTERM)
    check_interrupted("SIGTERM np1", d, rc, 143, se, N, ref300)
    res = run(CRACK, "crack_sigterm", ["-ts_max_steps", str(N), "-gimp_restart",
                                       os.path.join(d, "checkpoint.h5")])
    same_bits("SIGTERM np1 then restart", ref300, res)
    d, rc, so, se, secs = interrupted("crack_sigint", N, 1, signal.SIGINT)
    check_interrupted("SIGINT np1", d, rc, 130, se, N, ref300)


def signals_mpiexec():
    # mpiexec (Open MPI 4.1) answers SIGTERM (and SIGINT) by sending the ranks SIGTERM after
    # odls_base_sigkill_timeout seconds and SIGKILL as long again: 3 s leave the ranks time to finish
    # the step and write. Where the run then stops depends on the machine's speed: this case checks
    # the outputs and that nothing hangs, and that its checkpoint restarts.
    d, rc, so, se, secs = interrupted("crack_sigterm_mpiexec", 100000, 2, signal.SIGTERM, timeout=60,
                                      env={"OMPI_MCA_odls_base_sigkill_timeout": "3"})
    steps = check_interrupted("SIGTERM to mpiexec -n 2 (%.1f s)" % secs, d, rc, None, se, 100000,
                              None)
    res = run(CRACK, "crack_sigterm_mpiexec", ["-ts_max_steps", str(steps + 2), "-gimp_restart",
                                               os.path.join(d, "checkpoint.h5")], ranks=2)
    c.check("SIGTERM to mpiexec then restart", gimptest.summary(res)["steps"] == steps + 2 and
            gimptest.summary(res)["status"] == "completed", "continued to step %d" % (steps + 2))


def signals_ranks():
    # SIGTERM to the ranks themselves (mpiexec's children) stops them after the step under way, at a
    # step known from history.csv: the restart on 2 ranks equals the uninterrupted 2-rank run bit
    # for bit, and mpiexec exits with the ranks' 143.
    d, rc, so, se, secs = interrupted("crack_sigterm_np2", 100000, 2, signal.SIGTERM, timeout=60,
                                      to_ranks=True)
    steps = check_interrupted("SIGTERM to the ranks of mpiexec -n 2 (%.1f s)" % secs, d, rc, 143, se,
                              100000, None)
    n2 = str(steps + 10)
    ref_2 = run(CRACK, "crack_ref_sigterm_np2", ["-ts_max_steps", n2], ranks=2)
    res = run(CRACK, "crack_sigterm_np2", ["-ts_max_steps", n2, "-gimp_restart",
                                           os.path.join(d, "checkpoint.h5")], ranks=2)
    same_bits("SIGTERM to the ranks, then restart np2", ref_2, res)


gimptest.concurrently([crack_np1, crack_np2, patch3, slab, tension, signals_np1, signals_mpiexec,
                       signals_ranks])
c.done()
