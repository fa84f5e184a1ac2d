"""Bad input in 3D (-gimp_dim 3) stops the run before step 1 with one line naming the option, the
value and what is valid, and a non-zero exit code, as in 2D (tests/check_input.py): 3D values
of the wrong size, bad shapes, faces and planes, the 2D-only options given in 3D and the 3D-only
ones in 2D. The base scene is options/patch3d.opts (a 1 x 0.4 x 0.4 m box, h = 0.1 m)."""
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
cases = [
    # (name, extra options, text the error line must contain)
    ("bad dimension", ["-gimp_dim", "4"], "-gimp_dim 4: must be an integer from 2 to 3"),
    ("2D box in 3D", ["-gimp_body0_box", "0,0,1,0.4"], "-gimp_body0_box 0,0,1,0.4: needs 6 values"),
    ("3D box inverted", ["-gimp_body0_box", "0,0,0.4,1,0.4,0"], "needs x0 < x1, y0 < y1 and z0 < z1"),
    ("2D domain in 3D", ["-gimp_domain", "-0.2,-0.2,1.2,0.6"], "-gimp_domain -0.2,-0.2,1.2,0.6"),
    ("domain not whole cells", ["-gimp_domain", "-0.2,-0.2,-0.2,1.25,0.6,0.6"], "whole number of cells"),
    ("body outside the domain", ["-gimp_domain", "0.2,-0.2,-0.2,1.2,0.6,0.6"], "must lie inside -gimp_domain"),
    ("ppc not a cube", ["-gimp_body0_ppc", "4"], "-gimp_body0_ppc 4: must be a perfect cube"),
    ("2D velocity", ["-gimp_body0_velocity", "1,0"], "-gimp_body0_velocity 1,0: needs 3 values"),
    ("2D gravity", ["-gimp_gravity", "0,-9.8"], "-gimp_gravity 0,-9.8: needs 3 values"),
    # a 3D option of another shape than the body's
    ("sphere of a box body", ["-gimp_body0_sphere", "0.5,0.2,0.2,0.1"],
     "-gimp_body0_sphere (given): is for shape sphere, but -gimp_body0_shape is box"),
    ("sphere radius", ["-gimp_bodies", "2", "-gimp_body1_shape", "sphere", "-gimp_body1_sphere",
                       "2,0.2,0.2,0"], "-gimp_body1_sphere 2,0.2,0.2,0: needs r > 0"),
    ("sphere missing", ["-gimp_bodies", "2", "-gimp_body1_shape", "sphere"],
     "-gimp_body1_sphere (missing)"),
    ("bad shape", ["-gimp_body0_shape", "cone"], "-gimp_body0_shape cone"),
    ("overlapping bodies", ["-gimp_bodies", "2", "-gimp_body1_shape", "sphere",
                            "-gimp_body1_sphere", "0.9,0.2,0.2,0.15"],
     "-gimp_body1_sphere: the body overlaps an earlier body"),
    ("empty body", ["-gimp_body0_hole_cylinders", "0.2,0.2,2", "-gimp_body0_hole_cylinder_axis", "x"],
     "-gimp_body0_box 0,0,0,1,0.4,0.4: the body holds no particle"),
    ("hole group", ["-gimp_body0_hole_spheres", "0.5,0.2,0.2"], "-gimp_body0_hole_spheres 0.5,0.2,0.2"),
    ("bad face", ["-gimp_traction0_side", "inside"], "-gimp_traction0_side inside"),
    ("2D traction value", ["-gimp_traction0_value", "100,0"], "-gimp_traction0_value 100,0: needs 3 values"),
    ("2D face range", ["-gimp_traction0_range", "0,0.4"], "-gimp_traction0_range 0,0.4: needs 4 values"),
    ("traction loads nothing", ["-gimp_traction0_range", "5,6,5,6"], "-gimp_traction0_side"),
    ("overlapping tractions", ["-gimp_tractions", "3", "-gimp_traction2_side", "right",
                               "-gimp_traction2_value", "1,0,0", "-gimp_traction2_range",
                               "0,0.2,0,0.2"],
     "-gimp_traction2_side: particles on it also lie on -gimp_traction0's"),
    ("loads on a body one particle thick", ["-gimp_body0_box", "0,0,0,0.05,0.4,0.4"],
     "-gimp_traction0_side: particles on it also lie on -gimp_traction1's"),
    ("disk loads nothing", ["-gimp_traction0_disk", "3,3,0.1"], "-gimp_traction0_side"),
    ("bc off the grid planes", ["-gimp_bcs", "1", "-gimp_bc0_z", "0.03"], "-gimp_bc0_z 0.03"),
    ("bc range reversed", ["-gimp_bcs", "1", "-gimp_bc0_x", "0", "-gimp_bc0_range", "1,0,1,0"],
     "-gimp_bc0_range 1,0,1,0: needs a0 < a1 and b0 < b1"),
    ("bc range off the grid", ["-gimp_bcs", "1", "-gimp_bc0_x", "0", "-gimp_bc0_range", "5,6,5,6"],
     "-gimp_bc0_range 5,6,5,6: no active grid node"),
    ("penalty without conditions", ["-gimp_penalty", "1e9"], "-gimp_penalty 1e9: acts only"),
    ("wavenumber without sine", ["-gimp_body0_wavenumber", "3"],
     "-gimp_body0_wavenumber 3: acts only with -gimp_body0_velocity_profile sine_x"),
    ("mms amplitude without mms", ["-gimp_mms_amplitude", "1e-3"],
     "-gimp_mms_amplitude 1e-3: acts only with -gimp_mms skb1d"),
    ("bc on two planes", ["-gimp_bcs", "1", "-gimp_bc0_x", "0", "-gimp_bc0_z", "0"], "exactly one"),
    ("dbc component", ["-gimp_dbcs", "1", "-gimp_dbc0_side", "left", "-gimp_dbc0_components", "x",
                       "-gimp_dbc0_uz", "0,0,1,0.001"], "-gimp_dbc0_uz (given)"),
    ("level box of 4", ["-gimp_levels", "2", "-gimp_level1_box", "0.2,0,0.8,0.4"],
     "-gimp_level1_box 0.2,0,0.8,0.4: needs 6 values"),
    ("level off grid lines", ["-gimp_levels", "2", "-gimp_level1_box", "0.25,0,0,0.8,0.4,0.4"],
     "-gimp_level1_box"),
    ("probe name with a comma", ["-gimp_probes", "1", "-gimp_probe0_name", "a,b",
                                 "-gimp_probe0_x", "0.5,0.2,0.2"], "-gimp_probe0_name a,b"),
    ("unstable dt", ["-ts_dt", "1"], "-ts_dt 1: exceeds the stable limit"),
    ("other TS type", ["-ts_type", "rk"], "-ts_type rk"),
    ("negative max time", ["-ts_max_time", "-1"], "-ts_max_time -1"),
    ("not a number", ["-gimp_E", "abc"], "-gimp_E abc"),
    ("nan", ["-gimp_rho", "nan"], "-gimp_rho nan"),
    ("nu 0.5 in 3D", ["-gimp_nu", "0.5"], "-gimp_nu 0.5"),
    ("unknown option", ["-gimp_dampnig", "10"], "-gimp_dampnig"),
    # What exists in 2D only (the dimension table), given in 3D: refused with its reason.
    ("cracks in 3D", ["-gimp_cracks", "1"], "-gimp_cracks 1: not available with -gimp_dim 3"),
    ("plane stress in 3D", ["-gimp_plane", "stress"],
     "-gimp_plane stress: not available with -gimp_dim 3 (plane models)"),
    ("multirate in 3D", ["-gimp_multirate", "true"], "-gimp_multirate true: not available"),
    ("circle in 3D", ["-gimp_body0_circle", "0.5,0.2,0.1"],
     "-gimp_body0_circle 0.5,0.2,0.1: not available with -gimp_dim 3"),
    ("2D holes in 3D", ["-gimp_body0_holes", "0.5,0.2,0.1"],
     "-gimp_body0_holes 0.5,0.2,0.1: not available with -gimp_dim 3"),
    ("corner tracking in 3D", ["-gimp_tracking", "corners"],
     "-gimp_tracking corners: not available with -gimp_dim 3"),
    ("cut cells in 3D", ["-gimp_cut_cells", "false"], "-gimp_cut_cells false: not available"),
    ("hole measure in 3D", ["-gimp_hole_measure", "0.5,0.2,0.1"], "-gimp_hole_measure 0.5,0.2,0.1: not"),
    ("cpdi in 3D", ["-gimp_tracking", "cpdi"], "-gimp_tracking cpdi: not available with -gimp_dim 3"),
    ("lanes in 3D", ["-gimp_lanes", "false"], "-gimp_lanes false: not available with -gimp_dim 3"),
    ("restart from no checkpoint", ["-gimp_restart", "x.h5"], "-gimp_restart x.h5: not a gimp checkpoint"),
]
for name, extra, needle in cases:
    p = gimptest.run(args, "options/patch3d.opts", extra + ["-ts_max_steps", "1"],
                     expect_ok=False, outdir=os.path.join(args.work, "bad3d"))
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    first = lines[0] if lines else "(no message)"
    one_line = len([l for l in lines if "error" in l.lower()]) == 1
    c.check(name, p.returncode == 2 and first.startswith("gimp: error: option") and
            needle in first and one_line, "exit %d: %s" % (p.returncode, first))

