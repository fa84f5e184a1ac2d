"""Particle domain tracking on the uniaxial tension block (paper section 4.1, options/tension.opts):
with strain-based sizes the particles separate (the paper: near 25 % strain); with corner
tracking they never separate up to 50 % strain. Under the held load (damped to rest) the stress
of every particle in the middle 60 % of the bar equals the applied traction as a true stress
of its column within 2 % (measured 1.62 %; the paper's difference to FE is 8 %), and the corner
size (10 %, 50 %, 80 %) changes the elongation by < 1 %."""
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
runs = {}
for mode in ("strain", "corners"):
    # With strain tracking the torn-off end flies out of the grid, which stops the run
    # (exit 3): what it wrote up to then is what this check reads.
    out = os.path.join(args.work, mode)
    proc = gimptest.run(args, "options/tension.opts", ["-gimp_tracking", mode], outdir=out,
                        expect_ok=False)
    if proc.returncode not in (0, 3):
        raise SystemExit("gimp failed (exit %d): %s" % (proc.returncode, proc.stderr))
    runs[mode] = gimptest.summary(out)["measures"]
    runs[mode]["status"] = gimptest.summary(out)["status"]
m = runs["strain"]
c.check("strain separates", m["separation_strain"] is not None and 0.15 < m["separation_strain"] < 0.35,
        "separation at engineering strain %s (max strain %.3f)" % (m["separation_strain"], m["max_strain"]))
m = runs["corners"]
c.check("corners hold", m["separation_strain"] is None and m["max_strain"] >= 0.5 and
        m["status"] == "completed",
        "no separation up to %.3f strain (largest gap %.2e particle sizes)" %
        (m["max_strain"], m["max_separation"]))


def stress_profile(d, force):
    """Every particle of every column in the middle 60 % of the bar (away from the held and the
    loaded end, Saint-Venant) carries sxx = the true stress force / H of its own column, H the
    column's current height from the particles' domains. Measured: -1.28 % .. -1.62 %."""
    cols = gimptest.columns_by_x(d)
    x0, x1 = d["x"][cols[0][0]], d["x"][cols[-1][-1]]
    worst, n, used = 0.0, 0, 0
    for col in cols:
        f = (sum(d["x"][i] for i in col) / len(col) - x0) / (x1 - x0)
        if not 0.2 <= f <= 0.8:
            continue
        used += 1
        H = max(d["y"][i] + d["ly"][i] for i in col) - min(d["y"][i] - d["ly"][i] for i in col)
        for i in col:
            e = d["sxx"][i] / (force / H) - 1
            n += 1
            if abs(e) > abs(worst):
                worst = e
    c.check("stress = true traction at every particle of the middle", n >= 20 and abs(worst) < 0.02,
            "%d particles in %d columns, worst sxx / (F / H) - 1 = %+.2f %% (tol 2 %%)" %
            (n, used, 100 * worst))


# Held load, damped to rest; true stress = p H0 / H with H the current height of a column.
p, H0 = 55e9, 10e-6
elong = {}
for size in (0.1, 0.5, 0.8):
    dump = os.path.join(args.work, "rest_%g.csv" % size)
    out = gimptest.run(args, "options/tension.opts", ["-gimp_damping", "2e8", "-ts_max_steps", "2500",
                                                  "-gimp_corner_size", str(size),
                                                  "-gimp_particle_dump", dump],
                       outdir=os.path.join(args.work, "rest_%g" % size))
    s = gimptest.summary(out)
    h = gimptest.history(out)
    elong[size] = h["strain_x"][-1]
    if size == 0.5:
        stress_profile(gimptest.read_csv(dump), p * H0)
# Measured: 0.3698, 0.3689, 0.3679 at 10 %, 50 %, 80 %: a spread of 0.53 %.
spread = (max(elong.values()) - min(elong.values())) / elong[0.5]
c.check("corner size", spread < 0.01, "elongation %s: spread %.2e" %
        (", ".join("%.4f at %g" % (elong[k], k) for k in sorted(elong)), spread))
c.done()
