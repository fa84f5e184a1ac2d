"""A penny-shaped crack inclined to a remote uniaxial tension (options/penny_inclined3d.opts):
K_I, K_II and K_III at every front point against the closed form for an inclined penny crack in
an infinite body.

The closed form. A crack of radius a with unit normal n in a remote uniaxial stress sigma e_z e_z
(beta the angle between n and e_z) carries on its plane the normal stress sigma_n = sigma cos^2
beta and the shear traction tau = sigma sin beta cos beta along the in-plane unit vector s (the
direction of the in-plane part of sigma.n). Around the front, with phi the angle of the front's
ahead direction a measured from s, turning about n (a = cos phi s + sin phi (n x s)):

    K_I   = 2 sigma_n sqrt(a / pi)                                  (constant),
    K_II  = 4 tau sqrt(a / pi) cos(phi) / (2 - nu),
    K_III = 4 (1 - nu) tau sqrt(a / pi) sin(phi) / (2 - nu).

Signs in gimp's frame (include/gimp/cracks/front.hpp: x1 = a, x2 = n, x3 = a x n; K_II > 0 slides
the normal's side along +a, K_III > 0 slides it along +x3). In the intact body the material on
the normal's side is held back by the shear traction -tau s from the other side; the crack frees
it, so the normal's side slides along +s against the other side, everywhere on the crack. The
slide's component along a is s.a = cos phi (K_II's sign) and along x3 = a x n it is
s.(a x n) = sin phi (K_III's sign): with phi as defined both closed forms hold with the signs as
written. In the scene n = (sin beta, 0, cos beta) and s = (-cos beta, 0, sin beta), n x s = -e_y:
the modelled half (y >= 0) is phi from -180 to 0 degrees. K_II changes sign at the front's crest
(y = a, phi = -90 degrees: positive on the side x < 0, negative on x > 0); K_III is negative all
along the half and changes sign on the symmetry plane y = 0 (phi = 0 and 180 degrees: the mirror
half has K_III > 0).

The frame of a front point is its polygon edge's (the disk is a regular polygon): a = t x n with t
along the edge; phi is taken from that a, which is the frame the integrals measure in (the
edge's a differs from the radial direction by up to half an edge's angle).

Errors as a fraction of a scale: K_I's of the exact K_I (constant along the front), K_II's and
K_III's of the largest |K| of their closed form over the front
(4 tau sqrt(a / pi) / (2 - nu) and (1 - nu) times it), so their zeros do not blow up the error.
Front points whose domain (tube half length L) reaches the symmetry plane y = 0 are the ends:
their tubes take the mirror images of the particles across the plane (docs/method.md, Symmetry
planes; summary.json's "images" is 2, both ends of the half front on the plane, checked). The interior points and the ends are
checked apart; every point is printed.

Checked (measured in brackets, as fractions of the scales above; the worst point of each): at
the 18 interior points K_I within 5 % [+2.9 %], K_II within 5 % [-1.6 %], K_III within 5 %
[-4.4 %, beside the front's crest]; at the 14 end points K_I within 5 % [+2.8 %], K_II within 5 %
[+0.9 %], K_III within 5 % [-1.6 %; -75.5 % before the mirror images]; the sign of K_II and
K_III the closed form's wherever it is above a fifth of its largest value; the run ends near rest
(kinetic below 1e-6 of the strain energy [4.6e-7]). The table is written to
<work>/penny_inclined3d_front.csv."""
import math
import os

import gimptest

args = gimptest.parse_args()
OPTS = "options/penny_inclined3d.opts"


def options(path):
    """The options of an options file as name -> value string."""
    out = {}
    with open(path) as f:
        for line in f:
            w = line.split()
            if w and w[0].startswith("-"):
                out[w[0][1:]] = w[1] if len(w) > 1 else ""
    return out


def reals(s):
    return [float(v) for v in s.split(",")]


def dot(u, v):
    return sum(p * q for p, q in zip(u, v))


def cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def unit(u):
    n = math.sqrt(dot(u, u))
    return [p / n for p in u]


