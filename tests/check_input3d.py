"""Bad input in 3D (-gimp_dim 3) stops the run before step 1 with one line naming the option, the
value and what is valid, and a non-zero exit code, as in 2D (tests/check_input.py): 3D values
of the wrong size, bad shapes, faces and planes, the 2D-only options given in 3D and the 3D-only
ones in 2D. The base scene is options/patch3d.opts (a 1 x 0.4 x 0.4 m box, h = 0.1 m)."""
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
# Every bad-input case of 3D scenes runs in one process in test_bad_input (tests/bad_input/
# cases3d.tsv). A few of them run here as processes: exit code 2 and exactly one line on stderr.
cases = [
    ('traction loads nothing', ['-gimp_traction0_range', '5,6,5,6'],
     '-gimp_traction0_side'),
    ('nu 0.5 in 3D', ['-gimp_nu', '0.5'],
     '-gimp_nu 0.5'),
    ('unknown option', ['-gimp_dampnig', '10'],
     '-gimp_dampnig'),
    ('crack polyline in 3D', ['-gimp_cracks', '1', '-gimp_crack0_points', '0,0,1,1'],
     '-gimp_crack0_points 0,0,1,1: not available with -gimp_dim 3'),
]
# The cases run two at a time (gimptest.concurrently) once they are all listed.
later = []


def bad_3d(name, extra, needle):
    p = gimptest.run(args, "options/patch3d.opts", extra + ["-ts_max_steps", "1"],
                     expect_ok=False,
                     outdir=os.path.join(args.work, "bad3d_" + name.replace(" ", "_")))
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    first = lines[0] if lines else "(no message)"
    one_line = len([l for l in lines if "error" in l.lower()]) == 1
    c.check(name, p.returncode == 2 and first.startswith("gimp: error: option") and
            needle in first and one_line, "exit %d: %s" % (p.returncode, first))


def bad_2d(name, extra, needle):
    p = gimptest.run(args, "options/patch.opts", extra + ["-ts_max_steps", "1"], expect_ok=False,
                     outdir=os.path.join(args.work, "bad2d_" + name.replace(" ", "_")))
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    first = lines[0] if lines else "(no message)"
    c.check(name, p.returncode == 2 and needle in first, "exit %d: %s" % (p.returncode, first))


for case in cases:
    later.append(lambda case=case: bad_3d(*case))

# 3D-only options given in 2D are refused (the 2D scene does not read them).
for name, extra, needle in (
        ("sphere in 2D", ["-gimp_body0_sphere", "0.5,0.2,0.2,0.1"],
         "-gimp_body0_sphere 0.5,0.2,0.2,0.1: not available with -gimp_dim 2 (solid bodies)"),
        ("disk in 2D", ["-gimp_traction0_disk", "0.2,0.2,0.1"],
         "-gimp_traction0_disk 0.2,0.2,0.1: not available with -gimp_dim 2")):
    later.append(lambda a=(name, extra, needle): bad_2d(*a))

# The front integrals' tubes against what they may not reach (docs/options.md, *3D: the tube at
# each front point*): a penny crack of radius 0.12 m centred in the 0.4 m square section (normal
# x, h = 0.025 m: the default radius 5 cells = 0.125 m) has its front 0.08 m from the faces y = 0,
# y = 0.4, z = 0 and z = 0.4 at the polygon's vertices on the axes: every front point's tube is
# clipped to its clearance (0.08 m at the nearest), with one warning naming the face; a radius
# under every clearance is not clipped; two parallel cracks 0.06 m apart clip each other's tubes;
# a crack 0.12 m wide has its tubes clipped to half its width by its own other side.
fine = ["-gimp_h", "0.025", "-ts_max_steps", "1", "-gimp_cracks", "1",
        "-gimp_crack0_disk", "0.5,0.2,0.2,1,0,0,0.12"]


