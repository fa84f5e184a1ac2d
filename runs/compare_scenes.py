#!/usr/bin/env python3
"""Run every scene with two gimp binaries ("before" and "after") and compare the results.

    python3 runs/compare_scenes.py --before BIN_A --after BIN_B [--scenes DIR] [--work DIR]
                                   [--max-steps N] [--only NAME ...] [--tol 1e-12]

Each scene (options/*.opts, or the --only names) runs with
    -options_file <scene> -gimp_output_dir <work>/<before|after>/<scene>
    -gimp_particle_dump <that dir>/particles.csv -ts_max_steps <min(N, scene's own)>
    -gimp_output_interval 0
from the scenes directory (scenes include others by relative name). The outputs compared:

summary.json  every leaf, recursively. Keys 'wall_seconds', 'setup_seconds', 'cpu_seconds',
    'particle_steps_per_second' (timings) and 'version' are skipped. Strings and nulls must be equal (else difference = inf). Numbers are compared within a *family*:
    the leaf's path with list indices and digits removed (levels[2].box[1] -> levels[].box,
    probes.tip.stress[3] -> probes.tip.stress, measures.hoop_45 -> measures.hoop_), and the
    members of "energy" form one family (all in J). The difference of a leaf is
        |a - b| / S,   S = max |v| over the family in both runs,
    i.e. the max-norm relative difference of the family as a vector: plain relative for a
    lone scalar (time, kt, ...), while a near-zero component (momentum_y, a shear stress, KE
    at rest) is measured against the size of its siblings instead of blowing up. S = 0 (all
    zero) gives 0. A key only in "before" is a failure; one only in "after" is reported.
particles.csv rows matched by id, columns by name; per column max_i |a_i - b_i| / S_col with
    S_col = max |v| of that column over all particles of both runs (so a stress near zero on
    one particle does not dominate). Missing / extra ids are failures.
history.csv   rows matched by step (by position if there is no step column), columns by
    name; per column the same normalised maximum as for the particles.

A failing run (non-zero exit) is reported (exit code, last stderr line) and fails the scene
unless both binaries exit with the same code; existing outputs are still compared. A scene
that both binaries refuse (the same non-zero code, no outputs) passes when the last lines of
their stderr agree (a fragment that other scenes include, say). Caveat: a
quantity that is physically zero up to round-off (history momentum_x of patch, ~1e-14) is
normalised by its own round-off scale and shows O(1) differences as soon as the summation
order changes; compare.json has the absolute differences and scales. --families measures each
CSV column against the largest component of its quantity instead (vx against max(|vx|, |vy|),
sxy against the whole stress, momentum_y against every momentum component, KII_J against KI_J:
family_of), which leaves O(1) only where every component is round-off (the total momentum of a
body at rest). Exit 0 iff all within --tol.
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import time

SKIP_KEYS = {"wall_seconds", "setup_seconds", "cpu_seconds", "particle_steps_per_second",
             "version"}
SHARED_UNIT_DICTS = {"energy"}


def scene_steps(path, cwd):
    """The scene's own -ts_max_steps (last occurrence wins, included files expanded), or None."""
    steps = None
    try:
        tokens = [t for line in open(path) for t in line.split("#")[0].split()]
    except OSError:
        return None
    for i, tok in enumerate(tokens[:-1]):
        if tok == "-options_file":
            inner = scene_steps(os.path.join(cwd, tokens[i + 1]), cwd)
            steps = inner if inner is not None else steps
        elif tok == "-ts_max_steps":
            steps = int(tokens[i + 1])
    return steps


def run(binary, scene_file, out, steps, cwd):
    """Run one scene into an emptied directory out; exit code, seconds, last stderr line."""
    for root, dirs, files in os.walk(out, topdown=False):
        for f in files:
            os.remove(os.path.join(root, f))
        for sub in dirs:
            os.rmdir(os.path.join(root, sub))
    os.makedirs(out, exist_ok=True)
    cmd = [binary, "-options_file", scene_file, "-gimp_output_dir", out,
           "-gimp_particle_dump", os.path.join(out, "particles.csv"),
           "-ts_max_steps", str(steps), "-gimp_output_interval", "0"]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
        rc, err = p.returncode, [l for l in p.stderr.splitlines() if l.strip()]
    except OSError as e:
        rc, err = 127, [str(e)]
    return {"rc": rc, "seconds": round(time.monotonic() - t0, 3), "stderr": err[-1] if err else ""}


def flatten(node, path, out):
    """Leaves of a JSON tree as {path: (family, value)}."""
    if isinstance(node, dict):
        for k, v in node.items():
            if k not in SKIP_KEYS:
                flatten(v, f"{path}.{k}" if path else k, out)
    elif isinstance(node, list):
        for i, v in enumerate(node):
            flatten(v, f"{path}[{i}]", out)
    else:
        parent = path.rpartition(".")[0]
        fam = parent if parent in SHARED_UNIT_DICTS else path
        out[path] = ("".join(c for c in fam if not c.isdigit()), node)
    return out


