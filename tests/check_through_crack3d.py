"""A straight crack through a slab (options/through_crack3d.opts), held in plane strain by
rollers on its faces, against the same scene in 2D plane strain (options/through_crack2d.opts):
an edge crack of length a = 10 mm in a 40 x 80 mm plate under remote tension, three levels to
1 mm, damped to rest.

The slab's crack polygon reaches 1 mm beyond both faces; input cuts its edge x = a at the faces,
so the front is the part inside the slab, and the grid nodes on the faces belong to one side of
the crack (a mouth edge lies there).

Checked (measured in brackets): at every front point, K_I by the interaction integral within 2 %
of the 2D K_I (the J-integral's interaction integral at the tip) [+5.5e-6], and K from G,
sqrt(G E / (1 - nu^2)), within 2 % of the 2D one [+2.7e-6]; K_II and K_III below 0.5 % of K_I
[3e-15]; the front points lie on the front inside the slab; both runs at rest (K_I changed by
less than 0.1 % over their last 400 steps). In pure shear, K_II within 2 % of the 2D K_II
[+5.5e-6] and K from G within 2 % [+2.8e-6], K_III below 0.5 % of K_II [2.9e-11] with a mirror
image of the tube across each face (the rollers' planes are symmetry planes; docs/method.md). A restart from a checkpoint of step 100 equals the
uninterrupted run at step 200 bit for bit."""
import math
import gimptest

args = gimptest.parse_args()
E, nu, t = 2.3e9, 0.3, 0.004
Ep = E / (1 - nu * nu)
d2 = gimptest.run(args, "options/through_crack2d.opts")
d3 = gimptest.run(args, "options/through_crack3d.opts")
tip = gimptest.summary(d2)["cracks"][0]
front = gimptest.summary(d3)["cracks"][0]["front"]
K2, KG2 = tip["KI_J"], math.sqrt(tip["G_J"] * Ep)
c = gimptest.Checks()
c.check("front points", len(front) >= 2 and all(
    abs(f["x"][0] - 0.01) < 1e-9 and abs(f["x"][1] - 0.04) < 1e-9 and 0 < f["x"][2] < t
    for f in front), "%d points at z = %s mm" % (len(front), ", ".join(
        "%.3f" % (1e3 * f["x"][2]) for f in front)))
for f in front:
    z = "z = %.2f mm" % (1e3 * f["x"][2])
    eI = f["KI"] / K2 - 1
    eG = math.sqrt(max(f["G"], 0) * Ep) / KG2 - 1
    c.check("K_I at " + z, abs(eI) <= 0.02,
            "%.1f kPa m^0.5 against 2D %.1f: %+.4f %% (tol 2 %%)" % (f["KI"] / 1e3, K2 / 1e3, 100 * eI))
    c.check("K from G at " + z, abs(eG) <= 0.02, "%+.4f %% against 2D (tol 2 %%)" % (100 * eG))
    other = max(abs(f["KII"]), abs(f["KIII"])) / f["KI"]
    c.check("K_II, K_III at " + z, other <= 0.005, "max |K_II|, |K_III| = %.1e K_I" % other)

# Mode II: the same slab in pure shear (tau = 1 MPa on all four sides; the crack faces slide),
# against the 2D twin's K_II by the interaction integral. The polygon's normal is -y where the 2D
# tip frame's is +y, so K_II changes sign with it. The rollers carry the plane-strain sigma_zz,
# odd about the crack plane in mode II: without the tubes' mirror images across the faces the
# mode III auxiliary field meets it there and K_III came out 27 % of K_II.
SHEAR = ["-gimp_tractions", "4", "-gimp_traction0_side", "top", "-gimp_traction1_side", "bottom",
         "-gimp_traction2_side", "right", "-gimp_traction3_side", "left"]
TAU3 = ["-gimp_traction0_value", "1e6,0,0", "-gimp_traction1_value", "-1e6,0,0",
        "-gimp_traction2_value", "0,1e6,0", "-gimp_traction3_value", "0,-1e6,0"]
TAU2 = [v.replace(",0,0", ",0").replace("0,1e6,0", "0,1e6").replace("0,-1e6,0", "0,-1e6")
        for v in TAU3]
s2 = gimptest.run(args, "options/through_crack2d.opts", SHEAR + TAU2, outdir=args.work + "/shear2d")
s3 = gimptest.run(args, "options/through_crack3d.opts", SHEAR + TAU3, outdir=args.work + "/shear3d")
K2II = gimptest.summary(s2)["cracks"][0]["KII_J"]
KG2s = math.sqrt(gimptest.summary(s2)["cracks"][0]["G_J"] * Ep)
for f in gimptest.summary(s3)["cracks"][0]["front"]:
    z = "z = %.2f mm" % (1e3 * f["x"][2])
    e = -f["KII"] / K2II - 1
    eG = math.sqrt(max(f["G"], 0) * Ep) / KG2s - 1
    c.check("shear: K_II at " + z, abs(e) <= 0.02,
            "%.1f kPa m^0.5 (normal -y) against 2D %.1f: %+.4f %% (tol 2 %%)" %
            (f["KII"] / 1e3, K2II / 1e3, 100 * e))
    c.check("shear: K from G at " + z, abs(eG) <= 0.02, "%+.4f %% against 2D (tol 2 %%)" % (100 * eG))
    c.check("shear: K_III at " + z, abs(f["KIII"]) <= 0.005 * abs(f["KII"]) and f["images"] == 2,
            "|K_III| = %.1e K_II, chain ends on a symmetry plane %d" % (abs(f["KIII"] / f["KII"]), f["images"]))

h2, h3 = gimptest.history(d2), gimptest.history(d3)
for name, h, col in (("2D", h2, "crack0_tip1_KI_J"), ("3D", h3, "crack0_KI_mean")):
    k = h[col]
    change = abs(k[-1] / k[-3] - 1)
    c.check(name + " at rest", change <= 1e-3, "K_I changed by %.1e over the last rows" % change)

# A restart from a checkpoint of step 100 ends at step 200 with the particles of the uninterrupted
# run, bit for bit (the crack's second fields are part of the checkpointed momentum).
full = args.work + "/full.csv"
gimptest.run(args, "options/through_crack3d.opts", ["-ts_max_steps", "200", "-gimp_particle_dump",
                                                     full], outdir=args.work + "/full")
part = args.work + "/part"
gimptest.run(args, "options/through_crack3d.opts",
             ["-ts_max_steps", "100", "-gimp_checkpoint_interval", "100"], outdir=part)
rest = args.work + "/rest.csv"
gimptest.run(args, "options/through_crack3d.opts",
             ["-ts_max_steps", "200", "-gimp_restart", part + "/checkpoint.h5",
              "-gimp_particle_dump", rest], outdir=part)
with open(full, "rb") as f, open(rest, "rb") as g:
    same = f.read() == g.read()
c.check("restart with a 3D crack", same, "step 200 after a restart at 100: particles %s" %
        ("identical" if same else "differ"))
c.done()
