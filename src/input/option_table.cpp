// The option table (input/options.hpp): every option of a scene, declared once. The run, the
// method and the outputs here; the bodies, loads, levels and cracks in option_table_parts.cpp;
// what exists in one dimension only in the feature table at the end.
#include "gimp/input/options.hpp"

#include "option_table.hpp"

namespace gimp::input {

// One declaration per entry, its help text on the next lines (kept so by clang-format off).
// clang-format off
namespace {

const std::vector<OptionSpec> kRun = {
    {"gimp_dim", Kind::Int, "", "2", "2|3", nullptr, intFrom(2, 3),
     "Spatial dimension of the scene: 2 or 3"},
    {"gimp_options_markdown", Kind::Bool, "", "false", "", nullptr, {},
     "Print this option table as Markdown (the list of docs/options.md) and exit"},
    {"gimp_scene", Kind::Word, "", "scene", "", nullptr, {},
     "Scene name, a plain file name: letters, digits, -, _ and . (not . or ..); the default"
     " output directory is output/<name>"},
    {"gimp_output_dir", Kind::Word, "", "output/<scene>", "", nullptr, {},
     "Output directory: history.csv, summary.json, fields.h5 with its XDMF files, checkpoint.h5"},
    {"gimp_output_interval", Kind::Int, "steps", "0", "", nullptr, atLeast(0),
     "Steps between HDF5 field outputs (0: the first and the last only)"},
    {"gimp_history_interval", Kind::Int, "steps", "10", "", nullptr, atLeast(1),
     "Steps between rows of history.csv"},
    {"gimp_monitor_interval", Kind::Int, "steps", "0", "", nullptr, atLeast(0),
     "Steps between energy and momentum monitor lines (0: off)"},
    {"gimp_sort_interval", Kind::Int, "steps", "50", "", nullptr, atLeast(0),
     "Steps between orderings of each rank's particles by level-0 cell (0: never)"},
    {"gimp_checkpoint_interval", Kind::Int, "steps", "0", "", nullptr, atLeast(0),
     "Steps between checkpoints (checkpoint.h5 in the output directory; 0: none, but on"
     " SIGINT/SIGTERM)"},
    {"gimp_restart", Kind::Word, "", "", "", nullptr, {},
     "Continue from this checkpoint (give the scene's options again; a relative path given in"
     " an options file is read beside that file)"},
    {"gimp_particle_dump", Kind::Word, "", "", "", nullptr, {},
     "Write the final particles as CSV (sorted by id) to this file"},
    {"gimp_grid_dump", Kind::Word, "", "", "", nullptr, {},
     "Write the active grid nodes as CSV (level, coordinates, zones) to this file"},
    {"gimp_balance", Kind::Bool, "", "true", "", nullptr, {},
     "Split level 0 among the ranks so that each holds about as many particles (counted from the"
     " bodies and the levels before seeding) along each axis the ranks divide; false: the same"
     " number of level-0 nodes each"},
    {"gimp_lanes", Kind::Bool, "", "true", "", nullptr, {},
     "Run the kernels of block particles in AVX2 lanes with FMA where the processor has them (2D:"
     " four particles at a time; 3D: a node's three components at once); the same results to"
     " round-off"},
    {"gimp_mms", Kind::Choice, "", "none", "none|skb1d", nullptr, {},
     "Manufactured solution: none, or skb1d (an axial standing wave in x, neo-Hookean, nu 0)"},
    {"gimp_mms_amplitude", Kind::Real, "m", "1e-4", "", nullptr, above(0),
     "Amplitude A of the manufactured solution"},
    {"gimp_hole_measure", Kind::Reals, "m", "", "cx,cy,r", nullptr, {},
     "Measure the hoop stress around the hole cx,cy,r (summary.json kt, hoop.csv; in 3D a"
     " cylinder along z, at mid-thickness)"},
    {"gimp_hole_measure_load", Kind::Real, "Pa", "", "", nullptr, {},
     "Remote stress p that normalises the hoop stress (load along x)"},
    {"gimp_memory_limit", Kind::Real, "bytes", "0", "", nullptr, atLeast(0),
     "Memory the run may take (0: the physical memory of the nodes it runs on); larger problems"
     " are refused before anything is allocated"},
};

const std::vector<OptionSpec> kMethod = {
    {"gimp_h", Kind::Real, "m", "(required)", "", nullptr, above(0),
     "Cell size of the background grid (level 0)"},
    {"gimp_domain", Kind::Reals, "m", "bodies + pad", "x0,y0,x1,y1", "x0,y0,z0,x1,y1,z1", {},
     "Grid domain, a whole number of cells (default: the bodies' bounding box padded by"
     " -gimp_pad cells)"},
    {"gimp_pad", Kind::Int, "cells", "2", "", nullptr, atLeast(0),
     "Cells of padding around the bodies for the default domain"},
    {"gimp_update", Kind::Choice, "", "musl", "usf|usl|musl", nullptr, {},
     "Update scheme: stress before the grid update (usf), after it (usl), or from the"
     " re-projected velocity (musl)"},
    {"gimp_transfer", Kind::Choice, "", "apic", "flip|apic|xpic", nullptr, {},
     "Particle velocity transfer: flip (FLIP/PIC blend of -gimp_flip), apic (affine PIC) or xpic"
     " (XPIC(m), m = -gimp_xpic_order)"},
    {"gimp_flip", Kind::Real, "", "1", "", nullptr, within(0, 1),
     "FLIP fraction of the particle velocity update with -gimp_transfer flip (1: FLIP, 0: PIC)"},
    {"gimp_xpic_order", Kind::Int, "", "2", "", nullptr, intFrom(1, 100),
     "Order m of XPIC(m): m - 1 extra projections filter the particle velocity (1: PIC)"},
    {"gimp_tracking", Kind::Choice, "", "cpdi2", "none|strain|stretch|corners|cpdi|cpdi2", nullptr, {},
     "Particle domain: none, strain ((1 + eps) l0), stretch (F l0), corners (the paper's corner"
     " tracking), cpdi (parallelogram of F) or cpdi2 (quadrilateral of tracked corners); the"
     " default cpdi2 is stretch with -gimp_multirate true"},
    {"gimp_corner_size", Kind::Real, "", "0.5", "", nullptr, within(0.1, 0.8),
     "Fictitious size of a tracked corner over the initial particle size"},
    {"gimp_separation_threshold", Kind::Real, "", "0.05", "", nullptr, above(0),
     "Gap between particles that started as neighbours, over their size, above which they count"
     " as separated"},
    {"gimp_half_step_start", Kind::Bool, "", "true", "", nullptr, {},
     "Start the leapfrog with a half kick (particle velocities at half steps; second order in"
     " time)"},
    {"gimp_cut_cells", Kind::Bool, "", "true", "", nullptr, {},
     "Particles whose square (cube in 3D) a hole or a curved edge (surface) cuts take the area"
     " (volume) inside the body and its centroid as position (false: whole squares or cubes"
     " whose centre is in the body)"},
    {"gimp_damping", Kind::Real, "1/s", "0", "", nullptr, atLeast(0),
     "Artificial damping coefficient d of Eq. 16"},
    {"gimp_mass_cutoff", Kind::Real, "", "1e-14 (apic), 1e-8", "", nullptr, within(0, 1, false, true),
     "Nodes lighter than this fraction of the mean particle mass are treated as empty"},
    {"gimp_cfl", Kind::Real, "", "0.3", "", nullptr, within(0, 1, true, false),
     "Default time step as a fraction of h_min / c_p, or of the critical step with"
     " -gimp_stability_check"},
    {"gimp_static_tol", Kind::Real, "", "0", "", nullptr, within(0, 1, false, true),
     "Stop at rest: when the kinetic energy falls below this fraction of the strain energy at"
     " three history rows in a row (0: off)"},
    {"gimp_static_min_time", Kind::Real, "s", "0", "", nullptr, atLeast(0),
     "Earliest time the rest criterion may stop the run"},
    {"gimp_stability_check", Kind::Bool, "", "false", "", nullptr, {},
     "Critical time step from the largest eigenvalue of M^-1 K (SLEPc): summary.json"
     " dt_critical, the default step -gimp_cfl x dt_critical, a -ts_dt above it refused"},
    {"gimp_stability_interval", Kind::Int, "steps", "0", "", nullptr, atLeast(0),
     "Steps between re-checks of the critical step (0: at the start only)"},
    {"gimp_allow_unstable_dt", Kind::Bool, "", "false", "", nullptr, {},
     "Accept a -ts_dt above the critical step (for stability studies)"},
    {"gimp_multirate", Kind::Bool, "", "false", "", nullptr, {},
     "A time step per level: level k steps with h_k / h_min times the finest step (-ts_dt)"},
    {"gimp_multirate_forces", Kind::Choice, "", "impulse", "impulse|node", nullptr, {},
     "How the rate classes' forces reach the nodes with -gimp_multirate: impulse (each class's"
     " at its own start; for waves) or node (at the start of each node's slowest class's step;"
     " exact at a static state; needs -gimp_update usl)"},
};

const std::vector<OptionSpec> kMaterial = {
    {"gimp_material", Kind::Choice, "", "linear", "linear|neohookean", nullptr, {},
     "Constitutive model: linear (hypoelastic, Jaumann rate) or neohookean (compressible)"},
    {"gimp_E", Kind::Real, "Pa", "(each body's)", "", nullptr, above(0), "Young's modulus"},
    {"gimp_nu", Kind::Real, "", "0", "", nullptr, within(-1, 0.5, true, true), "Poisson's ratio"},
    {"gimp_rho", Kind::Real, "kg/m^3", "(each body's)", "", nullptr, above(0), "Mass density"},
    {"gimp_plane", Kind::Choice, "", "strain", "strain|stress", nullptr, {},
     "The plane model: plane strain or plane stress"},
    {"gimp_thickness", Kind::Real, "m", "1", "", nullptr, above(0), "Out-of-plane thickness"},
    {"gimp_Gc", Kind::Real, "J/m^2", "(none)", "", nullptr, above(0),
     "Toughness: a crack tip (2D) or front point (3D) grows when its G reaches it (with"
     " -gimp_crack_growth mts)"},
};

} // namespace
// clang-format on

const std::vector<OptionSpec> &optionTable() {
  static const std::vector<OptionSpec> all = [] {
    std::vector<OptionSpec> t;
    for (const std::vector<OptionSpec> *part :
         {&kRun, &kMethod, &kMaterial, &bodyOptions(), &loadOptions(), &gridOptions()})
      t.insert(t.end(), part->begin(), part->end());
    return t;
  }();
  return all;
}

const std::vector<Feature> &featureTable() {
  static const std::vector<Feature> f = {
      {"crack polylines",
       In2D,
       {"gimp_crackK_points"},
       "a crack in the plane is a polyline; 3D cracks are planar polygons (-gimp_crackK_polygon, "
       "-gimp_crackK_disk)"},
      {"crack polygons",
       In3D,
       {"gimp_crackK_polygon", "gimp_crackK_disk", "gimp_crack_front_spacing"},
       "a 3D crack is a planar polygon with a front; a 2D crack is a polyline "
       "(-gimp_crackK_points)"},
      {"plane models",
       In2D,
       {"gimp_plane", "gimp_thickness"},
       "plane strain or stress and a thickness belong to plane scenes; 3D is the full model"},
      {"plane shapes",
       In2D,
       {"gimp_bodyK_shape=rectangle", "gimp_bodyK_shape=circle", "gimp_bodyK_shape=ellipse",
        "gimp_bodyK_shape=polygon", "gimp_bodyK_circle", "gimp_bodyK_ellipse", "gimp_bodyK_polygon",
        "gimp_bodyK_holes", "gimp_bodyK_hole_ellipses", "gimp_bodyK_hole_polygons",
        "gimp_bodyK_hole_polygonJ", "gimp_bodyK_add_boxes", "gimp_bodyK_add_circles",
        "gimp_bodyK_add_ellipses", "gimp_bodyK_add_polygons", "gimp_bodyK_add_polygonJ"},
       "plane bodies; 3D bodies are boxes, spheres and cylinders with "
       "box, spherical and cylindrical holes (3D bodies: box, sphere, cylinder, hole_boxes, "
       "hole_spheres, hole_cylinders), and particle files in both"},
      {"solid bodies",
       In3D,
       {"gimp_bodyK_shape=box", "gimp_bodyK_shape=sphere", "gimp_bodyK_shape=cylinder",
        "gimp_bodyK_sphere", "gimp_bodyK_cylinder", "gimp_bodyK_cylinder_axis",
        "gimp_bodyK_hole_spheres", "gimp_bodyK_hole_boxes", "gimp_bodyK_hole_cylinders",
        "gimp_bodyK_hole_cylinder_axis"},
       "solids and their holes exist in 3D (give -gimp_dim 3); plane bodies are rectangles, "
       "circles, ellipses and polygons"},
      {"a z axis",
       In3D,
       {"gimp_tractionK_side=back", "gimp_tractionK_side=front", "gimp_dbcK_side=back",
        "gimp_dbcK_side=front", "gimp_dbcK_uz", "gimp_dbcK_components=z", "gimp_dbcK_components=xz",
        "gimp_dbcK_components=yz", "gimp_dbcK_components=xyz", "gimp_bcK_z", "gimp_bcK_type=x",
        "gimp_bcK_type=y", "gimp_bcK_type=z"},
       "a z axis exists in 3D scenes (give -gimp_dim 3)"},
      {"loads on a disk of a face",
       In3D,
       {"gimp_tractionK_disk"},
       "a disk on a face: 2D tractions act on edges (give -gimp_dim 3 for faces)"},
  };
  return f;
}

} // namespace gimp::input
