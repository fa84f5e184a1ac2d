#!/usr/bin/python3
"""Tracking mode: speed against error -- the table of docs/performance.md, section "Tracking mode:
speed against error", that decides the default of -gimp_tracking.

Usage: /usr/bin/python3 runs/study_tracking.py --gimp build/gimp --root . --work WORK
           [--modes none,stretch,corners,cpdi,cpdi2] [--dims 2,3]
           [--cases bend4,bend8,tension,plate] [--write-docs]

For each dimension and each mode it runs four cases (into WORK/<case>_<dim>d_<mode>*; a case
whose WORK/<case>_<dim>d_<mode>_result.json is there already is not run again) and records an
error and a time:

  bend4, bend8  options/tracking_bend.opts (2D) / tracking_bend3d.opts (3D): a neo-Hookean
                cantilever, L/H = 10, P L^2/EI = 4, damped to rest, with 4 (h = 0.0125 m) and 8
                (h = 0.00625 m) cells through the depth; the 3D one is one particle layer
                wide, the grid nodes its weights reach held in z (the same plane strain).
                Error: the tip's displacement against the elastica's (tests/elastica.py),
                |(u, v) - (u, v)_ref| / |(u, v)_ref| at the centre of the end section
                (elastica.centre_line, from particle dumps).
  tension       options/tension.opts / tension3d.opts, the silicon bar pulled past 50 %
                engineering strain (the dynamic run, 1250 steps): separation of former
                neighbours (summary.json separation_strain) is a failure. Then the bar under the
                held load damped to rest (-gimp_damping 2e8, 2500 steps, about 37 % strain):
                error = the largest |sxx / s_exact - 1| over every particle of the middle 60 %
                of the bar, s_exact the true stress the load gives there: for the dead load
                (none, stretch, corners) the force over the column's current
                cross-section, measured from the particles' centres (span x n / (n - 1) along
                y, and z, n particles across), so it does not depend on the domains the mode
                tracks; with cpdi and cpdi2 the traction acts on the current faces, a true
                stress, so s_exact = p.
  plate         options/tracking_plate2d.opts / tracking_plate3d.opts: a strip with a hole,
                d/W = 0.2, 0.5 mm thick, h = 0.5 mm, damped to rest. Error: |kt / kt_ref - 1|,
                kt the hole measure's fitted edge value (summary.json) and kt_ref the
                finite-width gross-section value (2 + (1 - d/W)^3) / (1 - d/W) = 3.14, the
                formula of tests/check_plate.py.

Time: summary.json cpu_seconds of the run that gives the error (the run to rest; for tension the
rest run, 2500 steps for every mode), one rank. CPU time, not wall time: the machine is shared,
and the wall time is kept beside it in result.json. particle_steps_per_second is kept too.

The aggregate per mode and dimension is the cost of accuracy, G = geometric mean over the four
cases of (error x seconds): lower is better, and the ratio of two modes' G is the factor of
error x time between them, each case weighted alike whatever its scale. A mode that fails a case
(separates, or a run that stops) has no G: it is not eligible as a default. Prints the markdown
tables; with --write-docs it replaces the text between the markers in docs/performance.md.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import elastica  # noqa: E402
import gimptest  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--gimp", required=True)
ap.add_argument("--root", required=True)
ap.add_argument("--work", required=True)
ap.add_argument("--modes", default="none,stretch,corners,cpdi,cpdi2")
ap.add_argument("--dims", default="2,3")
ap.add_argument("--cases", default="bend4,bend8,tension,plate")
ap.add_argument("--write-docs", action="store_true")
a = ap.parse_args()
a.gimp, a.root, a.work = (os.path.abspath(p) for p in (a.gimp, a.root, a.work))
os.makedirs(a.work, exist_ok=True)
MODES = a.modes.split(",")
DIMS = [int(d) for d in a.dims.split(",")]
CASES = a.cases.split(",")
BEGIN = "<!-- study_tracking: table -->"
END = "<!-- /study_tracking: table -->"
Q_BEND = 4.0
L_BEND = 0.5
KT_REF = (2 + (1 - 0.2) ** 3) / (1 - 0.2)
P_TENSION, H0_TENSION = 55e9, 10e-6


def gimp(opts, outdir, extra):
    """Run gimp; return (exit code, stderr, summary or None)."""
    cmd = [a.gimp, "-options_file", os.path.join(a.root, "options", opts),
           "-gimp_output_dir", outdir] + extra
    t0 = time.time()
    p = subprocess.run(cmd, cwd=a.work, capture_output=True, text=True)
    wall = time.time() - t0
    summ = None
    if os.path.exists(os.path.join(outdir, "summary.json")):
        summ = gimptest.summary(outdir)
        summ["wall_outside"] = wall
    return p.returncode, p.stderr, summ


def timing(summ):
    return {"seconds": summ["cpu_seconds"], "wall": summ["wall_seconds"],
            "psps": summ.get("particle_steps_per_second"), "steps": summ["steps"],
            "particles": summ["particles"], "status": summ["status"]}


def bend(dim, mode, cells, base):
    h = 0.05 / cells
    if dim == 2:
        opts, extra = "tracking_bend.opts", ["-gimp_h", repr(h)]
    else:  # one particle layer (h/2) wide at every h, z rollers on the planes z = 0 and h
        opts = "tracking_bend3d.opts"
        extra = ["-gimp_h", repr(h), "-gimp_domain", "-0.025,-0.45,%r,0.55,0.1,%r" % (-h, 2 * h),
                 "-gimp_body0_box", "0,-0.025,0,0.5,0.025,%r" % (h / 2), "-gimp_bc2_z", repr(h)]
    extra += ["-gimp_tracking", mode]
    d0, d1 = base + "_initial.csv", base + "_final.csv"
    rc, err, _ = gimp(opts, base + "_initial", extra + ["-ts_max_steps", "0",
                                                        "-gimp_particle_dump", d0])
    if rc != 0:
        return {"fail": "setup: exit %d: %s" % (rc, err.strip()[-200:])}
    rc, err, summ = gimp(opts, base, extra + ["-gimp_particle_dump", d1])
    if rc != 0 or summ is None or summ["status"] != "at_rest":
        return {"fail": "exit %d, %s" % (rc, summ and summ["status"])}
    s, x, y, _ = elastica.centre_line(elastica.read_dump(d0), elastica.read_dump(d1), 0.0)
    _, ur, vr = elastica.Elastica(Q_BEND, length=L_BEND).at(s[-1])
    u, v = x[-1] - s[-1], y[-1]
    r = timing(summ)
    r.update(error=math.hypot(u - ur, v - vr) / math.hypot(ur, vr), du=u / ur - 1, dv=v / vr - 1)
    return r


def span(d, col, axis):
    """A column's current extent along axis from its particles' centres: n particles across,
    (max - min) n / (n - 1)."""
    vals = sorted(d[axis][i] for i in col)
    n = len({round(v * 1e9) for v in (d[axis + "0"][i] for i in col)})
    return (vals[-1] - vals[0]) * n / (n - 1)


def tension(dim, mode, base):
    opts = "tension.opts" if dim == 2 else "tension3d.opts"
    rc, err, summ = gimp(opts, base + "_pull", ["-gimp_tracking", mode])
    if rc not in (0, 3) or summ is None:
        return {"fail": "pull: exit %d: %s" % (rc, err.strip()[-200:])}
    m = summ["measures"]
    pull = {"separation": m["separation_strain"], "max_strain": m["max_strain"]}
    d0, d1 = base + "_initial.csv", base + "_rest.csv"
    rc, err, _ = gimp(opts, base + "_initial", ["-gimp_tracking", mode, "-ts_max_steps", "0",
                                                "-gimp_particle_dump", d0])
    rc, err, summ = gimp(opts, base + "_rest", ["-gimp_tracking", mode, "-gimp_damping", "2e8",
                                                "-ts_max_steps", "2500",
                                                "-gimp_particle_dump", d1])
    sep = None
    if m["separation_strain"] is not None:
        sep = "separates at %.0f %% strain" % (100 * m["separation_strain"])
    if rc != 0 or summ is None:
        why = err.strip().splitlines()[-1] if err.strip() else ""
        return dict(pull, fail=(sep + "; " if sep else "") + "the run to rest stops (exit %d)"
                    % rc, why=why)
    r = timing(summ)
    r.update(pull)
    if sep:
        r["fail"] = sep
    init, d = gimptest.read_csv(d0), gimptest.read_csv(d1)
    order = sorted(range(len(init["id"])), key=lambda i: init["id"][i])
    ids = sorted(range(len(d["id"])), key=lambda i: d["id"][i])
    for axis in ("x", "y", "z")[:dim]:  # initial positions beside the final ones, by id
        d[axis + "0"] = [0.0] * len(ids)
        for i, j in zip(ids, order):
            d[axis + "0"][i] = init[axis][j]
    cols = {}
    for i, x0 in enumerate(d["x0"]):
        cols.setdefault(round(x0 * 1e9), []).append(i)
    keys = sorted(cols)
    worst, n = 0.0, 0
    for k in keys[round(0.2 * (len(keys) - 1)):round(0.8 * (len(keys) - 1)) + 1]:
        col = cols[k]
        if mode in ("cpdi", "cpdi2"):
            exact = P_TENSION
        else:
            area = span(d, col, "y") * (span(d, col, "z") if dim == 3 else 1.0)
            exact = P_TENSION * H0_TENSION ** (dim - 1) / area
        for i in col:
            e = d["sxx"][i] / exact - 1
            n += 1
            worst = e if abs(e) > abs(worst) else worst
    r.update(error=abs(worst), signed=worst, counted=n, strain_rest=summ["measures"]["max_strain"])
    return r


def plate(dim, mode, base):
    rc, err, summ = gimp("tracking_plate%dd.opts" % dim, base, ["-gimp_tracking", mode])
    if rc != 0 or summ is None or summ["status"] != "at_rest":
        return {"fail": "exit %d, %s" % (rc, summ and summ["status"])}
    r = timing(summ)
    kt = summ["measures"]["kt"]
    r.update(error=abs(kt / KT_REF - 1), kt=kt)
    return r


def result(case, dim, mode):
    base = os.path.join(a.work, "%s_%dd_%s" % (case, dim, mode))
    path = base + "_result.json"
    if os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    print("running %s %dD %s" % (case, dim, mode), file=sys.stderr, flush=True)
    if case.startswith("bend"):
        r = bend(dim, mode, int(case[4:]), base)
    elif case == "tension":
        r = tension(dim, mode, base)
    else:
        r = plate(dim, mode, base)
    with open(path, "w") as f:
        json.dump(r, f, indent=1)
    return r


res = {(c, d, m): result(c, d, m) for d in DIMS for c in CASES for m in MODES}
LABEL = {"bend4": "bending, 4 cells through H", "bend8": "bending, 8 cells through H",
         "tension": "tension past 50 %", "plate": "plate with a hole"}


def cell(r):
    if "error" not in r:
        return "**fails** (%s) | -" % r.get("fail")
    e = "%.2f %%" % (100 * r["error"])
    if "fail" in r:
        e = "**fails** (%s; %s)" % (r["fail"], e)
    return "%s | %.1f" % (e, r["seconds"])


out = ["| case | dim | " + " | ".join("`%s` error | s" % m for m in MODES) + " |",
       "| --- | --- | " + " | ".join("--- | ---" for _ in MODES) + " |"]
for d in DIMS:
    for c in CASES:
        out.append("| %s | %dD | %s |" % (LABEL[c], d, " | ".join(cell(res[(c, d, m)])
                                                                  for m in MODES)))
out += ["", "| dim | " + " | ".join("`%s`" % m for m in MODES) + " |",
        "| --- | " + " | ".join("---" for _ in MODES) + " |"]


def gmean(vals):
    return math.exp(sum(math.log(v) for v in vals) / len(vals))


def aggregate(d, cases, label):
    """A row of G over the given cases per mode (None for a mode that fails one), and the best."""
    g = {}
    for m in MODES:
        rs = [res[(c, d, m)] for c in cases]
        if not any("fail" in r or "error" not in r for r in rs):
            g[m] = gmean([max(r["error"], 1e-6) * r["seconds"] for r in rs])
    top = min(g, key=g.get) if g else None
    row = ["fails" if m not in g else "%.3g (x %.2f)%s" % (
        g[m], g[m] / g[top], " **best**" if m == top else "") for m in MODES]
    out.append("| %dD: %s | %s |" % (d, label, " | ".join(row)))
    return top, g


best, G = {}, {}
for d in DIMS:
    best[d], G[d] = aggregate(d, CASES, "G [s], x the best")
for d in DIMS:
    row = []
    for m in MODES:
        rs = [res[(c, d, m)] for c in CASES]
        row.append("%.2f %% / %.2f s" % (100 * gmean([max(r["error"], 1e-6) for r in rs]),
                                         gmean([r["seconds"] for r in rs]))
                   if all("error" in r for r in rs) else "-")
    out.append("| %dD: geometric mean of the errors / of the seconds | %s |" %
               (d, " | ".join(row)))
if "tension" in CASES and len(CASES) > 1:
    for d in DIMS:
        aggregate(d, [c for c in CASES if c != "tension"], "G without tension (bending, plate)")
detail = ["", "| case | dim | mode | error | du tip | dv tip | kt | sxx error (signed) | "
          "pull: max strain, separation | s (CPU) | s (wall) | steps | particles | "
          "particle-steps/s |", "| --- " * 14 + "|"]
for d in DIMS:
    for c in CASES:
        for m in MODES:
            r = res[(c, d, m)]
            if "seconds" not in r:
                detail.append("| %s | %dD | `%s` | %s |" % (c, d, m, r.get("fail")) + " |" * 10)
                continue
            pull = "-"
            if "max_strain" in r:
                pull = "%.1f %%, %s" % (100 * r["max_strain"], "none" if r["separation"] is None
                                        else "at %.1f %%" % (100 * r["separation"]))
            detail.append("| %s | %dD | `%s` | %.2f %% | %s | %s | %s | %s | %s | %.2f | %.2f | "
                          "%d | %d | %s |" % (
                              c, d, m, 100 * r["error"],
                              "%+.2f %%" % (100 * r["du"]) if "du" in r else "-",
                              "%+.2f %%" % (100 * r["dv"]) if "dv" in r else "-",
                              "%.4f" % r["kt"] if "kt" in r else "-",
                              "%+.2f %%" % (100 * r["signed"]) if "signed" in r else "-", pull,
                              r["seconds"], r["wall"], r["steps"], r["particles"],
                              "%.3g" % r["psps"] if r.get("psps") else "-"))
text = "\n".join(out + detail)
print(text)
for d in DIMS:
    if best[d]:
        others = sorted((G[d][m] / G[d][best[d]], m) for m in G[d] if m != best[d])
        print("best %dD: %s; next %s" % (d, best[d], ", ".join("%s x %.2f" % (m, f)
                                                             for f, m in others)))
if a.write_docs:
    path = os.path.join(a.root, "docs", "performance.md")
    with open(path) as f:
        doc = f.read()
    i, j = doc.index(BEGIN) + len(BEGIN), doc.index(END)
    with open(path, "w") as f:
        f.write(doc[:i] + "\n" + text + "\n" + doc[j:])
