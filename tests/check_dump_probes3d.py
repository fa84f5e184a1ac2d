"""The particle dump and the probes in 3D (-gimp_particle_dump, -gimp_probeK_*; docs/output.md,
"3D runs" and "Probes").

Scene: the 3D block on two levels thrown across the rank boundary and stretched
(options/migrate3d.opts, 300 steps: every stress component non-zero), with four probes: inside
the block on level 1 (inner) and on level 0 (coarse), and two points outside it whose nearest
particles are the block's corners (outside, far); on 1 and 2 ranks. And the 3D bar
(options/bar3d.opts, particles at exact binary positions) with a probe at a cell centre, where 8
particles tie (ties: the smallest id), on 1 and 2 ranks, the second time at the level-0 cell on
the rank boundary (x = 13 m, 4 of the 8 particles on each rank).
Dump (checked on every run): the header id,x,y,z,vx,vy,vz,sxx,syy,szz,syz,sxz,sxy,V,lx,ly,lz;
ids strictly increasing, one row per particle (summary.json's count); each row equal, bit for
bit, to its particle in the last frame of fields.h5 (matched by position: x, v, the stress
components from the row-major 3 x 3 tensor, V, l); at step 0 V = 8 lx ly lz; on 2 ranks the
same ids and values within 1e-10 of each group's largest value [2.7e-14].
Probes: summary.json probes with id, x0 (3), u (3), stress (6); history.csv columns NAME_ux,
_uy, _uz, _sxx, _syy, _szz, _syz, _sxz, _sxy after strain_x (the separation measure), in
declaration order; the id is the particle nearest the point at the start (from the step-0 dump; ties the smallest id) and x0
its initial position (to the 13 digits printed); u = the dump's x - x0 and stress = the dump's
row of that id, and the history's last row = summary.json's (to the 13 digits printed); on 2
ranks the same ids and x0, u and stress within 1e-10 [2.5e-14], with the "far" probe's particle
moved across the rank boundary.
"""
import os

import h5py
import numpy as np

import compare3d
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
BLOCK, BAR = "options/migrate3d.opts", "options/bar3d.opts"
PROBES = (("inner", (0.33, 0.27, 0.31)), ("coarse", (0.24, 0.33, 0.26)),
          ("outside", (0.0, 0.0, 0.0)), ("far", (1.1, 0.5, 0.5)))
STRESS = ("sxx", "syy", "szz", "syz", "sxz", "sxy")
TENSOR = {"sxx": (0, 0), "syy": (1, 1), "szz": (2, 2), "syz": (1, 2), "sxz": (0, 2), "sxy": (0, 1)}


def probe_options(probes):
    o = ["-gimp_probes", str(len(probes))]
    for k, (name, x) in enumerate(probes):
        o += ["-gimp_probe%d_name" % k, name, "-gimp_probe%d_x" % k, ",".join(map(repr, x))]
    return o


def rel(a, b, scale):
    return abs(a - b) / (scale or 1.0)


def check_dump(tag, out, dump, step0=False):
    header, d = compare3d.read_dump(dump)
    s = gimptest.summary(out)
    ids = d["id"]
    c.check(tag + ": dump header", header == compare3d.HEADER, header)
    c.check(tag + ": dump rows sorted by id", len(ids) == s["particles"] and
            all(a < b for a, b in zip(ids, ids[1:])),
            "%d rows (summary: %d particles), ids %d .. %d strictly increasing: %s" % (
                len(ids), s["particles"], ids[0], ids[-1],
                all(a < b for a, b in zip(ids, ids[1:]))))
    if step0:
        worst = max(rel(V, 8 * lx * ly * lz, V) for V, lx, ly, lz in
                    zip(d["V"], d["lx"], d["ly"], d["lz"]))
        c.check(tag + ": V = 8 lx ly lz at step 0", worst < 1e-15, "largest |V - 8 lx ly lz| / V "
                "= %.1e" % worst)
        return d
    with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
        g = f["particles"][sorted(f["particles"].keys())[-1]]
        x, v, st, V, l = (np.array(g[k]) for k in ("x", "v", "stress", "V", "l"))
    at = {tuple(p): k for k, p in enumerate(x)}
    bad = 0
    for i in range(len(ids)):
        k = at.get((d["x"][i], d["y"][i], d["z"][i]))
        same = k is not None and all(
            d[col][i] == val for col, val in (
                [(("vx", "vy", "vz")[a], v[k][a]) for a in range(3)] +
                [(col, st[k][3 * TENSOR[col][0] + TENSOR[col][1]]) for col in STRESS] +
                [(col, st[k][3 * TENSOR[col][1] + TENSOR[col][0]]) for col in STRESS] +
                [("V", V[k])] + [(("lx", "ly", "lz")[a], l[k][a]) for a in range(3)]))
        bad += not same
    c.check(tag + ": dump = last frame of fields.h5", bad == 0 and len(at) == len(ids),
            "%d of %d rows differ from their particle (x, v, stress, V, l; matched by position)" %
            (bad, len(ids)))
    return d


