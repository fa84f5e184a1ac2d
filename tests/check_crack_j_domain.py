"""The J-integral's domain at a crack tip clipped to the tip's clearance (docs/options.md, *The
J-integral's domain at each tip*), on a single-edge-notched strip: 40 x 20 mm, 1 mm cells, an
edge crack along y = 10 mm to the tip at x = 20 mm (10 mm from the top and bottom edges), pulled
by 1 MPa on top and bottom and damped for 3000 steps (kinetic / strain energy about 1e-6: J is
domain-independent to well under 1 % there). Checks:
1. the default radius (5 cells, 5 mm) is not clipped: j_radius 0.005, j_domain_clipped false,
   no warning;
2. -gimp_crack_j_radius 0.03 reaches past the top and bottom edges: the warning line, and in
   summary.json j_radius 0.01 (the clearance) and j_domain_clipped true; G_J and K_I by J from
   the clipped domain within 2 % of the default domain's (measured 0.23 %);
3. the same on 2 ranks: one warning line, the flag, G_J equal to 1 rank's to 1e-10;
4. the default radius in a strip 8 mm tall (clearance 4 mm) clips itself, with its warning;
5. a tip 1.5 cells from the edge: no domain fits, the warning, G_J, KI_J, KII_J and j_radius
   null while VCCT is measured; the same tip with a radius given is refused on 2 ranks with one
   error line.
"""
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
os.makedirs(args.work, exist_ok=True)
SCENE = os.path.join(args.work, "strip.opts")
with open(SCENE, "w") as f:
    f.write("""-gimp_scene j_domain_strip
-gimp_E 2.3e9
-gimp_nu 0.33
-gimp_rho 1500
-gimp_plane stress
-gimp_thickness 1e-3
-gimp_h 1e-3
-gimp_bodies 1
-gimp_body0_box 0,0,0.04,0.02
-gimp_body0_ppc 4
-gimp_cracks 1
-gimp_crack0_points -0.002,0.01,0.02,0.01
-gimp_tractions 2
-gimp_traction0_side top
-gimp_traction0_value 0,1e6
-gimp_traction1_side bottom
-gimp_traction1_value 0,-1e6
-gimp_damping 2e4
-gimp_transfer flip
-gimp_flip 0
-ts_dt 2e-7
-ts_max_steps 3000
-gimp_history_interval 500
-gimp_output_interval 0
""")


def run(name, extra=(), ranks=1, ok=True):
    """(process, the crack tip of summary.json or None)."""
    out = os.path.join(args.work, name)
    p = gimptest.run(args, SCENE, list(extra), ranks=ranks, outdir=out, expect_ok=False)
    if ok and p.returncode != 0:
        raise SystemExit("gimp failed (exit %d) on %s:\n%s%s" % (p.returncode, name, p.stdout,
                                                                 p.stderr))
    tip = gimptest.summary(out)["cracks"][0] if ok else None
    return p, tip


def lines(p, head):
    return [x for x in (p.stdout + p.stderr).splitlines() if x.startswith(head)]


CLIP = ("gimp: warning: option -gimp_crack_j_radius 0.03 at the tip 0.02,0.01 of crack 0 reaches "
        "the edge of body 0 (0.01 m away): its J domain is clipped to 0.01 m (j_domain_clipped "
        "in summary.json)")

# The 3000-step runs of one rank, two at a time (the 2-rank run after them).
first = gimptest.concurrently([lambda: run("default"),
                               lambda: run("clipped1", ["-gimp_crack_j_radius", "0.03"])])

# 1. The default domain.
p, base = first[0]
warned = lines(p, "gimp: warning:")
c.check("default radius: 5 cells, not clipped, no warning",
        abs(base["j_radius"] - 0.005) < 1e-15 and base["j_domain_clipped"] is False and
        not warned, "j_radius %s, clipped %s, warnings %s" % (base["j_radius"],
                                                              base["j_domain_clipped"], warned))

