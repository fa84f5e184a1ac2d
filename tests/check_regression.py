"""Regression tier: every scene (options/*.opts and bench/*.opts, 2D and 3D alike) and a few
variants of them (VARIANTS: step options that no scene file uses) run a few dozen steps (a few
hundred where bodies move across ranks) on 1 and 2 ranks, and their outputs must equal the
references stored in tests/regression/<name>.<ranks>.json to 1e-12.

    python3 tests/check_regression.py --gimp build/gimp                 (every scene, 1 and 2 ranks)
    python3 tests/check_regression.py --gimp build/gimp --scene patch block3d --ranks 2
    python3 tests/check_regression.py --gimp build/gimp --extra '-gimp_nu 0.3001'  (must fail)
    python3 tests/check_regression.py --gimp build/gimp --regen [--scene ...] [--steps N]
    python3 tests/check_regression.py --references     (every scene has both references, and
                                                        every reference a scene; runs nothing)
(tools/regen_regression.py is --regen with the defaults filled in.)

A run, from the scene's directory (scenes include others by relative name):
    [mpiexec -n R] gimp [-options_file BASE] -options_file <scene> [OPTIONS]
        -gimp_output_dir <work dir> -gimp_output_interval 0 -gimp_history_interval H
        -ts_max_steps N -gimp_particle_dump <work dir>/particles.csv [--extra options]
N (steps), H (history interval), BASE (only for a fragment that adds to another scene:
rest_tension_levels.opts on rest_tension.opts) and OPTIONS (a variant's) are stored in the
reference, so that a check and a regeneration run the same thing; a new reference takes them
from STEPS, BASE and VARIANTS below (H = N / 12).

A reference holds the exit code, summary.json (less the timing keys), every history.csv row
and the particle dump: whole for a scene of at most FULL_ROWS particles, else a digest (see
digest()). The comparison, as runs/compare_scenes.py's:

summary.json  every leaf. Strings, booleans and nulls must be equal. Numbers are compared
    within a *family*: the leaf's path with digits removed (levels[2].box[1] ->
    levels[].box[], probes.tip.stress[3] -> probes.tip.stress[]), and the members of
    "energy" form one family; difference = |a - b| / S with S = max |v| over the family in
    both runs, so a near-zero component (momentum_y, a shear stress) is measured against the
    size of its siblings.
history.csv   rows matched by step, columns by name; per column max |a - b| / S_col with S_col
    = max |v| of the column over both runs. A missing or added row fails.
particles     whole dumps: as history.csv, rows matched by id. Digests: the ids must be equal
    (count and hash), and each column's min, max, block sums and signed block sums differ by
    at most tol x S_col (S_col = max |v| of the column): a change of one particle in a block
    of BLOCK shows undiluted in its block's sums.
A key or column of the reference missing from the new output fails; one only in the new output
is reported and does not fail (new keys may be added). An exit code that differs fails.
Timing keys (SKIP_KEYS, and any key ending in "seconds" or "per_second") are not compared.

Exit 0 iff every run passes; details of every run in <work>/regression.json.
"""
import argparse
import csv
import hashlib
import json
import math
import os
import shlex
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
REFERENCES = os.path.join(HERE, "regression")
SCENE_DIRS = ("options", "bench")  # relative to the repository root
RANKS = (1, 2)

