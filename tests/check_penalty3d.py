"""Penalty displacement conditions (Eq. 9) in 3D (options/penalty3d.opts): a free block held at
x = 0 and pulled to u = 1e-4 m at x = L by penalty conditions on its x faces (x components
only), damped to rest. Exact (small strain; the finite-strain correction is O(u / L) = 1e-4):
uniaxial stress sigma_xx = E u / L, every other component 0, the two conditions' forces on the
body -+ sigma_xx A.

Checked (measured in brackets): every particle's sigma_xx within 1e-3 of E u / L [1.5e-4] and
the other components below 1e-3 of it [6.4e-5]; the reactions equal and opposite and within
1e-3 of sigma_xx A [7.4e-5]; the energy balance (kinetic + strain - external work + damping)
within 5e-3 of the external work over the run [1.3e-3, while the ends move; 1.6e-4 at rest: the
work is taken from the grid velocities at each step's start and end, an O(dt) ledger]; at rest (kinetic below 1e-12 of the strain energy).
A wrong prescribed value (--extra "-gimp_dbc1_ux 0,0,0.05,1.1e-4,10,1.1e-4") fails the first
checks."""
import os
import gimptest

args = gimptest.parse_args()
E, u, L, A = 1e7, 1e-4, 1.0, 0.16
s_ex = E * u / L
dump = os.path.join(args.work, "penalty3d.csv")
out = gimptest.run(args, "options/penalty3d.opts", ["-gimp_particle_dump", dump])
d = gimptest.read_csv(dump)
s = gimptest.summary(out)
h = gimptest.history(out)
c = gimptest.Checks()
exx = max(abs(v / s_ex - 1) for v in d["sxx"])
eo = max(max(abs(v) for v in d[k]) for k in ("syy", "szz", "syz", "sxz", "sxy")) / s_ex
c.check("sxx", exx <= 1e-3, "max |sxx / (E u / L) - 1| = %.2e over %d particles" % (exx, len(d["sxx"])))
c.check("other components", eo <= 1e-3, "max |s_ij| / sxx = %.2e" % eo)
r0, r1 = s["reactions"]["dbc0"], s["reactions"]["dbc1"]
er = max(abs(-r0[0] / (s_ex * A) - 1), abs(r1[0] / (s_ex * A) - 1))
side = max(abs(v) for v in r0[1:] + r1[1:])
c.check("reactions", er <= 1e-3 and side == 0.0,
        "dbc0 %.6g N, dbc1 %.6g N, exact -+%.6g N: %.2e; y, z components %g" %
        (r0[0], r1[0], s_ex * A, er, side))
bal = max(abs(t) for t in h["total"]) / max(h["external_work"])
c.check("energy balance", bal <= 5e-3, "max |total| / external work = %.2e" % bal)
rest = h["kinetic"][-1] / h["strain"][-1]
c.check("at rest", rest <= 1e-12, "kinetic / strain = %.1e" % rest)
c.done()
