"""Faults found while a scene is set up or run (docs/validation.md, *Unstable runs* and *Bad input
and faults*), serial and under mpiexec -n 2. Every case ends with exactly one non-empty stderr
line, `gimp: error: ...` holding the case's texts, an exit code that is not a signal (3 for a run
that went unstable, 2 for bad input or no memory), within the timeout; warnings are checked on
stdout, once.

- a run that went unstable is named so, with the quantity that grew, even when the particle then
  leaves the grid: a load of 1e5 E (2D, 3D, 2 ranks), a time step forced above the critical step
  with -gimp_allow_unstable_dt (2D, 3D; warned at the start); the line names the time step
  against h_min / c_p; a particle that leaves the grid moving as a solid does (drift) is not
  called unstable;
- a body flush with the domain's edge is warned of alike in 2D and 3D (also when round-off puts
  its particles' edges 1 ulp past it) and a body at rest there runs;
- options gimp hands to PETSc objects: -da_processors_x/y that do not fit the ranks, a misspelt
  eigen-solver type, a viewer PETSc would meet at exit (-log_view);
- size: a 3D grid beyond PetscInt; an allocation that fails under an address-space limit with
  -gimp_memory_limit raised above it (std::bad_alloc or PETSc's out-of-memory error)."""
import json
import os
import subprocess
import sys
import time
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
R = args.root
PATCH = os.path.join(R, "options", "patch.opts")
PATCH3D = os.path.join(R, "options", "patch3d.opts")
DRIFT = os.path.join(R, "options", "drift.opts")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
TIMEOUT = 60
launcher = subprocess.run([args.mpiexec, "--version"], capture_output=True, text=True)
QUIET = ["-q"] if "Open MPI" in launcher.stdout + launcher.stderr or \
    "OpenRTE" in launcher.stdout + launcher.stderr else []
# An address-space limit for gimp alone (not the launcher): its allocations fail beyond it.
LIMITED = ("import os, resource, sys\n"
           "n = int(sys.argv[1])\n"
           "resource.setrlimit(resource.RLIMIT_AS, (n, n))\n"
           "os.execv(sys.argv[2], sys.argv[2:])\n")


def gimp(name, opts, ranks=1, address_limit=None):
    """Run gimp; (returncode or None on timeout, stdout, stderr, output directory)."""
    out = os.path.join(W, name.replace(" ", "_") + ("_np%d" % ranks))
    cmd = [args.gimp] + opts + ["-gimp_output_dir", out]
    if address_limit is not None:
        cmd = [sys.executable, "-c", LIMITED, str(address_limit)] + cmd
    if ranks > 1:
        cmd = [args.mpiexec] + QUIET + ["-n", str(ranks)] + cmd
    try:
        p = subprocess.run(cmd, cwd=W, env=ENV, capture_output=True, text=True,
                           timeout=TIMEOUT, errors="replace")
        return p.returncode, p.stdout, p.stderr, out
    except subprocess.TimeoutExpired:
        return None, "", "(hung: killed after %d s)" % TIMEOUT, out


def one_error(name, opts, needles, code, ranks=1, absent=(), warning=None, address_limit=None,
              status=None):
    """Exactly one stderr line, `gimp: error:` with every needle and none of `absent`; exit code
    `code`; `warning` (if given) once on stdout; summary.json's status (if given)."""
    t0 = time.time()
    rc, out, err, outdir = gimp(name, opts, ranks, address_limit)
    lines = [l for l in err.splitlines() if l.strip()]
    ok = rc == code and len(lines) == 1 and lines[0].startswith("gimp: error: ")
    ok = ok and all(n in lines[0] for n in needles) and not any(a in lines[0] for a in absent)
    detail = "exit %s, %.1f s: %s" % (rc, time.time() - t0, " | ".join(lines[:3])[:400])
    if warning is not None:
        warned = [l for l in out.splitlines() if l.startswith("gimp: warning:")]
        ok = ok and len(warned) == 1 and warning in warned[0]
        detail += " | warnings: %s" % warned
    if status is not None:
        try:
            with open(os.path.join(outdir, "summary.json")) as f:
                got = json.load(f)["status"]
        except (OSError, ValueError, KeyError):
            got = None
        ok = ok and got == status
        detail += " | status %s" % got
    c.check("%s%s" % (name, " (2 ranks)" if ranks > 1 else ""), ok, detail)


# The cases run two at a time (gimptest.concurrently) once they are all listed.
cases = []


def later(f, *a, **k):
    cases.append(lambda: f(*a, **k))


def patch(*extra):
    return ["-options_file", PATCH] + list(extra)


def patch3d(*extra):
    return ["-options_file", PATCH3D] + list(extra)


# --- 1. the right diagnosis: unstable, not "left the grid" ------------------------------------
LOAD2 = ("-gimp_traction0_value", "1e12,0", "-gimp_traction1_value", "-1e12,0")
LOAD3 = ("-gimp_traction0_value", "1e12,0,0", "-gimp_traction1_value", "-1e12,0,0")
GREW = ["step 1 t 0.00025", "its speed", "times c_p = 116.023870223 m/s", "the run went unstable",
        "dt 0.00025 s = 0.29 h_min / c_p (h_min / c_p = 0.000861892 s)"]
for ranks in (1, 2):
    later(one_error, "load of 1e5 E", patch(*LOAD2, "-ts_max_steps", "50"), GREW, 3, ranks,
              status="unstable")
later(one_error, "load of 1e5 E in 3D", patch3d(*LOAD3, "-ts_max_steps", "50"),
          ["step 1 t 0.000258567482", "its speed", "the run went unstable",
           "dt 0.000258567 s = 0.3 h_min / c_p"], 3, status="unstable")