def tubes_clipped():
    p = gimptest.run(args, "options/patch3d.opts", fine, expect_ok=False,
                     outdir=os.path.join(args.work, "tubes"))
    warned = [l for l in p.stdout.splitlines() if "gimp: warning: the default front radius" in l]
    front = gimptest.summary(os.path.join(args.work, "tubes"))["cracks"][0]["front"] \
        if p.returncode == 0 else []
    Rs = [f["R"] for f in front]
    c.check("tubes clipped at the faces", p.returncode == 0 and len(warned) == 1 and
            "body 0's face" in warned[0] and front and all(f["clipped"] for f in front) and
            abs(min(Rs) - 0.08) < 1e-9 and max(Rs) <= 0.125,
            "exit %d, %d points, R %s .. %s m; %s" % (p.returncode, len(front), min(Rs, default=0),
                                                      max(Rs, default=0), warned))


def tubes_fit():
    p = gimptest.run(args, "options/patch3d.opts", fine + ["-gimp_crack_j_radius", "0.07"],
                     expect_ok=False, outdir=os.path.join(args.work, "tubes_fit"))
    front = gimptest.summary(os.path.join(args.work, "tubes_fit"))["cracks"][0]["front"] \
        if p.returncode == 0 else []
    c.check("a radius within every clearance", p.returncode == 0 and "warning" not in p.stdout and
            front and all(f["R"] == 0.07 and not f["clipped"] for f in front),
            "exit %d, %d points" % (p.returncode, len(front)))


def tubes_two():
    p = gimptest.run(args, "options/patch3d.opts",
                     fine + ["-gimp_cracks", "2", "-gimp_crack1_disk", "0.56,0.2,0.2,1,0,0,0.12"],
                     expect_ok=False, outdir=os.path.join(args.work, "tubes_two"))
    warned = [l for l in p.stdout.splitlines() if "gimp: warning:" in l and "reaches crack" in l]
    cracks = gimptest.summary(os.path.join(args.work, "tubes_two"))["cracks"] \
        if p.returncode == 0 else []
    c.check("two cracks clip each other's tubes", p.returncode == 0 and len(warned) == 2 and
            len(cracks) == 2 and all(abs(max(f["R"] for f in k["front"]) - 0.06) < 1e-9
                                     for k in cracks),
            "exit %d; %s" % (p.returncode, warned))


def tubes_narrow():
    p = gimptest.run(args, "options/patch3d.opts",
                     ["-gimp_h", "0.025", "-ts_max_steps", "1", "-gimp_cracks", "1",
                      "-gimp_crack0_polygon", "0.5,0.11,0.1,0.5,0.23,0.1,0.5,0.23,0.3,0.5,0.11,0.3"],
                     expect_ok=False, outdir=os.path.join(args.work, "tubes_narrow"))
    warned = [l for l in p.stdout.splitlines() if "its own crack's front" in l]
    front = gimptest.summary(os.path.join(args.work, "tubes_narrow"))["cracks"][0]["front"] \
        if p.returncode == 0 else []
    c.check("a narrow crack's other side: half the distance", p.returncode == 0 and
            len(warned) == 1 and front and abs(min(f["R"] for f in front) - 0.06) < 1e-9,
            "exit %d, R %s; %s" % (p.returncode, sorted({f["R"] for f in front}), warned))


def two_ranks():
    # Under mpiexec an input error found alike on every rank ends every rank with one line.
    p = gimptest.run(args, "options/patch3d.opts",
                     ["-gimp_cracks", "1", "-gimp_crack0_points", "0,0,1,1"], ranks=2,
                     expect_ok=False, outdir=os.path.join(args.work, "bad3d_mpi"))
    lines = [l for l in p.stderr.splitlines() if "gimp: error" in l]
    c.check("2 ranks, one line", p.returncode != 0 and len(lines) == 1, "exit %d: %s" %
            (p.returncode, lines))


gimptest.concurrently(later + [tubes_clipped, tubes_fit, tubes_two, tubes_narrow, two_ranks])
c.done()