def nearest(d0, point):
    """(id, initial position, margin to the next-nearest distance^2) of the particle nearest
    point in the step-0 dump d0, the smallest id among equals."""
    best = sorted((sum((d0[a][i] - point[j]) ** 2 for j, a in enumerate("xyz")), d0["id"][i], i)
                  for i in range(len(d0["id"])))
    d2, pid, i = best[0]
    ties = [b for b in best if b[0] == d2]
    nxt = next((b[0] for b in best if b[0] > d2), float("inf"))
    return pid, (d0["x"][i], d0["y"][i], d0["z"][i]), len(ties), nxt - d2


def check_probes(tag, out, dump_rows, d0, probes):
    s = gimptest.summary(out)
    h = gimptest.history(out)
    cols = list(h.keys())
    want = [p + q for p, _ in probes for q in ("_ux", "_uy", "_uz") + tuple(
        "_" + x for x in STRESS)]
    at = cols.index("strain_x") + 1 if "strain_x" in cols else -1
    c.check(tag + ": history columns", at > 0 and cols[at:at + len(want)] == want,
            "after strain_x: %s ... (%d probe columns)" % (",".join(cols[at:at + 3]),
                                                             len(cols) - at))
    sp = s["probes"]
    shape_ok = list(sp.keys()) == [p for p, _ in probes] and all(
        sorted(sp[p].keys()) == ["id", "stress", "u", "x0"] and len(sp[p]["x0"]) == 3 and
        len(sp[p]["u"]) == 3 and len(sp[p]["stress"]) == 6 for p in sp)
    c.check(tag + ": summary probes", shape_ok, "; ".join(
        "%s: %s" % (p, ", ".join("%s %s" % (k, len(v) if isinstance(v, list) else v)
                                 for k, v in sorted(sp[p].items()))) for p in sp))
    if not shape_ok:
        return {}
    row = {pid: i for i, pid in enumerate(dump_rows["id"])}
    for name, point in probes:
        pid, x0, nties, margin = nearest(d0, point)
        q = sp[name]
        c.check("%s: probe %s follows the nearest particle" % (tag, name),
                q["id"] == pid and max(rel(a, b, 1.0) for a, b in zip(q["x0"], x0)) < 1e-12 and
                (nties > 1 or margin > 1e-12),
                "id %d at x0 %s, nearest to %s: id %d (%d at that distance%s)" % (
                    q["id"], q["x0"], point, pid, nties,
                    ", the next %.1e m^2 further" % margin if nties == 1 else ", the smallest id"))
        i = row.get(q["id"])
        if i is None:
            c.check("%s: probe %s in the dump" % (tag, name), False, "id %d not in the dump" %
                    q["id"])
            continue
        xs = [dump_rows[a][i] for a in "xyz"]
        st = [dump_rows[k][i] for k in STRESS]
        uscale = max(abs(v) for v in q["u"]) or 1.0
        sscale = max(abs(v) for v in st) or 1.0
        du = max(rel(q["u"][a], xs[a] - q["x0"][a], uscale) for a in range(3))
        ds = max(rel(q["stress"][k], st[k], sscale) for k in range(6))
        hu = max(rel(h[name + "_u" + a][-1], q["u"][j], uscale) for j, a in enumerate("xyz"))
        hs = max(rel(h[name + "_" + k][-1], q["stress"][j], sscale) for j, k in enumerate(STRESS))
        c.check("%s: probe %s = its dump row" % (tag, name),
                max(du, ds, hu, hs) < 1e-11 and h["step"][-1] == s["steps"],
                "|u| %.3e m, |stress| %.3e Pa; against the dump: u %.1e, stress %.1e; history's "
                "last row (step %d) against summary: u %.1e, stress %.1e (tol 1e-11)" % (
                    uscale, sscale, du, ds, h["step"][-1], hu, hs))
    return sp