FORCED = ("-gimp_stability_check", "-gimp_allow_unstable_dt", "-gimp_history_interval", "100000",
          "-ts_max_steps", "3000")
later(one_error, "dt forced far above the critical step", patch(*FORCED, "-ts_dt", "2e-3"),
          ["step 4 t 0.008 s", "its speed", "the run went unstable",
           "dt 0.002 s = 2.32 h_min / c_p (h_min / c_p = 0.000861892 s)"], 3,
          warning="-ts_dt 0.002 s exceeds dt_critical = 0.000786954252895 s "
                  "(-gimp_allow_unstable_dt): the run will likely go unstable; dt 0.002 s = 2.32 "
                  "h_min / c_p", status="unstable")
# --- 2. a forced time step: warned at the start, named in the failure line -------------------
later(one_error, "dt forced above the critical step", patch(*FORCED, "-ts_dt", "1e-3"),
          ["step 8 t 0.008 s", "is not positive", "the run went unstable",
           "dt 0.001 s = 1.16 h_min / c_p"], 3,
          warning="-ts_dt 0.001 s exceeds dt_critical = 0.000786954252895 s")
later(one_error, "dt forced above the critical step in 3D", patch3d(*FORCED, "-ts_dt", "2e-3"),
          ["step 5 t 0.01 s", "is not positive", "dt 0.002 s = 2.32 h_min / c_p"], 3,
          warning="-ts_dt 0.002 s exceeds dt_critical = 0.000729925134283 s")
later(one_error, "dt forced above the critical step", patch(*FORCED, "-ts_dt", "1e-3"),
          ["step 8 t 0.008 s", "the run went unstable", "dt 0.001 s = 1.16 h_min / c_p"], 3, 2,
          status="unstable")
# A particle that leaves the grid as a solid moves (0.34 c_p) is not called unstable.
later(one_error, "drift leaves the grid", ["-options_file", DRIFT, "-ts_max_steps", "3000"],
          ["step 482", "it left the grid domain (enlarge -gimp_domain"], 3,
          absent=["unstable", "c_p"], status="unstable")

# --- bodies flush with the domain's edge: warned of alike in 2D and 3D ------------------------
EDGE = "reaches the grid's edge (particle 0)"
REST2 = ("-gimp_traction0_value", "0,0", "-gimp_traction1_value", "0,0")
REST3 = ("-gimp_traction0_value", "0,0,0", "-gimp_traction1_value", "0,0,0")


def at_rest(name, opts):
    rc, out, err, _ = gimp(name, opts + ["-ts_max_steps", "20"])
    warned = [l for l in out.splitlines() if l.startswith("gimp: warning:")]
    c.check(name + " at rest: warned, runs", rc == 0 and not err.strip() and len(warned) == 1 and
            EDGE in warned[0], "exit %s: %s %s" % (rc, warned, err.strip()[:200]))


for name, opts in (("flush body in 2D", patch("-gimp_pad", "0", *REST2)),
                   ("flush body in 3D", patch3d("-gimp_pad", "0", *REST3))):
    later(at_rest, name, opts)
for name, opts in (("flush body in 2D", patch("-gimp_pad", "0")),
                   ("flush body in 3D", patch3d("-gimp_pad", "0"))):
    later(one_error, name + " pulled", opts + ["-ts_max_steps", "20"],
              ["step 1", "it left the grid domain (enlarge -gimp_domain"], 3,
              absent=["unstable"], warning=EDGE)

# --- 3. options handed to PETSc objects ------------------------------------------------------
for ranks in (1, 2):
    later(one_error, "more ranks along x than ranks",
          patch("-da_processors_x", "3", "-ts_max_steps", "1"),
              ["option -da_processors_x 3: Too many processors in X direction: 3 %d" % ranks,
               "their product the number of ranks"], 2, ranks)
later(one_error, "rank layout not the rank count",
          patch("-da_processors_x", "1", "-da_processors_y", "1", "-ts_max_steps", "1"),
          ["option -da_processors_x 1, -da_processors_y 1: Given Bad partition"], 2, 2)
later(one_error, "misspelt eigen-solver type",
          patch("-gimp_stability_check", "-gimp_stability_eps_type", "foo", "-ts_max_steps", "1"),
          ["option -gimp_stability_eps_type foo: Unknown EPS type given: foo"], 2, 2)
later(one_error, "misspelt spectral transform in 3D",
          patch3d("-gimp_stability_check", "-gimp_stability_st_type", "foo", "-ts_max_steps", "1"),
          ["option -gimp_stability_st_type foo: Unable to find requested ST type foo"], 2, 2)
later(one_error, "log viewer of unknown type", patch("-log_view", "foo:bar", "-ts_max_steps", "1"),
          ["option -log_view foo:bar: Unknown PetscViewer type given: foo"], 2)

# --- 5. sizes and memory ---------------------------------------------------------------------
later(one_error, "3D level beyond PetscInt", patch3d("-gimp_h", "0.0005", "-ts_max_steps", "1"),
          ["option -gimp_h 0.0005:", "1.3e+09 grid nodes (level 0: 2e+03 x 805 x 805)",
           "more than PetscInt can index"], 2, 2)
MEMORY = ["option -gimp_memory_limit: out of memory"]
for ranks in (1, 2):
    later(one_error, "memory limit above the machine's",
              patch3d("-gimp_h", "0.006", "-gimp_memory_limit", "1e12", "-ts_max_steps", "1"),
              MEMORY, 2, ranks, address_limit=1000 * 1000 * 1000)
gimptest.concurrently(cases)
c.done()