# What a new reference runs (a stored reference keeps its own values; --steps overrides).
# Costs measured on the 2-core machine with the baseline binary: every scene but two runs 60
# steps on 1 or 2 ranks in 0.4 to 1 s, about 0.35 s of it start-up; none has a costly setup.
DEFAULT_STEPS = 60  # past the first particle sort (-gimp_sort_interval 50)
STEPS = {
    # 3D blocks of 1e5 particles, 0.06 s a step
    "block3d": 30, "block3d_levels": 30, "block3d_tenth": 20,
    # an inclined penny crack in a block of 1.3e5 particles on four levels (0.15 s a step; the
    # load reaches the crack in neither 12 nor 30 steps, and 12 run every path the 30 did)
    "penny_inclined3d": 12,
    # a penny crack that grows from step 80 (0.05 s a step)
    "penny_growth3d": 110,
    # bodies that move far enough for particles to change rank on 2 ranks (the scene's own
    # length, or the steps until the first migrations)
    "drift": 400, "drift3": 480, "migrate3d": 300, "disks": 300,
    "drift3-multirate": 480, "drift3-cpdi": 480, "drift3-cpdi2": 480,
    "migrate3d-corners": 300, "migrate3d-cpdi2": 300,
}
# Scenes whose history rows cost more than a step (the K along a crack front: about 0.5 s a
# row on the inclined penny crack): a row every HISTORY steps instead of every steps / 12.
HISTORY = {"penny_inclined3d": 4, "penny3d": 15}
# Fragments that are not a scene on their own: run on top of the scene they extend.
BASE = {"rest_tension_levels": "rest_tension.opts", "spin3d_levels": "spin3d.opts"}
# Variants "<scene>-<tag>": the scene with options that no scene file sets, so that every
# step variant is in the tier: multi-rate steps (both force rules; in 3D too), CPDI domains, USF,
# XPIC, the stability check (SLEPc), 3D FLIP with USL, 3D corner and CPDI domains (crossing
# ranks).
VARIANTS = {
    "drift3-multirate": ["-gimp_multirate", "true"],
    "block3d_multirate-multirate": ["-gimp_multirate", "true"],
    "rest_tension_levels-multirate_node": ["-gimp_multirate", "true", "-gimp_multirate_forces",
                                           "node", "-gimp_update", "usl"],
    "drift3-cpdi": ["-gimp_tracking", "cpdi"],
    "drift3-cpdi2": ["-gimp_tracking", "cpdi2"],
    "patch3-usf": ["-gimp_update", "usf"],
    "patch3-xpic": ["-gimp_transfer", "xpic", "-gimp_xpic_order", "3"],
    "patch3-stability": ["-gimp_stability_check", "true"],
    "patch3d-flip_usl": ["-gimp_transfer", "flip", "-gimp_update", "usl"],
    "tension3d-cpdi": ["-gimp_tracking", "cpdi"],
    "migrate3d-corners": ["-gimp_tracking", "corners"],
    "migrate3d-cpdi2": ["-gimp_tracking", "cpdi2"],
}

SKIP_KEYS = {"wall_seconds", "setup_seconds", "cpu_seconds", "version",
             "particle_steps_per_second"}
SHARED_UNIT_DICTS = {"energy"}
FULL_ROWS = 128  # particle dumps up to this many rows are stored whole
BLOCK = 1024     # particles per block of a digest


# ---------------------------------------------------------------------------------------------
# Scenes and runs

def scenes(root):
    """{name: (path relative to root, options)} of every scene file and variant; a name in two
    directories is an error (references are named by scene)."""
    found = {}
    for d in SCENE_DIRS:
        for f in sorted(os.listdir(os.path.join(root, d))):
            if f.endswith(".opts"):
                name = f[:-len(".opts")]
                if name in found:
                    raise SystemExit("check_regression: scene %s is both %s and %s/%s"
                                     % (name, found[name][0], d, f))
                found[name] = (os.path.join(d, f), [])
    for name, options in VARIANTS.items():
        scene = name.partition("-")[0]
        if scene in found:  # else its reference has no scene: --references says so
            found[name] = (found[scene][0], options)
    return found


def ref_path(name, ranks):
    return os.path.join(REFERENCES, "%s.%d.json" % (name, ranks))


def skipped(key):
    return key in SKIP_KEYS or key.endswith("seconds") or key.endswith("per_second")


def clean(node):
    """summary.json without the timing keys."""
    if isinstance(node, dict):
        return {k: clean(v) for k, v in node.items() if not skipped(k)}
    if isinstance(node, list):
        return [clean(v) for v in node]
    return node


