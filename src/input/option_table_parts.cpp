// The option table's bodies, loads, constraints, probes, grid levels and cracks. A family's
// index is K (gimp_bodyK_box: body K = 0 .. -gimp_bodies - 1), a second index J.
#include "option_table.hpp"

namespace gimp::input {

// One declaration per entry, its help text on the next lines (kept so by clang-format off).
// clang-format off
namespace {

/// A body's shape: the option that names it and the shape's own option.
const std::vector<OptionSpec> &bodyShapes() {
  static const std::vector<OptionSpec> t = {
    {"gimp_bodies", Kind::Int, "", "1", "", nullptr, intFrom(1, 1000),
     "Number of bodies, each -gimp_bodyK_* with K = 0 .. N-1"},
    {"gimp_bodyK_shape", Kind::Choice, "", "rectangle (2D), box (3D)", "rectangle|circle|ellipse|polygon|file|box|sphere|cylinder", nullptr, {},
     "Shape of body K: in 2D rectangle (_box), circle, ellipse, polygon or a particle file; in"
     " 3D box, sphere, cylinder or a particle file"},
    {"gimp_bodyK_box", Kind::Reals, "m", "", "x0,y0,x1,y1", "x0,y0,z0,x1,y1,z1", {},
     "The body's rectangle (2D) or box (3D)"},
    {"gimp_bodyK_circle", Kind::Reals, "m", "", "cx,cy,r", nullptr, {}, "The body's circle"},
    {"gimp_bodyK_ellipse", Kind::Reals, "m", "", "cx,cy,a,b", nullptr, {},
     "The body's ellipse, half-axes a along x and b along y"},
    {"gimp_bodyK_polygon", Kind::Reals, "m", "", "x0,y0,x1,y1,...", nullptr, {},
     "The body's polygon (simple, at most 200 vertices)"},
    {"gimp_bodyK_file", Kind::Word, "", "", "", nullptr, {},
     "CSV file of the body's particles: x,y (3D: x,y,z) and lx,ly (lx,ly,lz) or V, optionally"
     " vx,vy (vx,vy,vz) (a relative path given in an options file is read beside that file)"},
    {"gimp_bodyK_sphere", Kind::Reals, "m", "", "cx,cy,cz,r", nullptr, {}, "The body's sphere"},
    {"gimp_bodyK_cylinder", Kind::Reals, "m", "", "a,b,r,lo,hi", nullptr, {},
     "The body's cylinder: centre in the two other coordinates (x, y, z order), radius, extent"
     " along its axis"},
    {"gimp_bodyK_cylinder_axis", Kind::Choice, "", "z", "x|y|z", nullptr, {},
     "The axis of the body's cylinder"},
  };
  return t;
}

/// A body's holes and the shapes joined to it.
const std::vector<OptionSpec> &bodyHoles() {
  static const std::vector<OptionSpec> t = {
    {"gimp_bodyK_holes", Kind::Reals, "m", "", "cx,cy,r,...", nullptr, {},
     "Circular holes removed from the body (at most 100)"},
    {"gimp_bodyK_hole_ellipses", Kind::Reals, "m", "", "cx,cy,a,b,...", nullptr, {},
     "Elliptic holes inside the body (at most 100)"},
    {"gimp_bodyK_hole_polygons", Kind::Int, "", "0", "", nullptr, intFrom(0, 20),
     "Number of polygonal holes, each _hole_polygonJ"},
    {"gimp_bodyK_hole_polygonJ", Kind::Reals, "m", "", "x0,y0,x1,y1,...", nullptr, {},
     "Polygonal hole J"},
    {"gimp_bodyK_add_boxes", Kind::Reals, "m", "", "x0,y0,x1,y1,...", nullptr, {},
     "Rectangles joined to the body (a union)"},
    {"gimp_bodyK_add_circles", Kind::Reals, "m", "", "cx,cy,r,...", nullptr, {},
     "Circles joined to the body"},
    {"gimp_bodyK_add_ellipses", Kind::Reals, "m", "", "cx,cy,a,b,...", nullptr, {},
     "Ellipses joined to the body"},
    {"gimp_bodyK_add_polygons", Kind::Int, "", "0", "", nullptr, intFrom(0, 20),
     "Number of polygons joined to the body, each _add_polygonJ"},
    {"gimp_bodyK_add_polygonJ", Kind::Reals, "m", "", "x0,y0,x1,y1,...", nullptr, {},
     "Polygon J joined to the body"},
    {"gimp_bodyK_hole_spheres", Kind::Reals, "m", "", "cx,cy,cz,r,...", nullptr, {},
     "Spherical holes removed from the body"},
    {"gimp_bodyK_hole_boxes", Kind::Reals, "m", "", "x0,y0,z0,x1,y1,z1,...", nullptr, {},
     "Box holes removed from the body"},
    {"gimp_bodyK_hole_cylinders", Kind::Reals, "m", "", "a,b,r,...", nullptr, {},
     "Cylindrical holes through the body: centre in the two other coordinates, radius"},
    {"gimp_bodyK_hole_cylinder_axis", Kind::Choice, "", "z", "x|y|z", nullptr, {},
     "The axis of the body's cylindrical holes"},
  };
  return t;
}

/// A body's particles, initial motion and own material.
const std::vector<OptionSpec> &bodyParticles() {
  static const std::vector<OptionSpec> t = {
    {"gimp_bodyK_ppc", Kind::Int, "", "4 (2D), 8 (3D)", "", nullptr, {},
     "Particles per cell: n^2 in 2D (1, 4, 9, ...), n^3 in 3D (1, 8, 27, ...)"},
    {"gimp_bodyK_hole_ppc", Kind::Int, "", "_ppc", "", nullptr, {},
     "Particles per cell in the cells next to a hole: a perfect square next to a circular hole"
     " (2D), a perfect cube next to a spherical or cylindrical one (3D)"},
    {"gimp_bodyK_hole_band", Kind::Real, "m", "one cell", "", nullptr, atLeast(0),
     "Width of the band around each hole that gets _hole_ppc"},
    {"gimp_bodyK_velocity", Kind::Reals, "m/s", "0", "vx,vy", "vx,vy,vz", {},
     "Initial velocity of the body"},
    {"gimp_bodyK_velocity_profile", Kind::Choice, "", "uniform", "uniform|sine_x", nullptr, {},
     "Initial velocity profile: uniform, or sine_x: velocity sin(k (X - x0)), x0 the body's low"
     " x"},
    {"gimp_bodyK_wavenumber", Kind::Real, "1/m", "", "", nullptr, {},
     "Wavenumber k of the sine_x profile"},
    {"gimp_bodyK_spin", Kind::Reals, "rad/s", "0", "w", "wx,wy,wz", {},
     "Initial rigid rotation about the centre of the body's box, added to the velocity: the"
     " angular velocity (about the plane's normal in 2D, a vector in 3D)"},
    {"gimp_bodyK_material", Kind::Choice, "", "-gimp_material", "linear|neohookean", nullptr, {},
     "The body's constitutive model"},
    {"gimp_bodyK_E", Kind::Real, "Pa", "-gimp_E", "", nullptr, above(0),
     "The body's Young's modulus"},
    {"gimp_bodyK_nu", Kind::Real, "", "-gimp_nu", "", nullptr, within(-1, 0.5, true, true),
     "The body's Poisson's ratio"},
    {"gimp_bodyK_rho", Kind::Real, "kg/m^3", "-gimp_rho", "", nullptr, above(0),
     "The body's mass density"},
    {"gimp_bodyK_Gc", Kind::Real, "J/m^2", "-gimp_Gc", "", nullptr, above(0),
     "The body's toughness: a crack tip or front point in it grows when its G reaches it (with"
     " -gimp_crack_growth mts)"},
  };
  return t;
}

/// Body force, tractions and penalty conditions.
const std::vector<OptionSpec> &faceLoads() {
  static const std::vector<OptionSpec> t = {
    {"gimp_gravity", Kind::Reals, "m/s^2", "0", "gx,gy", "gx,gy,gz", {},
     "Body force per unit mass"},
    {"gimp_tractions", Kind::Int, "", "0", "", nullptr, intFrom(0, 1000),
     "Number of tractions, each -gimp_tractionK_*"},
    {"gimp_tractionK_body", Kind::Int, "", "0", "", nullptr, {}, "The body the traction loads"},
    {"gimp_tractionK_side", Kind::Choice, "", "right", "left|right|bottom|top|back|front", nullptr, {},
     "The side of the body's box it loads (x-, x+, y-, y+, z-, z+)"},
    {"gimp_tractionK_range", Kind::Reals, "m", "the whole side", "from,to", "a0,a1,b0,b1", {},
     "The part of the side it loads: an interval along it (2D), a rectangle in its two in-face"
     " coordinates in axis order (3D)"},
    {"gimp_tractionK_disk", Kind::Reals, "m", "", "a,b,r", nullptr, {},
     "Load only the circle of the face: centre in its in-face coordinates (axis order), radius"},
    {"gimp_tractionK_value", Kind::Reals, "Pa", "(required)", "tx,ty", "tx,ty,tz", {},
     "The traction vector at full load (a dead load on the particles' initial faces)"},
    {"gimp_tractionK_ramp", Kind::Ramp, "s,-", "constant 1", "t0,f0,t1,f1,...", nullptr, {},
     "Load factor table, linear in between, held after the last entry"},
    {"gimp_dbcs", Kind::Int, "", "0", "", nullptr, intFrom(0, 1000),
     "Number of penalty displacement conditions (Eq. 9), each -gimp_dbcK_*"},
    {"gimp_dbcK_body", Kind::Int, "", "0", "", nullptr, {}, "The body the condition acts on"},
    {"gimp_dbcK_side", Kind::Choice, "", "right", "left|right|bottom|top|back|front", nullptr, {},
     "The side of the body's box it acts on"},
    {"gimp_dbcK_range", Kind::Reals, "m", "the whole side", "from,to", "a0,a1,b0,b1", {},
     "The part of the side it acts on (as for tractions)"},
    {"gimp_dbcK_components", Kind::Choice, "", "xy (2D), xyz (3D)", "x|y|z|xy|xz|yz|xyz", nullptr, {},
     "The constrained displacement components"},
    {"gimp_dbcK_ux", Kind::Ramp, "s,m", "0", "t0,u0,t1,u1,...", nullptr, {},
     "Prescribed displacement table of the x component"},
    {"gimp_dbcK_uy", Kind::Ramp, "s,m", "0", "t0,u0,t1,u1,...", nullptr, {},
     "Prescribed displacement table of the y component"},
    {"gimp_dbcK_uz", Kind::Ramp, "s,m", "0", "t0,u0,t1,u1,...", nullptr, {},
     "Prescribed displacement table of the z component"},
    {"gimp_dbcK_penalty_scale", Kind::Real, "", "1", "", nullptr, above(0),
     "Factor on -gimp_penalty for this condition"},
    {"gimp_penalty", Kind::Real, "Pa/m", "0", "", nullptr, atLeast(0),
     "Penalty alpha of Eq. 9 (0: 100 M / h_min, capped for stability at rho h_min / (2 dt^2); M"
     " the P-wave modulus)"},
    {"gimp_penalty_traction", Kind::Bool, "", "true", "", nullptr, {},
     "Include the traction term sigma_p n of Eq. 9 (false: pure penalty)"},
  };
  return t;
}

/// Node constraints and probes.
const std::vector<OptionSpec> &nodeLoads() {
  static const std::vector<OptionSpec> t = {
    {"gimp_bcs", Kind::Int, "", "0", "", nullptr, intFrom(0, 1000),
     "Number of grid-node constraints, each -gimp_bcK_*"},
    {"gimp_bcK_x", Kind::Real, "m", "", "", nullptr, {},
     "Constrain the grid nodes on the line (plane) x = value"},
    {"gimp_bcK_y", Kind::Real, "m", "", "", nullptr, {},
     "Constrain the grid nodes on the line (plane) y = value"},
    {"gimp_bcK_z", Kind::Real, "m", "", "", nullptr, {},
     "Constrain the grid nodes on the plane z = value"},
    {"gimp_bcK_type", Kind::Choice, "", "fixed", "fixed|roller|x|y|z", nullptr, {},
     "fixed (every component), roller (the normal component) or one component"},
    {"gimp_bcK_range", Kind::Reals, "m", "the whole line", "from,to", "a0,a1,b0,b1", {},
     "The part of the line (an interval) or plane (a rectangle, axis order) constrained"},
    {"gimp_probes", Kind::Int, "", "0", "", nullptr, intFrom(0, 1000),
     "Number of probes, each -gimp_probeK_*"},
    {"gimp_probeK_name", Kind::Word, "", "probeK", "", nullptr, {},
     "Probe name in history.csv and summary.json (a word without commas, quotes or spaces)"},
    {"gimp_probeK_x", Kind::Reals, "m", "(required)", "x,y", "x,y,z", {},
     "Initial position; the probe follows the particle nearest to it"},
  };
  return t;
}

/// The parts in their order.
std::vector<OptionSpec> joined(std::initializer_list<const std::vector<OptionSpec> *> parts) {
  std::vector<OptionSpec> all;
  for (const std::vector<OptionSpec> *p : parts)
    all.insert(all.end(), p->begin(), p->end());
  return all;
}

} // namespace

const std::vector<OptionSpec> &bodyOptions() {
  static const std::vector<OptionSpec> t = joined({&bodyShapes(), &bodyHoles(), &bodyParticles()});
  return t;
}

const std::vector<OptionSpec> &loadOptions() {
  static const std::vector<OptionSpec> t = joined({&faceLoads(), &nodeLoads()});
  return t;
}

const std::vector<OptionSpec> &gridOptions() {
  static const std::vector<OptionSpec> t = {
    {"gimp_levels", Kind::Int, "", "1", "", nullptr, intFrom(1, 8),
     "Number of grid levels (1: uniform); level K > 0 by -gimp_levelK_box and _ratio"},
    {"gimp_levelK_box", Kind::Reals, "m", "(required)", "x0,y0,x1,y1", "x0,y0,z0,x1,y1,z1", {},
     "Box of level K, its corners on the parent level's grid lines"},
    {"gimp_levelK_ratio", Kind::Real, "", "2", "", nullptr, intFrom(2, 16),
     "Refinement ratio of level K to its parent"},
    {"gimp_levelK_follow", Kind::Word, "", "none", "", nullptr, {},
     "What level K's box follows: none, crackC_tipT (2D: crack C's tip T, 0 its first point, 1"
     " its last), crackC_front (3D: the centre of crack C's front, the middle of its front points'"
     " bounding box) or probeN (probe N's particle); the box keeps its size and moves by whole cells"
     " of its parent when the point comes within _follow_margin of a face, and the particles it"
     " newly covers are split to its particle size"},
    {"gimp_follow_merge", Kind::Bool, "", "true", "", nullptr, {},
     "Where a following box moved away, merge the particles it had split (or seeded) back to the"
     " coarser level's size; false keeps them as they are"},
    {"gimp_levelK_follow_margin", Kind::Real, "m", "a quarter of the box's smallest side", "",
     nullptr, above(0), "How near a face of level K's box the point it follows may come"},
    {"gimp_cracks", Kind::Int, "", "0", "", nullptr, atLeast(0),
     "Number of cracks, each -gimp_crackK_points (2D) or -gimp_crackK_polygon or _disk (3D)"},
    {"gimp_crackK_points", Kind::Reals, "m", "(required)", "x0,y0,x1,y1,...", nullptr, {},
     "Crack polyline (at most 100 points): an end strictly inside a body is a tip, one on or"
     " outside its edge a mouth"},
    {"gimp_crackK_polygon", Kind::Reals, "m", "(required)", "x0,y0,z0,...", nullptr, {},
     "3D crack as a planar polygon (at most 1000 points): an edge inside a body is a front, one"
     " on or outside its surface a mouth"},
    {"gimp_crackK_disk", Kind::Reals, "m", "", "cx,cy,cz,nx,ny,nz,r", nullptr, {},
     "3D crack as a disk (centre, normal, radius), a regular polygon with edges of about one"
     " cell; instead of -gimp_crackK_polygon"},
    {"gimp_crack_j_radius", Kind::Real, "m", "5 cells at the tip", "", nullptr, above(0),
     "Radius of the J-integral's domain around each tip (2D: clipped to the tip's clearance;"
     " 3D: of the tube around the front, and its half-length along it, clipped at each front"
     " point to its clearance)"},
    {"gimp_crack_front_spacing", Kind::Real, "m", "2 cells at the front", "", nullptr, above(0),
     "3D: the largest distance between the front points where G and K are measured"},
    {"gimp_crack_growth", Kind::Choice, "", "none", "none|mts", nullptr, {},
     "Crack growth: none, or mts: a 2D tip whose G by J reaches the toughness -gimp_Gc grows by"
     " one increment in the direction of the maximum hoop stress from its K_I and K_II; a 3D"
     " front point whose G reaches it advances by one increment in the crack's plane (a kink or"
     " twist over 5 degrees stops the crack)"},
    {"gimp_crack_growth_step", Kind::Real, "m", "one cell at the tip or front", "", nullptr,
     above(0), "Length of a growth increment (at most the tip's J radius or the front's tube"
     " radius)"},
    {"gimp_crack_growth_length", Kind::Real, "m", "20 growth steps", "", nullptr, above(0),
     "The longest each tip or front may grow in all; the nodes within it of the tip's start (of"
     " the front as given, in the crack's plane) get second velocity fields at setup"},
    {"gimp_crack_growth_interval", Kind::Int, "steps", "10", "", nullptr, intFrom(1, 1e9),
     "Steps between growth checks (each measures every tip's or front point's G and K)"},
    {"gimp_crack_growth_release", Kind::Real, "s", "0", "", nullptr, atLeast(0),
     "The time over which an increment (a tip's segment, a front's advance) opens: the nodes it"
     " newly cut keep their two fields bonded, the bond falling linearly from whole to none (0:"
     " the increment opens at once)"},
  };
  return t;
}
// clang-format on

} // namespace gimp::input