def diff(a, b, scale):
    """|a - b| / scale; 0 for equal values (NaN == NaN), inf if it cannot be measured."""
    if a == b or (math.isnan(a) and math.isnan(b)):
        return 0.0
    d = abs(a - b)
    return d / scale if scale > 0 and math.isfinite(d) else math.inf


def compare_summary(fa, fb):
    try:
        A = flatten(json.load(open(fa)), "", {})
        B = flatten(json.load(open(fb)), "", {})
    except (OSError, ValueError) as e:
        return {"error": str(e), "worst": math.inf, "key": "unreadable"}
    scale = {}
    for fam, v in list(A.values()) + list(B.values()):
        if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v):
            scale[fam] = max(scale.get(fam, 0.0), abs(float(v)))
    res = {"worst": 0.0, "key": "", "diffs": {},
           "missing": sorted(set(A) - set(B)), "added": sorted(set(B) - set(A))}
    for key in sorted(set(A) & set(B)):
        (fam, a), (_, b) = A[key], B[key]
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (a, b)):
            d = diff(float(a), float(b), scale.get(fam, 0.0))
        else:
            d = 0.0 if a == b else math.inf
        if d > 0:
            res["diffs"][key] = {"before": a, "after": b, "diff": d}
        if d > res["worst"]:
            res["worst"], res["key"] = d, key
    if res["missing"]:
        res["worst"], res["key"] = math.inf, "missing:" + res["missing"][0]
    return res


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(x) for x in r] for r in rows[1:] if r]


def family_of(column):
    """The quantity a CSV column is a component of (--families): a particle's x, y, z -> the
    position, vx, vy, vz -> v, lx.. -> l, sxx, sxy.. -> s; a history's momentum_x.. -> momentum,
    a probe's far_sxx, far_sxy.. -> far_s and far_ux.. -> far_u; a crack tip's KI_J, KII_J ->
    K_J and G_vcct, GII_vcct -> G_vcct; opening_n, opening_t -> opening_."""
    if column in ("x", "y", "z"):
        return "position"
    m = re.fullmatch(r"(v|l|X0_?)[xyz]", column)
    if m:
        return m.group(1)
    if re.fullmatch(r"momentum_[xyz]", column):
        return "momentum"
    column = re.sub(r"(?<=s)[xyz][xyz]$|(?<=u)[xyz]$|(?<=opening_)[nt]$", "", column)
    return re.sub(r"(?<=_)([KG])I+(?=_|$)", r"\1", column)


def compare_table(fa, fb, key, families=False):
    """Per-column normalised max difference of two CSV tables, rows matched by column key; with
    families, each column is measured against the largest value of its quantity's components
    (family_of) instead of its own."""
    try:
        (ha, ra), (hb, rb) = read_csv(fa), read_csv(fb)
    except (OSError, ValueError, IndexError) as e:
        return {"error": str(e), "worst": math.inf, "column": "unreadable"}
    ia = {(r[ha.index(key)] if key in ha else n): r for n, r in enumerate(ra)}
    ib = {(r[hb.index(key)] if key in hb else n): r for n, r in enumerate(rb)}
    res = {"rows": [len(ra), len(rb)], "worst": 0.0, "column": "", "columns": {},
           "missing_columns": [c for c in ha if c not in hb],
           "added_columns": [c for c in hb if c not in ha],
           "missing_rows": len(set(ia) - set(ib)), "added_rows": len(set(ib) - set(ia))}
    common = [k for k in ia if k in ib]
    own = {}
    for c in ha:
        if c not in hb or c == key:
            continue
        ca, cb = ha.index(c), hb.index(c)
        vals = [abs(r[ca]) for r in ra] + [abs(r[cb]) for r in rb]
        own[c] = max([v for v in vals if math.isfinite(v)], default=0.0)
    family_scale = {}
    for c, v in own.items():
        family_scale[family_of(c)] = max(family_scale.get(family_of(c), 0.0), v)
    for c in own:
        ca, cb = ha.index(c), hb.index(c)
        scale = family_scale[family_of(c)] if families else own[c]
        worst, at, absd = 0.0, None, 0.0
        for k in common:
            a, b = ia[k][ca], ib[k][cb]
            d = diff(a, b, scale)
            if d > worst:
                worst, at, absd = d, k, abs(a - b)
        res["columns"][c] = {"diff": worst, "abs": absd, "scale": scale, "at": at}
        if worst > res["worst"]:
            res["worst"], res["column"] = worst, c
    if res["missing_columns"] or res["missing_rows"] or res["added_rows"]:
        res["worst"] = math.inf
        res["column"] = ("missing column " + res["missing_columns"][0] if res["missing_columns"]
                         else f"rows {len(ra)} vs {len(rb)}")
    return res