def run(args, root, scene_file, plan, ranks, out):
    """Run one scene into an emptied directory out; (exit code, seconds, last stderr line)."""
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    cwd = os.path.dirname(os.path.join(root, scene_file))
    cmd = [args.gimp]
    if plan["base"]:
        cmd += ["-options_file", os.path.join(cwd, plan["base"])]
    cmd += ["-options_file", os.path.join(root, scene_file)] + plan["options"]
    cmd += ["-gimp_output_dir", out,
            "-gimp_output_interval", "0", "-gimp_history_interval", str(plan["history_interval"]),
            "-ts_max_steps", str(plan["steps"]),
            "-gimp_particle_dump", os.path.join(out, "particles.csv")]
    cmd += shlex.split(args.extra)
    if ranks > 1:
        cmd = [args.mpiexec, "-n", str(ranks)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True, errors="replace",
                           timeout=args.timeout)
        rc, err = p.returncode, [l for l in p.stderr.splitlines() if l.strip()]
    except subprocess.TimeoutExpired:
        rc, err = "timeout", ["killed after %g s" % args.timeout]
    except OSError as e:
        rc, err = 127, [str(e)]
    with open(os.path.join(out, "command.txt"), "w") as f:
        f.write("cd %s && %s\n" % (shlex.quote(cwd), " ".join(shlex.quote(c) for c in cmd)))
    return rc, time.monotonic() - t0, err[-1] if err else ""


# ---------------------------------------------------------------------------------------------
# Outputs as stored in a reference

def read_table(path):
    """A CSV of numbers as {"columns": [...], "rows": [[...], ...]}, or None if absent. The key
    column (step, id) is read as int, the others as float (nan and inf included)."""
    try:
        with open(path, newline="") as f:
            rows = [r for r in csv.reader(f) if r]
        key = rows[0][0] in ("step", "id")
        return {"columns": rows[0],
                "rows": [[int(r[0]) if key else float(r[0])] + list(map(float, r[1:]))
                         for r in rows[1:]]}
    except (OSError, IndexError, ValueError):  # absent, empty or not numbers: as if absent
        return None


def exact_sum(values):
    """The correctly rounded sum (math.fsum): the same numbers give the same sum in any order,
    and a change to one of them shows in full. Sums with inf or nan are plain sums."""
    try:
        return math.fsum(values)
    except (ValueError, OverflowError):
        return sum(values)


def sign(pid):
    """A fixed pseudo-random +1 or -1 per particle id, for the signed block sums."""
    return 1.0 if (pid * 2654435761) >> 13 & 1 else -1.0


def digest(table, block):
    """The particle dump (rows sorted by id) as: the count and a hash of the ids; per column the
    min, the max, and per block of `block` rows the sum and the signed sum (+-1 by id), so that
    changes that cancel in a block's sum (an exchange between particles) show in its signed
    sum."""
    cols, rows = table["columns"], table["rows"]
    ids = [r[0] for r in rows]
    res = {"columns": cols, "count": len(rows), "block": block,
           "ids_sha256": hashlib.sha256(",".join(map(str, ids)).encode()).hexdigest(),
           "min": {}, "max": {}, "sum": {}, "signed": {}}
    w = [sign(i) for i in ids]
    for j, c in enumerate(cols[1:], 1):
        v = [float(r[j]) for r in rows]
        res["min"][c] = min(v, default=0.0)
        res["max"][c] = max(v, default=0.0)
        res["sum"][c] = [exact_sum(v[k:k + block]) for k in range(0, len(v), block)]
        res["signed"][c] = [exact_sum(a * b for a, b in zip(v[k:k + block], w[k:k + block]))
                            for k in range(0, len(v), block)]
    return res


def collect(out, rc, block=None):
    """What a run left in out, in the reference layout (without the plan). block: "whole" keeps
    the particle dump whole, a number digests it with blocks of that size (as the reference
    does), None decides by size (whole up to FULL_ROWS particles)."""
    try:
        with open(os.path.join(out, "summary.json")) as f:
            summary = clean(json.load(f))
    except (OSError, ValueError):
        summary = None
    parts = read_table(os.path.join(out, "particles.csv"))
    if parts is not None and block != "whole":
        if block is not None or len(parts["rows"]) > FULL_ROWS:
            parts = digest(parts, block or BLOCK)
    return {"exit_code": rc, "summary": summary,
            "history": read_table(os.path.join(out, "history.csv")), "particles": parts}


