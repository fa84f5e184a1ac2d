"""Output contract (docs/output.md): summary.json keys, history.csv columns, HDF5 particle and
grid fields at the output interval, and XDMF files whose every HDF5 reference exists with
the stated dimensions."""
import os
import re
import gimptest

args = gimptest.parse_args()
out = gimptest.run(args, "options/patch.opts", ["-ts_max_steps", "100", "-gimp_output_interval", "40"])
c = gimptest.Checks()
s = gimptest.summary(out)
keys = ["scene", "version", "ranks", "steps", "time", "dt", "wall_seconds", "cpu_seconds",
        "particles", "levels",
        "energy", "probes", "measures"]
c.check("summary keys", all(k in s for k in keys), "missing: %s" % [k for k in keys if k not in s])
c.check("summary values", s["steps"] == 100 and s["ranks"] == 1 and s["particles"] == 160 and
        abs(s["time"] - 100 * s["dt"]) < 1e-12 and set(s["energy"]) >= {"kinetic", "strain",
        "external_work", "damping"} and "centre" in s["probes"],
        "steps %s, particles %s, probes %s" % (s["steps"], s["particles"], list(s["probes"])))
lv = s["levels"][0]
c.check("levels", abs(lv["h"] - 0.1) < 1e-15 and lv["active_nodes"] == 15 * 9,
        "h %g, box %s, active nodes %d" % (lv["h"], lv["box"], lv["active_nodes"]))
h = gimptest.history(out)
cols = ["step", "time", "kinetic", "strain", "external_work", "damping", "total", "momentum_x",
        "momentum_y", "centre_ux", "centre_sxx"]
c.check("history columns", all(k in h for k in cols), "columns %s" % list(h))
c.check("history rows", h["step"] == [float(i) for i in range(0, 101, 20)], "steps %s" % h["step"])
# Energy balance: kinetic + strain - external work + damping stays at its initial value (0)
# up to the O(dt) transfer error of a suddenly loaded, heavily damped (d dt = 0.1) block;
# a wrong sign or a missing term in any of them is an error of order the term itself.
scale = max(h["external_work"])
c.check("energy balance", max(abs(x) for x in h["total"]) < 0.06 * scale and
        h["damping"][-1] > 0.3 * scale,
        "max |total| = %.3e J vs external work %.3e J" % (max(abs(x) for x in h["total"]), scale))
try:
    import h5py
    f = h5py.File(os.path.join(out, "fields.h5"), "r")
    steps = sorted(f["particles"])
    c.check("hdf5 steps", steps == ["step_%08d" % i for i in (0, 40, 80, 100)], "groups %s" % steps)
    x = f["particles/step_00000100/x"]
    c.check("hdf5 particles", x.shape == (160, 2) and f["particles/step_00000100/stress"].shape ==
            (160, 4), "x %s" % (x.shape,))
    c.check("hdf5 grid", f["grid/step_00000100/level_0/velocity"].shape == (9, 15, 2),
            "velocity %s" % (f["grid/step_00000100/level_0/velocity"].shape,))
    bad = []
    for xmf in ("particles.xmf", "grid.xmf"):
        text = open(os.path.join(out, xmf)).read()
        for dims, ref in re.findall(r'Dimensions="([0-9 ]+)"[^>]*Format="HDF">fields\.h5:([^<]+)<', text):
            shape = tuple(int(d) for d in dims.split())
            if ref not in f or f[ref].shape != shape:
                bad.append(ref)
    c.check("xdmf references", not bad, "bad references: %s" % bad[:3])
except ImportError:
    c.check("h5py", False, "python3-h5py is not installed (tools/setup.sh installs it)")
c.done()