o = options(os.path.join(args.root, OPTS))
disk = reals(o["gimp_crack0_disk"])
centre, n, a = disk[:3], unit(disk[3:6]), disk[6]
nu = float(o["gimp_nu"])
sigma = reals(o["gimp_traction0_value"])[2]
h_fine = float(o["gimp_h"]) / 2 ** (int(o["gimp_levels"]) - 1)
beta = math.acos(n[2])
sigma_n = sigma * math.cos(beta) ** 2
tau = sigma * math.sin(beta) * math.cos(beta)
tr = [sigma * n[2] * e for e in (0, 0, 1)]  # sigma.n
s = unit([tr[i] - dot(tr, n) * n[i] for i in range(3)])
m = cross(n, s)
root = math.sqrt(a / math.pi)
K0 = 2 * sigma * root
KI_exact = 2 * sigma_n * root
KII_max = 4 * tau * root / (2 - nu)
KIII_max = (1 - nu) * KII_max

# The disk's polygon as gimp builds it (src/input/scene_cracks3d.cpp, diskPolygon): e1 the axis
# least aligned with n made orthogonal to it, e2 = n x e1, vertices at 2 pi k / N from e1 towards
# e2, N a multiple of 4 with edges of about one finest cell.
least = min(range(3), key=lambda i: (abs(n[i]), i))
e1 = [1.0 if i == least else 0.0 for i in range(3)]
e1 = unit([e1[i] - dot(e1, n) * n[i] for i in range(3)])
e2 = cross(n, e1)
N = 4 * max(8, math.ceil(2 * math.pi * a / h_fine / 4))


def vertex(k):
    t = 2 * math.pi * k / N
    return [centre[i] + a * (math.cos(t) * e1[i] + math.sin(t) * e2[i]) for i in range(3)]


out = gimptest.run(args, OPTS)
sm = gimptest.summary(out)
front = sm["cracks"][0]["front"]
c = gimptest.Checks()

rows = []
off_edge = 0.0
for f in front:
    p, q = vertex(f["edge"]), vertex(f["edge"] + 1)
    t = unit([q[i] - p[i] for i in range(3)])
    d = [f["x"][i] - p[i] for i in range(3)]
    off_edge = max(off_edge, math.sqrt(max(0.0, dot(d, d) - dot(d, t) ** 2)))
    ahead = cross(t, n)
    phi = math.atan2(dot(ahead, m), dot(ahead, s))
    ex = (KI_exact, KII_max * math.cos(phi), KIII_max * math.sin(phi))
    got = (f["KI"], f["KII"], f["KIII"])
    err = ((got[0] - ex[0]) / ex[0], (got[1] - ex[1]) / KII_max, (got[2] - ex[2]) / KIII_max)
    end = f["x"][1] < f["L"]  # the domain reaches the symmetry plane y = 0
    rows.append(dict(phi=math.degrees(phi), x=f["x"], got=got, ex=ex, err=err, end=end,
                     G=f["G"], images=f["images"]))
c.check("front points on their polygon edges (the frame as gimp's)", off_edge < 1e-6 * a,
        "largest distance %.2g m, %d front points, %d-gon" % (off_edge, len(front), N))

E = float(o["gimp_E"])
Ep, mu = E / (1 - nu * nu), E / (2 * (1 + nu))
print("K_0 = 2 sigma sqrt(a/pi) = %.6g Pa m^0.5; exact K_I = %.6g, max |K_II| = %.6g, "
      "max |K_III| = %.6g" % (K0, KI_exact, KII_max, KIII_max))
print("%8s %7s | %8s %8s | %8s %8s | %8s %8s | %7s %7s %7s | %6s" %
      ("phi[deg]", "y/a", "K_I/K0", "exact", "K_II/K0", "exact", "K_III/K0", "exact",
       "e_I", "e_II", "e_III", "G/G_ex"))
