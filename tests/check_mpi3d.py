"""np = 2 equals np = 1 in 3D, with migration (options/migrate3d.opts): a block on two levels
thrown along x across the rank boundary and stretched by a sine velocity profile, 300 steps.

Runs: one rank; two ranks as PETSc splits the level-0 DMDA (along x here, so about half of the
particles migrate); two ranks split along z (-da_processors_z 2). Checked (measured in
brackets): every column of the final particle dump (sorted by id) against one rank's, relative
to the column's largest magnitude, below 1e-10 [8.7e-14]: the sums over particles on the nodes
run in another order, nothing else differs; the history's energies likewise [1.2e-13]; particles
migrated in the x-split run [260 of 544] (the block must cross the boundary for the test to mean
anything).

The 2-rank run also writes field frames every 100 steps: fields.h5 holds /particles/step_* with
x (N, 3) and stress (N, 9) and /grid/step_*/level_k with velocity (P, N, M, 3) and mass (P, N, M)
of the level's nodes, and every dataset that particles.xmf and grid.xmf (ParaView's XDMF, XYZ
geometry and 3DCoRectMesh topology) name exists in fields.h5 with the shape they give."""
import os
import re
import gimptest

args = gimptest.parse_args()
RUNS = (("1 rank", 1, []), ("2 ranks", 2, []),
        ("2 ranks along z", 2, ["-da_processors_x", "1", "-da_processors_y", "1",
                                "-da_processors_z", "2"]))
c = gimptest.Checks()
ref = None
for name, ranks, extra in RUNS:
    tag = name.replace(" ", "_")
    dump = os.path.join(args.work, "migrate3d_%s.csv" % tag)
    frames = ["-gimp_output_interval", "100"] if ranks == 2 and not extra else []
    out = gimptest.run(args, "options/migrate3d.opts",
                       extra + frames + ["-gimp_particle_dump", dump], ranks=ranks,
                       outdir=os.path.join(args.work, "migrate3d_" + tag))
    d, h, s = gimptest.read_csv(dump), gimptest.history(out), gimptest.summary(out)
    if ref is None:
        ref = (d, h)
        continue
    worst, col = 0.0, ""
    for k in ref[0]:
        scale = max(abs(v) for v in ref[0][k]) or 1.0
        e = max(abs(a - b) for a, b in zip(ref[0][k], d[k])) / scale
        if e >= worst:
            worst, col = e, k
    c.check(name + " particles", len(d["id"]) == len(ref[0]["id"]) and worst <= 1e-10,
            "%d particles; largest difference %.1e of the column's scale (%s; tol 1e-10)" %
            (len(d["id"]), worst, col))
    eh = max(abs(a - b) / max(abs(a), 1e-300) for k in ("kinetic", "strain")
             for a, b in zip(ref[1][k], h[k]))
    c.check(name + " energies", eh <= 1e-10, "largest relative difference %.1e" % eh)
    if not extra:
        m = s["measures"]["particles_migrated"]
        c.check(name + " migration", m > 0, "%d particles migrated" % m)
        fields_out = out
import h5py  # noqa: E402 (Debian's python3-h5py; tools/setup.sh installs it)

with h5py.File(os.path.join(fields_out, "fields.h5"), "r") as f:
    groups = sorted(f["particles"])
    want = ["step_%08d" % i for i in (0, 100, 200, 300)]
    c.check("hdf5 frames", groups == want, "groups %s" % groups)
    g = f["particles/step_00000300"]
    c.check("hdf5 particles", g["x"].shape == (544, 3) and g["stress"].shape == (544, 9),
            "x %s, stress %s" % (g["x"].shape, g["stress"].shape))
    lv = f["grid/step_00000300/level_1"]
    c.check("hdf5 grid", lv["velocity"].shape[3:] == (3,) and
            lv["mass"].shape == lv["velocity"].shape[:3],
            "level 1: velocity %s, mass %s" % (lv["velocity"].shape, lv["mass"].shape))
    bad, refs = [], 0
    for xmf in ("particles.xmf", "grid.xmf"):
        text = open(os.path.join(fields_out, xmf)).read()
        for dims, ref in re.findall(r'Dimensions="([0-9 ]+)"[^>]*Format="HDF">fields\.h5:([^<]+)<',
                                    text):
            refs += 1
            if ref not in f or f[ref].shape != tuple(int(d) for d in dims.split()):
                bad.append(ref)
    c.check("xdmf references", refs > 0 and not bad, "%d references, bad: %s" % (refs, bad[:3]))
c.done()
