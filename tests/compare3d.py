"""Helpers shared by the 3D capability checks (check_*3d.py): the 3D particle dump, and the
comparison of two runs' dumps and histories with each quantity measured against its siblings
(a near-zero component, v_y of an axial bar or a shear stress, against the largest component of
its group), as tests/check_regression.py measures a family."""
import csv
import os

import gimptest

HEADER = "id,x,y,z,vx,vy,vz,sxx,syy,szz,syz,sxz,sxy,V,lx,ly,lz"
GROUPS = {"position": ("x", "y", "z"), "velocity": ("vx", "vy", "vz"),
          "stress": ("sxx", "syy", "szz", "syz", "sxz", "sxy"), "volume": ("V",),
          "half-size": ("lx", "ly", "lz")}
# history.csv columns compared as one family: the energies (measured against the largest of them)
ENERGIES = ("kinetic", "strain", "external_work", "damping", "total")


def read_dump(path):
    """A 3D particle dump: (header line, {column: [floats]}); ids as ints."""
    with open(path) as f:
        header = f.readline().strip()
        f.seek(0)
        rows = list(csv.DictReader(f))
    d = {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}
    if "id" in d:
        d["id"] = [int(r["id"]) for r in rows]
    return header, d


def dump_diff(a, b):
    """Largest difference of two dumps (rows matched by position, which must hold the same ids)
    relative to the largest magnitude of the quantity's group in a: (worst, group); inf when the
    ids differ."""
    if a["id"] != b["id"]:
        return float("inf"), "ids"
    worst, where = 0.0, ""
    for g, cols in GROUPS.items():
        scale = max(abs(v) for k in cols for v in a[k]) or 1.0
        e = max(abs(x - y) for k in cols for x, y in zip(a[k], b[k])) / scale
        if e >= worst:
            worst, where = e, g
    return worst, where


def history_diff(a, b):
    """Largest difference of two histories (rows by position, the same steps) over the energies
    (against the largest energy) and every probe column (against the largest of its kind, u or
    stress, of that probe): (worst, column)."""
    if a["step"] != b["step"]:
        return float("inf"), "steps"
    worst, where = 0.0, ""
    escale = max(abs(v) for k in ENERGIES for v in a[k]) or 1.0
    for k in a:
        if k in ENERGIES:
            scale = escale
        elif k[-3:] in ("_ux", "_uy", "_uz"):
            scale = max(abs(v) for s in ("_ux", "_uy", "_uz") for v in a[k[:-3] + s]) or 1.0
        elif k[-4:] in ("_sxx", "_syy", "_szz", "_syz", "_sxz", "_sxy"):
            scale = max(abs(v) for s in ("_sxx", "_syy", "_szz", "_syz", "_sxz", "_sxy")
                        for v in a[k[:-4] + s]) or 1.0
        else:
            continue
        e = max(abs(x - y) for x, y in zip(a[k], b[k])) / scale
        if e >= worst:
            worst, where = e, k
    return worst, where


def dump_run(args, opts, name, extra=(), ranks=1, expect_ok=True):
    """Run opts with a particle dump into work/name; (output dir, dump path) or the completed
    process when expect_ok is False."""
    out = os.path.join(args.work, name)
    dump = os.path.join(out, "particles.csv")
    os.makedirs(out, exist_ok=True)
    r = gimptest.run(args, opts, list(extra) + ["-gimp_particle_dump", dump], ranks=ranks,
                     outdir=out, expect_ok=expect_ok)
    return (out, dump) if expect_ok else r


def error_lines(p):
    """The 'gimp: error' lines of a completed process (stderr and stdout)."""
    return [ln for ln in (p.stderr + p.stdout).splitlines() if ln.startswith("gimp: error")]


def petsc_trace(p):
    """Whether a completed process printed a PETSc error trace or a signal report."""
    text = p.stderr + p.stdout
    return "PETSC ERROR" in text or "Process received signal" in text