# 3D-only options given in 2D are refused (the 2D scene does not read them).
for name, extra, needle in (
        ("sphere in 2D", ["-gimp_body0_sphere", "0.5,0.2,0.2,0.1"],
         "-gimp_body0_sphere 0.5,0.2,0.2,0.1: not available with -gimp_dim 2 (solid bodies)"),
        ("disk in 2D", ["-gimp_traction0_disk", "0.2,0.2,0.1"],
         "-gimp_traction0_disk 0.2,0.2,0.1: not available with -gimp_dim 2")):
    p = gimptest.run(args, "options/patch.opts", extra + ["-ts_max_steps", "1"], expect_ok=False,
                     outdir=os.path.join(args.work, "bad2d"))
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    first = lines[0] if lines else "(no message)"
    c.check(name, p.returncode == 2 and needle in first, "exit %d: %s" % (p.returncode, first))

# Under mpiexec an input error found alike on every rank ends every rank with one line.
p = gimptest.run(args, "options/patch3d.opts", ["-gimp_cracks", "1"], ranks=2, expect_ok=False,
                 outdir=os.path.join(args.work, "bad3d_mpi"))
lines = [l for l in p.stderr.splitlines() if "gimp: error" in l]
c.check("2 ranks, one line", p.returncode != 0 and len(lines) == 1, "exit %d: %s" %
        (p.returncode, lines))
c.done()
