"""Fixed-free elastic bar, axial mode 1 (docs/reference.md, section 1), GIMP with MUSL, no damping:
the period is within 1 % of T = 10 s and the total energy within 1 % over 5 periods."""
import math
import gimptest

args = gimptest.parse_args()
out = gimptest.run(args, "options/bar.opts", ["-gimp_history_interval", "2"])
h = gimptest.history(out)
t, u = h["time"], h["tip_ux"]
# Upward zero crossings of the tip displacement (u = A sin(omega t)).
ups = []
for k in range(1, len(t)):
    if u[k - 1] < 0 <= u[k]:
        ups.append(t[k - 1] + (t[k] - t[k - 1]) * (-u[k - 1]) / (u[k] - u[k - 1]))
E, L, rho, v0 = 100.0, 25.0, 1.0, 0.1
T = 2 * math.pi / (math.pi / (2 * L) * math.sqrt(E / rho))
c = gimptest.Checks()
c.check("crossings", len(ups) >= 4, "%d upward zero crossings in %.1f s" % (len(ups), t[-1]))
if len(ups) >= 2:
    period = (ups[-1] - ups[0]) / (len(ups) - 1)
    c.check("period", abs(period / T - 1) < 0.01,
            "measured %.5f s, exact %.5f s, error %.3f %%" % (period, T, 100 * (period / T - 1)))
amp = max(abs(x) for x in u)
exact_amp = v0 / (math.pi / (2 * L) * math.sqrt(E / rho))
c.check("amplitude", abs(amp / exact_amp - 1) < 0.02,
        "tip amplitude %.5f m, exact %.5f m" % (amp, exact_amp))
e = [k + s for k, s in zip(h["kinetic"], h["strain"])]
drift = max(abs(x / e[0] - 1) for x in e)
exact_e = rho * v0 ** 2 * L / 4  # per unit height and thickness; the bar is 1 x 1
c.check("energy", drift < 0.01 and t[-1] >= 5 * T * 0.999,
        "max |E/E0 - 1| = %.2e over %.1f periods; E0 = %.6g J, exact %.6g J" %
        (drift, t[-1] / T, e[0], exact_e))
c.check("initial energy", abs(e[0] / exact_e - 1) < 0.01, "E0 / exact - 1 = %.2e" % (e[0] / exact_e - 1))
c.done()