path = os.path.join(args.work, "penny_inclined3d_front.csv")
with open(path, "w") as fcsv:
    fcsv.write("phi_deg,x,y,z,KI,KI_exact,KII,KII_exact,KIII,KIII_exact,err_I,err_II,"
               "err_III,G,G_exact,end\n")
    for r in sorted(rows, key=lambda r: r["phi"]):
        g, e, x = r["got"], r["ex"], r["x"]
        G_ex = (e[0] ** 2 + e[1] ** 2) / Ep + e[2] ** 2 / (2 * mu)
        print("%8.1f %7.3f | %8.4f %8.4f | %8.4f %8.4f | %8.4f %8.4f | %+6.1f%% %+6.1f%% "
              "%+6.1f%% | %6.3f%s" % (r["phi"], x[1] / a, g[0] / K0, e[0] / K0, g[1] / K0,
                                      e[1] / K0, g[2] / K0, e[2] / K0, 100 * r["err"][0],
                                      100 * r["err"][1], 100 * r["err"][2], r["G"] / G_ex,
                                      "  end" if r["end"] else ""))
        fcsv.write("%.4f,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.5e,%.5e,%.5e,%.9e,%.9e,%d\n"
                   % (r["phi"], x[0], x[1], x[2], g[0], e[0], g[1], e[1], g[2], e[2],
                      r["err"][0], r["err"][1], r["err"][2], r["G"], G_ex, r["end"]))

# Tolerances (fractions of the scales above): the target, 5 %, for every K at every point.
# - K_I: measured +2.9 % interior, +2.8 % at the ends.
# - K_II: measured -1.6 % and +0.9 %. The curvature terms of the interaction integrals carry it:
#   without them (the auxiliary fields turning with the front taken as exact) |K_II| was
#   0.76-0.83 of the closed form all along the front, +16.4 % and -17.8 % of its scale, and K_I
#   -5.5 % (5 mm tubes).
# - K_III: measured -4.4 % interior and -1.6 % at the ends. The interior's worst points are
#   beside the front's crest (y near a), where the front runs diagonally across the cells and G
#   from the domain integral, with no auxiliary field, is itself 14-16 % above the closed form's.
#   There K_III depends on the tube: -6.6, -5.4 and -4.4 % with radii of 4, 5 and 6 mm (the
#   scene's), -8 to -9 % for every radius from 3 to 7 mm before the domain integral's arc length
#   was continuous behind the front's vertices (docs/validation.md, Inclined penny crack). At the
#   ends the tubes take the particles' mirror images across y = 0; cut at the plane instead, the
#   roller's sigma_yy met K_III's auxiliary field there and K_III read -75.5 % (about -0.33 of
#   its scale where the closed form goes to zero on the plane).
TOL = {"interior": (0.05, 0.05, 0.05), "end": (0.05, 0.05, 0.05)}
for part in ("interior", "end"):
    sel = [r for r in rows if r["end"] == (part == "end")]
    for k, name in enumerate(("K_I", "K_II", "K_III")):
        worst = max(sel, key=lambda r: abs(r["err"][k]))
        scale = "the exact K_I" if k == 0 else "max |%s| of the closed form" % name
        c.check("%s at the %s points (%d)" % (name, part, len(sel)),
                abs(worst["err"][k]) <= TOL[part][k],
                "worst %+.2f %% of %s at phi = %.1f deg (tol %g %%)" %
                (100 * worst["err"][k], scale, worst["phi"], 100 * TOL[part][k]))

# Signs: K_II's changes at the crest (phi = -90 deg), K_III is negative on the whole half. Where
# the closed form is above a fifth of its largest value the measured sign must be the same.
bad = [(name, r["phi"]) for r in rows for k, name in ((1, "K_II"), (2, "K_III"))
       if abs(r["ex"][k]) > 0.2 * (KII_max, KIII_max)[k - 1] and r["got"][k] * r["ex"][k] <= 0]
npos = sum(r["got"][1] > 0 for r in rows)
c.check("signs of K_II and K_III as the closed form's", not bad,
        "%d front points with K_II > 0 (phi > -90 deg: %d), K_III < 0 at %d of %d; wrong: %s" %
        (npos, sum(r["phi"] > -90 for r in rows), sum(r["got"][2] < 0 for r in rows), len(rows),
         bad or "none"))

wrong = [r["phi"] for r in rows if r["images"] != 2]
c.check("the front's two ends on the symmetry plane", not wrong,
        "mirror images across y = 0 at both ends of the chain; wrong at phi = %s" %
        (wrong or "none"))

h = gimptest.history(out)
ratio = h["kinetic"][-1] / h["strain"][-1]
c.check("near rest", ratio <= 1e-6, "kinetic / strain energy = %.2e" % ratio)
c.done()
