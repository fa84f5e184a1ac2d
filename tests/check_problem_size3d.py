"""The problem-size estimate and -gimp_memory_limit in 3D (docs/options.md, -gimp_memory_limit):
before anything is allocated the run's size is estimated from the scene (nodes of every level
from its box and cell size, particles of every body from its volume on each level's cells
times ppc) and a scene larger than the limit, or than PetscInt can index, is refused in one
line naming the option most likely wrong (exit 2, no PETSc trace).

Checked (measured in brackets):
- the estimate is the 3D count: its particles and grid nodes (parsed from the refusal at
  -gimp_memory_limit 1) equal those of the run, on the bar (options/bar3d.opts: 200 particles,
  1080 nodes) and on the block on two levels (options/migrate3d.opts: 544 particles, 637 + 1053
  nodes; a part of the body on each level);
- the refusal names the culprit, with 3D values: -gimp_h (the bar, nodes dominate),
  -gimp_level1_box with its 6 numbers (the block), -gimp_domain (the bar's, given),
  -gimp_pad (a pad of 100 cells), -gimp_body0_ppc (512 particles per cell: particles dominate),
  -gimp_body0_box (a body 2000 times longer than thick); each message names -gimp_memory_limit;
- the limit acts at the estimate: the bar refused at 0.9 of its estimate and run at 1.1 of it;
- the default limit is the physical memory: the bar at h = 0.005 m (1.6e9 particles, about 3 TB)
  refused naming "physical memory", within seconds and without allocating (the peak resident
  size of the runs so far below 200 MB [52 MB; 0.4 s]);
- a grid too large for PetscInt: the bar at -gimp_h 1e-4 (2.5e13 nodes on level 0), and a body of
  3.1e9 particles (more per rank than PetscInt counts), refused in one line even under
  -gimp_memory_limit 1e30, without a PETSc trace; on 2 ranks the same 3.1e9 particles are 1.6e9
  per rank, so the PetscInt refusal gives way to the memory one (per rank, as documented);
- on 2 ranks a refusal is one line (not one per rank).
Every run is capped at 4 GiB of address space per process, so that a refusal that does not come
fails the check instead of filling the machine.
"""
import os
import re
import resource
import shlex
import subprocess
import time

import compare3d
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
BAR, BLOCK = "options/bar3d.opts", "options/migrate3d.opts"
SIZE = re.compile(r"the scene needs about (\S+) particles and (\S+) grid nodes")


# Every run here is capped at 4 GiB of address space per process (RLIMIT_AS, set in the child):
# a refusal that fails to come must not let gimp allocate the hundreds of GB it was refused
# for (the machine's other work would meet the OOM killer); it fails here on its allocation.
CAP = 4 << 30


def cap():
    resource.setrlimit(resource.RLIMIT_AS, (CAP, CAP))


