"""sigma_z on the axis of the half-space under a circular load (options/halfspace3d.opts), read
from a particle dump as a user reads the field: at depth z0, the particles of the two layers
whose centres straddle z0 (within one particle spacing of it) and lie within rmax of the axis,
fitted by least squares with s0 + s1 r^2 + s2 (z - z0); s0 is the axis value. Shared by
tests/check_halfspace3d.py and runs/speed_error3d.py (standard library only)."""


def exact(z, p=1000.0, a=1.0):
    """Boussinesq's circular load on the axis: sigma_z = -p (1 - z^3 / (a^2 + z^2)^(3/2))."""
    return -p * (1 - z ** 3 / (a * a + z * z) ** 1.5)


def solve3(A, b):
    """Least squares with 3 unknowns by the normal equations (Gaussian elimination)."""
    M = [[sum(r[i] * r[j] for r in A) for j in range(3)] + [sum(r[i] * y for r, y in zip(A, b))]
         for i in range(3)]
    for i in range(3):
        piv = max(range(i, 3), key=lambda k: abs(M[k][i]))
        M[i], M[piv] = M[piv], M[i]
        for k in range(i + 1, 3):
            f = M[k][i] / M[i][i]
            M[k] = [x - f * y for x, y in zip(M[k], M[i])]
    x = [0.0] * 3
    for i in (2, 1, 0):
        x[i] = (M[i][3] - sum(M[i][j] * x[j] for j in range(i + 1, 3))) / M[i][i]
    return x


def axis_value(d, z0, spacing, rmax):
    """(s0, particles used) at depth z0 > 0 from a dump d (columns x, y, z, szz)."""
    rows, vals = [], []
    for x, y, z, s in zip(d["x"], d["y"], d["z"], d["szz"]):
        r2, dz = x * x + y * y, -z - z0
        if r2 < rmax * rmax and abs(dz) < spacing:
            rows.append((1.0, r2, dz))
            vals.append(s)
    return solve3(rows, vals)[0], len(rows)