# 2. and 3. A radius past the edges, on 1 and 2 ranks.
clipped = {}
for ranks in (1, 2):
    p, t = first[1] if ranks == 1 else \
        run("clipped%d" % ranks, ["-gimp_crack_j_radius", "0.03"], ranks=ranks)
    clipped[ranks] = t
    warned = lines(p, "gimp: warning:")
    c.check("%d rank(s): the clipping warning, once" % ranks, warned == [CLIP],
            "warnings %s" % warned)
    c.check("%d rank(s): summary marks the clipped domain and its radius" % ranks,
            t["j_domain_clipped"] is True and abs(t["j_radius"] - 0.01) < 1e-15,
            "j_radius %s, j_domain_clipped %s" % (t["j_radius"], t["j_domain_clipped"]))
    dg, dk = t["G_J"] / base["G_J"] - 1, t["KI_J"] / base["KI_J"] - 1
    c.check("%d rank(s): G_J and K_I by J of the clipped domain within 2 %% of the default's"
            % ranks, abs(dg) < 0.02 and abs(dk) < 0.02,
            "G_J %.6g against %.6g (%+.3f %%), KI_J %+.3f %%; VCCT G %.6g" %
            (t["G_J"], base["G_J"], 100 * dg, 100 * dk, t["G_vcct"]))
d = abs(clipped[2]["G_J"] / clipped[1]["G_J"] - 1)
c.check("2 ranks give 1 rank's clipped G_J", d < 1e-10, "relative difference %.3g" % d)

# 4. The default radius in a thin strip.
p, t = run("thin", ["-gimp_body0_box", "0,0,0.04,0.008", "-gimp_crack0_points",
                    "-0.002,0.004,0.02,0.004", "-ts_max_steps", "10"])
want = ("gimp: warning: the default J radius 0.005 m (5 cells) at the tip 0.02,0.004 of crack 0 "
        "reaches the edge of body 0 (0.004 m away): its J domain is clipped to 0.004 m")
warned = lines(p, "gimp: warning:")
c.check("thin strip: the default radius clips itself",
        len(warned) == 1 and warned[0].startswith(want) and t["j_domain_clipped"] is True and
        abs(t["j_radius"] - 0.004) < 1e-15,
        "warnings %s; j_radius %s, clipped %s" % (warned, t["j_radius"], t["j_domain_clipped"]))

# 5. No domain fits.
near = ["-gimp_crack0_points", "-0.002,0.0185,0.02,0.0185", "-ts_max_steps", "10"]
p, t = run("none", near)
warned = lines(p, "gimp: warning:")
want = ("gimp: warning: the tip 0.02,0.0185 of crack 0 is 0.0015 m from the edge of body 0, less "
        "than 2 cells (0.002 m): no J domain fits, G_J, KI_J and KII_J are not measured there "
        "(null in summary.json)")
c.check("no domain fits: the warning, J null, VCCT measured",
        warned == [want] and t["G_J"] is None and t["KI_J"] is None and t["KII_J"] is None and
        t["j_radius"] is None and isinstance(t["G_vcct"], float),
        "warnings %s; G_J %s, j_radius %s, G_vcct %s" % (warned, t["G_J"], t["j_radius"],
                                                        t["G_vcct"]))
p, _ = run("none_given", near + ["-gimp_crack_j_radius", "0.003"], ranks=2, ok=False)
errors = lines(p, "gimp: error:")
want = ("gimp: error: option -gimp_crack_j_radius 0.003: no domain fits at the tip 0.02,0.0185 "
        "of crack 0: it is 0.0015 m from the edge of body 0, less than 2 cells (0.002 m)")
c.check("no domain fits, radius given: refused with one line on 2 ranks",
        p.returncode != 0 and len(errors) == 1 and errors[0].startswith(want),
        "exit %d, error lines %s" % (p.returncode, errors))
c.done()