def dumps(node, indent=0):
    """JSON with one line per list of scalars (a row, a column of block sums) and one key per
    line above that: compact, diffable, every float as repr (full precision)."""
    pad = " " * indent
    if isinstance(node, dict) and node:
        items = ["%s %s: %s" % (pad, json.dumps(k), dumps(v, indent + 1)) for k, v in node.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(node, list) and any(isinstance(v, (dict, list)) for v in node):
        items = ["%s %s" % (pad, dumps(v, indent + 1)) for v in node]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    return json.dumps(node, separators=(",", ":"))


# ---------------------------------------------------------------------------------------------
# Comparison

def is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def diff(a, b, scale):
    """|a - b| / scale; 0 for equal values (NaN == NaN), inf if it cannot be measured."""
    if a == b or (math.isnan(a) and math.isnan(b)):
        return 0.0
    d = abs(a - b)
    return d / scale if scale > 0 and math.isfinite(d) else math.inf


def flatten(node, path, out):
    """Leaves of a JSON tree as {path: (family, value)}."""
    if isinstance(node, dict):
        for k, v in node.items():
            if not skipped(k):
                flatten(v, "%s.%s" % (path, k) if path else k, out)
    elif isinstance(node, list):
        for i, v in enumerate(node):
            flatten(v, "%s[%d]" % (path, i), out)
    else:
        parent = path.rpartition(".")[0]
        fam = parent if parent in SHARED_UNIT_DICTS else path
        out[path] = ("".join(c for c in fam if not c.isdigit()), node)
    return out


class Result:
    """The worst difference of one part (summary, history, particles) and what to show."""

    def __init__(self):
        self.worst, self.where, self.fails, self.added = 0.0, "", [], []

    def see(self, d, where, ref, new, tol):
        if d > self.worst:
            self.worst, self.where = d, where
        if d > tol:
            self.fails.append((d, where, ref, new))

    def fail(self, what):
        """A failure that is not a difference of values (a missing key, column or row)."""
        self.worst, self.where = math.inf, what
        self.fails.append((math.inf, what))


def compare_summary(ref, new, tol):
    r = Result()
    if ref is None or new is None:
        if ref is not None:
            r.fail("summary.json missing")
        elif new is not None:
            r.added.append("summary.json")
        return r
    A, B = flatten(ref, "", {}), flatten(new, "", {})
    scale = {}
    for fam, v in list(A.values()) + list(B.values()):
        if is_num(v) and math.isfinite(v):
            scale[fam] = max(scale.get(fam, 0.0), abs(float(v)))
    for key in A:
        if key not in B:
            r.fail("missing " + key)
            continue
        (fam, a), (_, b) = A[key], B[key]
        if is_num(a) and is_num(b):
            r.see(diff(float(a), float(b), scale.get(fam, 0.0)), key, a, b, tol)
        else:
            r.see(0.0 if a == b else math.inf, key, a, b, tol)
    r.added = [k for k in B if k not in A]
    return r


def compare_table(ref, new, key, tol, what):
    """Per-column normalised max difference of two tables, rows matched by column key."""
    r = Result()
    if ref is None or new is None:
        if ref is not None:
            r.fail(what + " missing")
        elif new is not None:
            r.added.append(what)
        return r
    ha, hb = ref["columns"], new["columns"]
    r.added = [c for c in hb if c not in ha]
    ka, kb = ha.index(key) if key in ha else None, hb.index(key) if key in hb else None
    ia = {(row[ka] if ka is not None else n): row for n, row in enumerate(ref["rows"])}
    ib = {(row[kb] if kb is not None else n): row for n, row in enumerate(new["rows"])}
    if set(ia) != set(ib):
        r.fail("%s rows: %d in the reference, %d new, %d of them in both"
               % (what, len(ia), len(ib), len(set(ia) & set(ib))))
    common = [k for k in ia if k in ib]
    for c in ha:
        if c not in hb:
            r.fail("%s column %s missing" % (what, c))
            continue
        if c == key:
            continue
        ca, cb = ha.index(c), hb.index(c)
        vals = [abs(row[ca]) for row in ref["rows"]] + [abs(row[cb]) for row in new["rows"]]
        scale = max([v for v in vals if math.isfinite(v)], default=0.0)
        for k in common:
            a, b = ia[k][ca], ib[k][cb]
            r.see(diff(a, b, scale), "%s at %s %s" % (c, key, k), a, b, tol)
    return r


def compare_digest(ref, new, tol):
    """Particle digests: ids equal, each column's min, max and block sums within tol x S_col."""
    r = Result()
    if ref["count"] != new["count"] or ref["ids_sha256"] != new["ids_sha256"]:
        r.fail("particle ids: %d in the reference, %d new%s" % (
            ref["count"], new["count"], ", not the same ids" if ref["count"] == new["count"]
            else ""))
        return r
    r.added = [c for c in new["columns"] if c not in ref["columns"]]
    for c in ref["columns"][1:]:
        if c not in new["columns"]:
            r.fail("particles column %s missing" % c)
            continue
        vals = [abs(x) for d in (ref, new) for x in (d["min"][c], d["max"][c])]
        scale = max([v for v in vals if math.isfinite(v)], default=0.0)
        for stat in ("min", "max"):
            r.see(diff(ref[stat][c], new[stat][c], scale), "%s %s" % (c, stat),
                  ref[stat][c], new[stat][c], tol)
        for stat in ("sum", "signed"):
            for k, (a, b) in enumerate(zip(ref[stat][c], new[stat][c])):
                r.see(diff(a, b, scale), "%s %s of block %d (rows %d-%d)" % (
                    c, stat, k, k * ref["block"], min((k + 1) * ref["block"], ref["count"]) - 1),
                    a, b, tol)
    return r


def compare_particles(ref, new, tol):
    if ref is not None and new is not None and "ids_sha256" in ref:
        return compare_digest(ref, new, tol)
    return compare_table(ref, new, "id", tol, "particles")


# ---------------------------------------------------------------------------------------------

def plan_of(name, reference, regen, steps):
    """Steps, history interval, base file and options of a run. A check runs what the reference
    stores. A regeneration takes the base and options from BASE and VARIANTS, the steps from
    --steps, else the reference, else STEPS (so that regenerating runs the same steps again),
    and a history row every steps / 12 steps (HISTORY for the costly rows)."""
    if not regen:
        return {k: reference[k] for k in ("steps", "history_interval", "base", "options")}
    n = steps or (reference or {}).get("steps") or STEPS.get(name, DEFAULT_STEPS)
    return {"steps": n, "history_interval": HISTORY.get(name, max(1, n // 12)),
            "base": BASE.get(name.partition("-")[0]), "options": VARIANTS.get(name, [])}


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except FileNotFoundError:
        return None


def fmt(r):
    return "%.2e (%s)" % (r.worst, r.where) if r.where else "%.2e" % r.worst


def check_references(root):
    """Every scene and variant has a reference for every rank count, and every reference has a
    scene and runs what BASE and VARIANTS say (else it is out of date: regenerate it)."""
    names = scenes(root)
    problems = ["%s: no reference %s (tools/regen_regression.py --scene %s)"
                % (n, os.path.relpath(ref_path(n, k), root), n)
                for n in names for k in RANKS if not os.path.exists(ref_path(n, k))]
    for f in sorted(os.listdir(REFERENCES)):
        base, _, ranks = f[:-len(".json")].rpartition(".") if f.endswith(".json") else ("", "", "")
        if base not in names or not ranks.isdigit() or int(ranks) not in RANKS:
            problems.append("tests/regression/%s: no scene or rank count of that name" % f)
            continue
        ref = load(os.path.join(REFERENCES, f))
        if ref.get("scene") != base or ref.get("file") != names[base][0]:
            problems.append("tests/regression/%s: made for %s (%s), not %s"
                            % (f, ref.get("scene"), ref.get("file"), names[base][0]))
        elif (ref.get("options"), ref.get("base")) != (names[base][1],
                                                       BASE.get(base.partition("-")[0])):
            problems.append("tests/regression/%s: runs %s on %s, VARIANTS and BASE say %s on %s "
                            "(tools/regen_regression.py --scene %s)" % (
                                f, ref.get("options"), ref.get("base"), names[base][1],
                                BASE.get(base.partition("-")[0]), base))
    for p in problems:
        print("FAIL " + p)
    print("%s: %d scenes and variants x %d rank counts, %d reference files" % (
        "FAIL" if problems else "PASS", len(names), len(RANKS),
        len([f for f in os.listdir(REFERENCES) if f.endswith(".json")])))
    return 1 if problems else 0


def regenerate(args, name, ranks, scene_file, plan, out, path):
    """Run a scene and write its reference; one line of what was stored."""
    rc, secs, err = run(args, args.root, scene_file, plan, ranks, out)
    ref = dict({"scene": name, "file": scene_file, "ranks": ranks}, **plan, **collect(out, rc))
    os.makedirs(REFERENCES, exist_ok=True)
    with open(path, "w") as f:
        f.write(dumps(ref) + "\n")
    rows = {k: "no" if t is None else t.get("count", len(t.get("rows", [])))
            for k, t in (("history", ref["history"]), ("particles", ref["particles"]))}
    print("%-34s %5d %5d %7.2f  exit %s, %s history rows, %s particles -> %s%s" % (
        name, ranks, plan["steps"], secs, rc, rows["history"], rows["particles"],
        os.path.relpath(path, args.root), " (%s)" % err if rc else ""), flush=True)
    return {"scene": name, "ranks": ranks, "steps": plan["steps"], "seconds": round(secs, 3),
            "exit_code": rc}


def check(args, name, ranks, scene_file, ref, out):
    """Run a scene as its reference says and compare; one line, and the worst differences of
    a failing run below it."""
    rc, secs, err = run(args, args.root, scene_file, plan_of(name, ref, False, None), ranks, out)
    block = None if ref["particles"] is None else ref["particles"].get("block", "whole")
    new = collect(out, rc, block)
    parts = {"summary": compare_summary(ref["summary"], new["summary"], args.tol),
             "history": compare_table(ref["history"], new["history"], "step", args.tol,
                                      "history"),
             "particles": compare_particles(ref["particles"], new["particles"], args.tol)}
    rc_ok = rc == ref["exit_code"]
    ok = rc_ok and not any(p.fails for p in parts.values())
    print("%-34s %5d %5d %7.2f  %-40s %-40s %-40s %s" % (
        name, ranks, ref["steps"], secs, fmt(parts["summary"])[:40], fmt(parts["history"])[:40],
        fmt(parts["particles"])[:40], "PASS" if ok else "FAIL"), flush=True)
    if not rc_ok:
        print("  exit code %s, the reference's %s: %s" % (rc, ref["exit_code"], err))
    for what, p in parts.items():
        for f in sorted(p.fails, key=lambda f: -f[0])[:5]:
            if len(f) == 2:
                print("  %s: %s" % (what, f[1]))
            else:
                print("  %s: %.3e at %s: reference %r, new %r" % ((what,) + f))
        if len(p.fails) > 5:
            print("  %s: %d more differences above %g" % (what, len(p.fails) - 5, args.tol))
        if p.added:
            print("  %s: only in the new output (not a failure): %s" % (what, ", ".join(p.added)))
    # The particle dump of a passing run is not kept (up to 40 MB).
    if ok and os.path.exists(os.path.join(out, "particles.csv")):
        os.remove(os.path.join(out, "particles.csv"))
    return {"scene": name, "ranks": ranks, "steps": ref["steps"], "seconds": round(secs, 3),
            "exit_code": rc, "pass": ok,
            "worst": {k: [str(p.worst), p.where] for k, p in parts.items()},
            "added": {k: p.added for k, p in parts.items() if p.added}}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gimp", help="the binary under test")
    ap.add_argument("--root", default=ROOT, help="the repository (its options/ and bench/)")
    ap.add_argument("--work", default="/tmp/gimp-regression", help="scratch directory")
    ap.add_argument("--mpiexec", default="mpiexec")
    ap.add_argument("--scene", nargs="+", metavar="NAME", help="only these scenes or variants")
    ap.add_argument("--ranks", nargs="+", type=int, default=list(RANKS), choices=RANKS)
    ap.add_argument("--extra", default="",
                    help="gimp options appended to every run (to see the tier fail on a "
                         "changed answer, e.g. --extra '-gimp_nu 0.3001')")
    ap.add_argument("--tol", type=float, default=1e-12)
    ap.add_argument("--timeout", type=float, default=300, help="seconds per run")
    ap.add_argument("--regen", action="store_true",
                    help="write the references from this binary's runs instead of checking")
    ap.add_argument("--steps", type=int, help="with --regen: steps of the scenes regenerated")
    ap.add_argument("--references", action="store_true",
                    help="only check that references and scenes match one to one")
    args = ap.parse_args(argv)
    args.root = os.path.abspath(args.root)
    if args.references:
        return check_references(args.root)
    if not args.gimp:
        ap.error("--gimp is required")
    if args.regen and args.extra:
        ap.error("--regen with --extra would store a perturbed answer")
    if args.steps is not None and not args.regen:
        ap.error("--steps goes with --regen (a check runs the reference's steps)")
    args.gimp, work = os.path.abspath(args.gimp), os.path.abspath(args.work)
    names = scenes(args.root)
    unknown = [n for n in args.scene or [] if n not in names]
    if unknown:
        ap.error("no scene or variant " + ", ".join(unknown))
    os.makedirs(work, exist_ok=True)
    if args.regen:
        print("%-34s %5s %5s %7s  %s" % ("scene", "ranks", "steps", "seconds", "stored"))
    else:
        print("%-34s %5s %5s %7s  %-40s %-40s %-40s %s" % (
            "scene", "ranks", "steps", "seconds", "summary", "history", "particles", "verdict"))
    report = []
    for name in args.scene or sorted(names):
        for ranks in args.ranks:
            path = ref_path(name, ranks)
            ref = load(path)
            out = os.path.join(work, "%s.np%d" % (name, ranks))
            if args.regen:
                plan = plan_of(name, ref, True, args.steps)
                report.append(regenerate(args, name, ranks, names[name][0], plan, out, path))
                if os.path.exists(os.path.join(out, "particles.csv")):  # stored in the reference
                    os.remove(os.path.join(out, "particles.csv"))
            elif ref is None:
                print("%-34s %5d  FAIL: no reference %s (tools/regen_regression.py --scene %s)"
                      % (name, ranks, os.path.relpath(path, args.root), name), flush=True)
                report.append({"scene": name, "ranks": ranks, "pass": False,
                               "error": "no reference"})
            else:
                report.append(check(args, name, ranks, names[name][0], ref, out))
            # The fields (up to 60 MB) are never compared.
            if os.path.exists(os.path.join(out, "fields.h5")):
                os.remove(os.path.join(out, "fields.h5"))
    ok_all = all(r.get("pass", True) for r in report)
    with open(os.path.join(work, "regression.json"), "w") as f:
        json.dump({"gimp": args.gimp, "extra": args.extra, "tol": args.tol,
                   "regen": args.regen, "pass": ok_all, "runs": report}, f, indent=1)
    total = sum(r.get("seconds", 0) for r in report)
    if args.regen:
        print("wrote %d references in %.1f s of runs" % (len(report), total))
        return 0
    print("%s: %d/%d runs equal their references within %g (%.1f s of runs); details in %s"
          % ("PASS" if ok_all else "FAIL", sum(r["pass"] for r in report), len(report),
             args.tol, total, os.path.join(work, "regression.json")))
    return 0 if ok_all else 1


if __name__ == "__main__":
    sys.exit(main())
