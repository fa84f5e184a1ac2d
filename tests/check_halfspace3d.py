"""A uniform pressure p on a circle of radius a on an elastic half-space, on three levels around
the load (options/halfspace3d.opts, a quarter by symmetry). Exact on the axis (Boussinesq's
circular load, independent of nu):

    sigma_z(z) = -p (1 - z^3 / (a^2 + z^2)^(3/2)).

The axis value is read from the particles as a user would read the field
(tests/halfspace_axis.py): at depth z0, the particles of the two layers whose centres straddle
z0 (within one finest particle spacing of it) and lie within r < a / 2 of the axis, fitted by
least squares with s0 + s1 r^2 + s2 (z - z0) (the field is even in r and smooth in z); s0 is
sigma_z on the axis.

Checked (measured in brackets): |s0 / exact - 1| within 0.6 % at z = a and z = 2a (the
validation figure) [0.26 %, 0.19 %], and within 3 % at every depth a / 2 .. 2.75 a on the curve, inside the
finest level [max 2.3 %, at a / 2]; the run ends at rest (kinetic below 1e-6 of the strain
energy). The curve is written to <work>/halfspace3d_axis.csv."""
import os
import gimptest
import halfspace_axis

args = gimptest.parse_args()
p, a = 1000.0, 1.0
spacing = 0.125  # particle spacing on the finest level (h_min = 0.25 m, 2 x 2 x 2 per cell)
dump = os.path.join(args.work, "halfspace3d_particles.csv")
out = gimptest.run(args, "options/halfspace3d.opts", ["-gimp_particle_dump", dump])
d = gimptest.read_csv(dump)


def axis_value(z0):
    return halfspace_axis.axis_value(d, z0, spacing, 0.5 * a)


exact = halfspace_axis.exact
c = gimptest.Checks()
worst = 0.0
with open(os.path.join(args.work, "halfspace3d_axis.csv"), "w") as f:
    f.write("z_over_a,sigma_z,exact,rel_error\n")
    for k in range(2, 12):  # inside the finest box (z >= -3 m)
        z0 = 0.25 * k * a
        s0, n = axis_value(z0)
        e = s0 / exact(z0) - 1
        f.write("%.4f,%.9e,%.9e,%.3e\n" % (z0 / a, s0, exact(z0), e))
        worst = max(worst, abs(e))
        if k in (4, 8):
            c.check("sigma_z at z = %ga" % (z0 / a), abs(e) <= 0.006,
                    "%.2f Pa from %d particles, exact %.2f Pa, error %.2f %% (tol 0.6 %%)" %
                    (s0, n, exact(z0), 100 * e))
c.check("sigma_z on the axis, z = a/2 .. 2.75a", worst <= 0.03, "max error %.2f %%" % (100 * worst))
h = gimptest.history(out)
ratio = h["kinetic"][-1] / h["strain"][-1]
c.check("at rest", ratio <= 1e-6, "kinetic / strain energy = %.2e" % ratio)
c.done()
