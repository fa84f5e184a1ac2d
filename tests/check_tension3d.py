"""Particle domain tracking on the 3D uniaxial tension block (options/tension3d.opts, the 2D
scene of check_tension.py as a solid): with strain-based sizes the particles separate (near 25 %
strain, as in 2D), and so they do with the stretches of F (near 45 %); with tracked corners,
CPDI and CPDI2 domains they never separate, corners reaching 50 % strain. Under the held load,
damped to rest, every particle of the middle 60 % of the bar carries the applied load as a
true stress: with corners (a dead load) the force over its column's current cross-section
(measured within 2.6 %, the cross-section taken from the particles' corner boxes), with CPDI
(a traction on the current faces) the traction itself (measured within 0.12 %)."""
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
SCENE = "options/tension3d.opts"
runs = {}
for mode in ("strain", "stretch", "corners", "cpdi", "cpdi2"):
    # A separated end flies out of the grid, which stops the run (exit 3): what it wrote up to
    # then is what this check reads.
    out = os.path.join(args.work, mode)
    proc = gimptest.run(args, SCENE, ["-gimp_tracking", mode], outdir=out, expect_ok=False)
    if proc.returncode not in (0, 3):
        raise SystemExit("gimp failed (exit %d): %s" % (proc.returncode, proc.stderr))
    s = gimptest.summary(out)
    runs[mode] = dict(s["measures"], status=s["status"])
for mode, lo, hi in (("strain", 0.15, 0.35), ("stretch", 0.3, 0.6)):
    m = runs[mode]
    c.check("%s separates" % mode,
            m["separation_strain"] is not None and lo < m["separation_strain"] < hi,
            "separation at engineering strain %s (max strain %.3f)" %
            (m["separation_strain"], m["max_strain"]))
for mode, reach in (("corners", 0.5), ("cpdi", 0.4), ("cpdi2", 0.4)):
    m = runs[mode]
    c.check("%s holds" % mode, m["separation_strain"] is None and m["max_strain"] >= reach and
            m["status"] == "completed",
            "no separation up to %.3f strain (largest gap %.2e particle sizes; needs %.2f)" %
            (m["max_strain"], m["max_separation"], reach))

P, A0 = 55e9, 1e-10  # the traction and the initial face: a dead load of P A0


def middle_columns(d):
    """The columns of particles (one x each) in the middle 60 % of the bar."""
    cols = gimptest.columns_by_x(d)
    x0, x1 = d["x"][cols[0][0]], d["x"][cols[-1][-1]]
    return [col for col in cols
            if 0.2 <= (sum(d["x"][i] for i in col) / len(col) - x0) / (x1 - x0) <= 0.8]


def extent(d, col, axis):
    return (max(d[axis][i] + d["l" + axis][i] for i in col) -
            min(d[axis][i] - d["l" + axis][i] for i in col))


for mode, tol in (("corners", 0.03), ("cpdi", 0.005)):
    dump = os.path.join(args.work, "rest_%s.csv" % mode)
    gimptest.run(args, SCENE, ["-gimp_tracking", mode, "-gimp_damping", "2e8", "-ts_max_steps",
                               "2500", "-gimp_particle_dump", dump],
                 outdir=os.path.join(args.work, "rest_" + mode))
    d = gimptest.read_csv(dump)
    worst, n = 0.0, 0
    cols = middle_columns(d)
    for col in cols:
        expected = P * A0 / (extent(d, col, "y") * extent(d, col, "z")) if mode == "corners" else P
        for i in col:
            e = d["sxx"][i] / expected - 1
            n += 1
            worst = e if abs(e) > abs(worst) else worst
    c.check("%s: true stress at every particle of the middle" % mode,
            n >= 100 and abs(worst) < tol,
            "%d particles in %d columns, worst sxx / expected - 1 = %+.2f %% (tol %.1f %%)" %
            (n, len(cols), 100 * worst, 100 * tol))
c.done()