def capped(tag, opts, extra, ranks=1):
    """gimptest.run's command (opts, extra, the --extra options) under the cap; the completed
    process."""
    out = os.path.join(args.work, tag)
    cmd = [args.gimp, "-options_file", os.path.join(args.root, opts), "-gimp_output_dir", out]
    cmd += list(extra) + shlex.split(args.extra)
    if ranks > 1:
        cmd = [args.mpiexec, "-n", str(ranks)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    return subprocess.run(cmd, cwd=args.work, env=env, capture_output=True, text=True,
                          preexec_fn=cap, timeout=120)


def refused(tag, opts, extra, ranks=1):
    """Run expecting a refusal: (exit code, error lines, process, seconds, peak RSS of the
    children so far [kB])."""
    t0 = time.time()
    p = capped(tag, opts, list(extra) + ["-ts_max_steps", "2"], ranks=ranks)
    return (p.returncode, compare3d.error_lines(p), p, time.time() - t0,
            resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)


def one_line(rc, lines, p, *needles):
    return (rc == 2 and len(lines) == 1 and not compare3d.petsc_trace(p) and
            all(n in lines[0] for n in needles))


# The estimate against the runs' own counts.
for name, opts in (("bar", BAR), ("two-level block", BLOCK)):
    rc, lines, p, _, _ = refused("estimate_" + name.split()[-1], opts,
                                 ["-gimp_memory_limit", "1"])
    m = SIZE.search(lines[0]) if lines else None
    out = os.path.join(args.work, "actual_" + name.split()[-1])
    run = capped("actual_" + name.split()[-1], opts, ["-ts_max_steps", "1"])
    s = gimptest.summary(out) if run.returncode == 0 else {"particles": -1, "levels": []}
    nodes = sum(lv["nodes"][0] * lv["nodes"][1] * lv["nodes"][2] for lv in s["levels"])
    ok = m is not None and float(m.group(1)) == s["particles"] and float(m.group(2)) == nodes
    c.check("estimate = the run's counts, " + name, ok,
            "estimated %s particles and %s nodes; the run: %d particles, %d nodes (%s)" % (
                m.group(1) if m else "?", m.group(2) if m else "?", s["particles"], nodes,
                " + ".join("x".join(map(str, lv["nodes"])) for lv in s["levels"])))

# The culprit named, with 3D values.
for name, opts, extra, culprit in (
        ("grid of the bar", BAR, [], "option -gimp_h 1:"),
        ("finer level", BLOCK, [], "option -gimp_level1_box 0.3,0.1,0.1,0.9,0.5,0.5:"),
        ("domain", BAR, ["-gimp_domain", "-2,-2,-2,27,3,3"],
         "option -gimp_domain -2,-2,-2,27,3,3:"),
        ("pad", BAR, ["-gimp_pad", "100"], "option -gimp_pad 100:"),
        ("particles per cell", BAR, ["-gimp_body0_ppc", "512"], "option -gimp_body0_ppc 512:"),
        ("a long body", BAR, ["-gimp_body0_box", "0,0,0,2000,1,1", "-gimp_body0_ppc", "27"],
         "option -gimp_body0_box 0,0,0,2000,1,1:")):
    rc, lines, p, _, _ = refused("culprit", opts, extra + ["-gimp_memory_limit", "1"])
    c.check("culprit: " + name, one_line(rc, lines, p, culprit, "of -gimp_memory_limit"),
            "exit %d: %s" % (rc, (lines or [p.stderr.strip()[-200:]])[0][:170]))

# The limit at the estimate.
rc, lines, p, _, _ = refused("limit", BAR, ["-gimp_memory_limit", "1"])
gb = re.search(r"about (\S+) GB of memory", lines[0] if lines else "")
est = float(gb.group(1)) * 1e9 if gb else 0.0
rc_lo, lines_lo, p_lo, _, _ = refused("limit_lo", BAR, ["-gimp_memory_limit", "%.6g" % (0.9 * est)])
p_hi = capped("limit_hi", BAR, ["-gimp_memory_limit", "%.6g" % (1.1 * est), "-ts_max_steps", "2"])
c.check("limit at the estimate", est > 0 and one_line(rc_lo, lines_lo, p_lo, "-gimp_memory_limit")
        and p_hi.returncode == 0,
        "estimate %.4g bytes: at 0.9 of it exit %d, at 1.1 of it exit %d" %
        (est, rc_lo, p_hi.returncode))

# The default limit: physical memory; refused before allocating.
rc, lines, p, secs, rss = refused("physical", BAR, ["-gimp_h", "0.005", "-ts_dt", "5e-5"])
c.check("physical memory", one_line(rc, lines, p, "option -gimp_h 0.005:",
                                    "of physical memory (-gimp_memory_limit)")
        and secs < 10 and rss < 200 * 1024,
        "exit %d in %.1f s, peak resident size so far %.0f MB: %s" % (
            rc, secs, rss / 1024.0, (lines or [p.stderr.strip()[-200:]])[0][:150]))

# PetscInt.
for name, extra, needle in (
        ("nodes", ["-gimp_h", "1e-4", "-ts_dt", "1e-6"], "more than PetscInt can index"),
        ("particles", ["-gimp_h", "0.02", "-gimp_body0_ppc", "1000", "-ts_dt", "1e-4"],
         "more than the particle swarm counts in a PetscInt")):
    rc, lines, p, secs, _ = refused("petscint", BAR, extra + ["-gimp_memory_limit", "1e30"])
    c.check("PetscInt: " + name, one_line(rc, lines, p, needle),
            "exit %d in %.1f s: %s" % (rc, secs, (lines or [p.stderr.strip()[-200:]])[0][:200]))

# Two ranks: one line; the swarm counts all particles in one PetscInt, so two ranks do not
# lift that limit.
rc, lines, p, _, _ = refused("np2_limit", BAR, ["-gimp_memory_limit", "1"], ranks=2)
c.check("2 ranks: one line", one_line(rc, lines, p, "option -gimp_h 1:", "-gimp_memory_limit"),
        "exit %d, %d error lines: %s" % (rc, len(lines), (lines or [""])[0][:120]))
rc, lines, p, _, _ = refused("np2_particles", BAR, ["-gimp_h", "0.02", "-gimp_body0_ppc", "1000",
                                                    "-ts_dt", "1e-4"], ranks=2)
c.check("2 ranks: particles in all", one_line(rc, lines, p, "option -gimp_body0_ppc 1000:",
                                               "more than the particle swarm counts in a PetscInt"),
        "exit %d, %d error lines: %s" % (rc, len(lines), (lines or [""])[0][:160]))
c.done()
