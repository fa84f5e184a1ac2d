"""The elastica of a cantilever under a dead transverse tip load, and the same measures taken
from gimp's particle dumps (tests/check_cantilever.py, runs/study_cantilever.py).

Reference. An inextensible, shear-rigid beam of length L, clamped at s = 0, carries at s = L a
force P of fixed direction (-y, transverse to the undeformed beam) and magnitude. With theta(s)
the rotation of the tangent (clockwise, so the tip moves to -y), the moment at s is
P (x(L) - x(s)), so EI theta' = P (x(L) - x(s)) and, with q = P L^2 / EI and s in units of L,

    theta'' = -q cos(theta),  theta(0) = 0,  theta'(1) = 0,
    x' = cos(theta),  y' = -sin(theta),  x(0) = y(0) = 0.

It is solved by shooting on theta'(0) (bisection: theta'(1) grows with theta'(0)) with RK4 on
4000 steps; q = 1 gives u/L = -0.05643, v/L = -0.30172, theta(L) = 26.434 degrees; q = 4
gives -0.32894, -0.66996, 64.242 degrees."""
import math

import numpy as np


def _rhs(y, q):
    th, k = y[0], y[1]
    return np.array([k, -q * math.cos(th), math.cos(th), -math.sin(th)])


def _shoot(q, k0, n):
    h = 1.0 / n
    y = np.array([0.0, k0, 0.0, 0.0])
    out = [y.copy()]
    for _ in range(n):
        a = _rhs(y, q)
        b = _rhs(y + 0.5 * h * a, q)
        c = _rhs(y + 0.5 * h * b, q)
        d = _rhs(y + h * c, q)
        y = y + h / 6 * (a + 2 * b + 2 * c + d)
        out.append(y.copy())
    return np.array(out)


class Elastica:
    """theta(s), x(s), y(s) of the clamped beam of length L under q = P L^2 / EI."""

    def __init__(self, q, length=1.0, n=4000):
        lo, hi = 0.0, q  # theta'(0) = q x(L)/L lies in (0, q]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if _shoot(q, mid, n)[-1, 1] > 0:
                hi = mid
            else:
                lo = mid
        y = _shoot(q, 0.5 * (lo + hi), n)
        self.L = length
        self.s = np.linspace(0.0, length, n + 1)
        self.theta, self.x, self.y = y[:, 0], y[:, 2] * length, y[:, 3] * length

    def at(self, s):
        """theta, u = x - s, v = y at arc length s (arrays or numbers)."""
        th = np.interp(s, self.s, self.theta)
        return th, np.interp(s, self.s, self.x) - s, np.interp(s, self.s, self.y)


def read_dump(path):
    """A -gimp_particle_dump as a structured array sorted by id."""
    d = np.genfromtxt(path, delimiter=",", names=True)
    return d[np.argsort(d["id"])]


def centre_line(dump0, dump1, y0):
    """The beam's centre line and section rotations from two dumps of the same particles
    (initial, deformed): particles are grouped in columns of equal initial x (= the arc length
    s of an inextensible centre line). A column's centre is the mean of its particles'
    positions (the section is symmetric about y0, the initial centre line); its rotation is the
    rotation of the section, the line the column's particles lie on (least squares of x and y
    against the initial y), measured clockwise like the elastica's theta. Beam theory's theta is
    the section's rotation; the slope of the centre line differs from it by the shear strain,
    and at the loaded end by the local distortion under the end traction (over about H / 5 the
    centre line's slope there was 1.6 degrees off while the section's rotation was not).
    Returns s, x, y, theta."""
    assert (dump0["id"] == dump1["id"]).all(), "the two dumps hold different particles"
    X0 = np.round(dump0["x"], 9)
    s = np.unique(X0)
    cx, cy, theta = (np.empty_like(s) for _ in range(3))
    for i, c in enumerate(s):
        m = X0 == c
        x, y, Y = dump1["x"][m], dump1["y"][m], dump0["y"][m]
        cx[i], cy[i] = x.mean(), y.mean() - y0
        ax, ay = np.polyfit(Y, x, 1)[0], np.polyfit(Y, y, 1)[0]
        theta[i] = math.atan2(ax, ay)  # the section's direction (0, 1) turns to (sin, cos)
    return s, cx, cy, theta