# The block: step 0, then 300 steps on 1 and 2 ranks.
popts = probe_options(PROBES)
out0, dump0 = compare3d.dump_run(args, BLOCK, "block_step0", popts + ["-ts_max_steps", "0"])
d0 = check_dump("block step 0", out0, dump0, step0=True)
res = {}
for ranks in (1, 2):
    out, dump = compare3d.dump_run(args, BLOCK, "block_np%d" % ranks, popts, ranks=ranks)
    d = check_dump("block np%d" % ranks, out, dump)
    res[ranks] = (d, check_probes("block np%d" % ranks, out, d, d0, PROBES))
dd, group = compare3d.dump_diff(res[1][0], res[2][0])
c.check("block: dump on 2 ranks = 1 rank", dd < 1e-10,
        "%d particles, largest difference %.1e of its group's scale (%s); tol 1e-10" %
        (len(res[1][0]["id"]), dd, group))
p1, p2 = res[1][1], res[2][1]
if p1 and p2:
    worst = 0.0
    for name in p1:
        us = max(abs(v) for v in p1[name]["u"])
        ss = max(abs(v) for v in p1[name]["stress"])
        worst = max([worst] + [rel(a, b, us) for a, b in zip(p1[name]["u"], p2[name]["u"])] +
                    [rel(a, b, ss) for a, b in zip(p1[name]["stress"], p2[name]["stress"])])
    same = all(p1[n]["id"] == p2[n]["id"] and p1[n]["x0"] == p2[n]["x0"] for n in p1)
    far = p2["far"]
    crossed = far["x0"][0] < 0.6 and far["x0"][0] + far["u"][0] > 0.7
    c.check("block: probes on 2 ranks = 1 rank", same and worst < 1e-10 and crossed,
            "same ids and x0: %s; u, stress differ by %.1e (tol 1e-10); far's particle from x = "
            "%.4f to %.4f m (across the ranks' boundary, 0.6 or 0.7 m)" % (
                same, worst, far["x0"][0], far["x0"][0] + far["u"][0]))

# Ties on the bar: 8 particles around a cell centre, on 1 rank and across the rank boundary.
for tag, point, ranks in (("bar tie np1", (0.5, 0.5, 0.5), 1),
                          ("bar tie np2", (13.0, 0.5, 0.5), 2)):
    probes = (("tip", (24.75, 0.75, 0.75)), ("tie", point))
    o0, du0 = compare3d.dump_run(args, BAR, tag.replace(" ", "_") + "_0",
                                 probe_options(probes) + ["-ts_max_steps", "0"], ranks=ranks)
    b0 = compare3d.read_dump(du0)[1]
    o, du = compare3d.dump_run(args, BAR, tag.replace(" ", "_"),
                               probe_options(probes) + ["-ts_max_steps", "20"], ranks=ranks)
    b = check_dump(tag, o, du)
    sp = check_probes(tag, o, b, b0, probes)
    pid, _, nties, _ = nearest(b0, point)
    c.check(tag + ": an 8-way tie", nties == 8 and sp and sp["tie"]["id"] == pid,
            "%d particles at the smallest distance from %s; the probe took id %s, the smallest "
            "is %d" % (nties, point, sp["tie"]["id"] if sp else "?", pid))
c.done()