def finite(node):
    """JSON-safe copy: inf and nan become strings."""
    if isinstance(node, dict):
        return {k: finite(v) for k, v in node.items()}
    if isinstance(node, list):
        return [finite(v) for v in node]
    return str(node) if isinstance(node, float) and not math.isfinite(node) else node


def fmt(d, what):
    return f"{d:.2e} ({what})" if what else f"{d:.2e}"


def main():
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", required=True)
    ap.add_argument("--after", required=True)
    ap.add_argument("--scenes", default=os.path.join(repo, "options"))
    ap.add_argument("--work", default="/tmp/gimp-compare")
    ap.add_argument("--max-steps", type=int, default=300)
    ap.add_argument("--only", nargs="+", metavar="NAME")
    ap.add_argument("--tol", type=float, default=1e-12)
    ap.add_argument("--families", action="store_true",
                    help="measure each CSV column against its quantity's largest component "
                    "(family_of): a momentum or a shear stress that is zero to round-off then "
                    "reads as round-off, not O(1)")
    args = ap.parse_args()
    scenes_dir, work = os.path.abspath(args.scenes), os.path.abspath(args.work)
    bins = {"before": os.path.abspath(args.before), "after": os.path.abspath(args.after)}
    names = ([n[:-5] if n.endswith(".opts") else n for n in args.only] if args.only else
             sorted(f[:-5] for f in os.listdir(scenes_dir) if f.endswith(".opts")))
    results, ok_all = [], True
    print(f"{'scene':22} {'runs':10} {'steps':>5} {'t_bef':>6} {'t_aft':>6}  "
          f"{'summary':34} {'particles':22} {'history':28} verdict", flush=True)
    for name in names:
        opts = os.path.join(scenes_dir, name + ".opts")
        own = scene_steps(opts, scenes_dir)
        steps = args.max_steps if own is None else min(args.max_steps, own)
        r = {"scene": name, "steps": steps, "runs": {}}
        for w in bins:
            r["runs"][w] = run(bins[w], opts, os.path.join(work, w, name), steps, scenes_dir)
        rb, ra = r["runs"]["before"], r["runs"]["after"]
        runs_ok = rb["rc"] == ra["rc"]
        r["run_status"] = "ok" if rb["rc"] == ra["rc"] == 0 else f"rc {rb['rc']}/{ra['rc']}"
        for w in (w for w in bins if r["runs"][w]["rc"]):
            print(f"  {name} {w}: exit {r['runs'][w]['rc']}: {r['runs'][w]['stderr']}")
        files = lambda f: [os.path.join(work, w, name, f) for w in bins]
        r["summary"] = compare_summary(*files("summary.json"))
        r["particles"] = compare_table(*files("particles.csv"), "id", args.families)
        r["history"] = compare_table(*files("history.csv"), "step", args.families)
        worst = max(r["summary"]["worst"], r["particles"]["worst"], r["history"]["worst"])
        refused = rb["rc"] == ra["rc"] != 0 and not any(
            os.path.exists(f) for f in files("summary.json") + files("history.csv"))
        if refused:
            worst = 0.0 if rb["stderr"] == ra["stderr"] else math.inf
        r["pass"] = runs_ok and worst <= args.tol
        ok_all &= r["pass"]
        print(f"{name:22} {r['run_status']:10} {steps:5d} {rb['seconds']:6.1f} "
              f"{ra['seconds']:6.1f}  "
              f"{fmt(r['summary']['worst'], r['summary']['key']):34} "
              f"{fmt(r['particles']['worst'], r['particles']['column']):22} "
              f"{fmt(r['history']['worst'], r['history']['column']):28} "
              f"{'PASS' if r['pass'] else 'FAIL'}", flush=True)
        added = r["summary"].get("added", []) + [f"{t}.csv:{c}" for t in ("particles", "history")
                                                  for c in r[t].get("added_columns", [])]
        if added:
            print(f"  {name}: added in after (not a failure): {', '.join(added)}")
        results.append(r)
    os.makedirs(work, exist_ok=True)
    with open(os.path.join(work, "compare.json"), "w") as f:
        json.dump(finite({"before": bins["before"], "after": bins["after"], "tol": args.tol,
                   "max_steps": args.max_steps, "pass": ok_all, "scenes": results}), f, indent=1)
    print(f"{'PASS' if ok_all else 'FAIL'}: {sum(r['pass'] for r in results)}/{len(results)} "
          f"scenes within {args.tol:g}; details in {os.path.join(work, 'compare.json')}")
    return 0 if ok_all else 1


if __name__ == "__main__":
    sys.exit(main())
