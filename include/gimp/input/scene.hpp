// A scene: everything a run needs, read from the PETSc options database and validated before
// the first step, in D = 2 or 3 dimensions. Bad input raises InputError with one line naming the
// option, the value and what would be valid.
//
// Scene<D> gathers its parts by concept: what a run writes (OutputOptions), the method
// (MethodOptions), how the run is driven and checked (RunControl), the grid (GridSpec<D>), the
// loads and constraints (Loads<D>) and what it measures (Measures); the bodies and their
// materials are the scene's own. Only the geometry depends on D: boxes, points, the bodies'
// shapes (input/bodies.hpp) and the faces that loads act on.
#pragma once

#include "gimp/core/box.hpp"
#include "gimp/core/errors.hpp"
#include "gimp/geometry/crack.hpp"
#include "gimp/geometry/crack_surface.hpp"
#include "gimp/input/bodies.hpp"
#include "gimp/input/material.hpp"

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace gimp {

enum class Update { USF, USL, MUSL };
enum class Transfer { Flip, Apic, Xpic };
enum class Tracking { None, Strain, Stretch, Corners, Cpdi, Cpdi2 };
/// The option values (-gimp_update, -gimp_transfer, -gimp_tracking) of each enum, in its order.
inline constexpr const char *kUpdateNames[] = {"usf", "usl", "musl"};
inline constexpr const char *kTransferNames[] = {"flip", "apic", "xpic"};
inline constexpr const char *kTrackingNames[] = {"none",    "strain", "stretch",
                                                 "corners", "cpdi",   "cpdi2"};

/// Whether particles carry tracked corners (corners: the paper's mode; cpdi2: the quadrilateral
/// CPDI domain).
inline bool tracksCorners(Tracking t) {
  return t == Tracking::Corners || t == Tracking::Cpdi2;
}
/// Whether the weights are CPDI's (Sadeghirad et al. 2011, 2013): averages of the grid's point
/// shape functions over the particle's parallelogram or quadrilateral, not tensor products.
inline bool usesCpdi(Tracking t) {
  return t == Tracking::Cpdi || t == Tracking::Cpdi2;
}
/// The sides of a body's box, in the order of Face::side: x-, x+, y-, y+, z-, z+.
enum class Side { Left = 0, Right = 1, Bottom = 2, Top = 3, Back = 4, Front = 5 };
enum class Mms { None, AxialWave };

/// Piecewise-linear time table of a load factor; empty means constant 1 (dead load).
struct Ramp {
  std::vector<double> t, f;
  double at(double time) const;
  /// The table's value, or zero when it is empty (a displacement held at zero).
  double valueOr0(double time) const { return t.empty() ? 0.0 : at(time); }
};

/// A part of one side of a body's box, where tractions and penalty conditions act: side 0 .. 2D-1
/// is x-, x+, y-, y+ (, z-, z+). In 2D a particle's edge lies on it, in 3D a particle's face. The
/// range is a part of the side: in 2D an interval along it, in 3D a rectangle in the side's two
/// in-face coordinates (from,to along the first, then the second, in axis order).
template <int D> struct Face {
  int body = 0;
  int side = 1;
  bool hasRange = false;
  std::array<double, 2 * (D - 1)> range{};
  int axis() const { return side / 2; }
  double normal() const { return side % 2 ? 1.0 : -1.0; }
  /// Whether the in-face coordinates of the point x lie in the range (always without one).
  bool inRange(const double *x) const {
    if (!hasRange) return true;
    int q = 0;
    for (int a = 0; a < D; ++a) {
      if (a == axis()) continue;
      if (x[a] < range[2 * q] || x[a] > range[2 * q + 1]) return false;
      ++q;
    }
    return true;
  }
};

template <int D> struct Traction : Face<D> {
  Coords<D> value{}; // traction vector at full load [Pa]
  Ramp ramp;
  bool hasDisk = false;         // 3D: only the circle `disk` of the face is loaded
  std::array<double, 3> disk{}; // a, b, r: a circle in the face's in-face coordinates
  /// 3D: the area of the rectangle [a0, a1] x [b0, b1] (in-face coordinates) that the traction
  /// loads: all of it, or with a disk the part inside the circle (exact).
  double loadedArea(double a0, double a1, double b0, double b1) const;
};

/// Prescribed displacement on a face by the penalty method (Eq. 9).
template <int D> struct DisplacementBC : Face<D> {
  std::array<bool, D> fix = filled(true); // constrained components
  std::array<Ramp, D> u;                  // prescribed displacement tables (empty: held at zero)
  double penaltyScale = 1.0;              // multiplies -gimp_penalty for this face
  static std::array<bool, D> filled(bool v) {
    std::array<bool, D> a;
    a.fill(v);
    return a;
  }
};

/// Grid-node constraint on the grid line (2D) or plane (3D) x_axis = coord, within a range of
/// it (an interval along the line, a rectangle of the plane).
template <int D> struct NodeBC {
  int axis = 0;
  double coord = 0;
  std::array<bool, D> fix = DisplacementBC<D>::filled(true);
  bool hasRange = false;
  std::array<double, 2 * (D - 1)> range{};
};

template <int D> struct Probe {
  std::string name;
  Coords<D> x{};
};

/// Where a run writes, and how often.
struct OutputOptions {
  std::string name = "scene";
  std::string outputDir;
  std::string particleDump; // final particles as CSV (-gimp_particle_dump)
  std::string gridDump;     // active grid nodes as CSV (-gimp_grid_dump)
  std::string restart;      // checkpoint to continue from (empty: a fresh run)
  int outputInterval = 0;   // steps between field outputs (0: initial and final only)
  int historyInterval = 10;
  int monitorInterval = 0;    // steps between monitor lines (0: off)
  int checkpointInterval = 0; // steps between checkpoints (0: none, but on an interrupt)
  int sortInterval = 50;      // steps between orderings of the particles by cell (0: never)
  bool help = false;
};

/// The method: update scheme, velocity transfer, domain tracking and their parameters.
struct MethodOptions {
  Update update = Update::MUSL;
  Transfer transfer = Transfer::Apic; // particle <-> grid velocity transfer
  double flip = 1.0;                  // FLIP fraction of -gimp_transfer flip
  int xpicOrder = 2;                  // m of XPIC(m)
  bool halfStepStart = true;          // leapfrog start: half kick on the first step
  bool cutCells = true;               // particles cut by a hole take the cut's area and centroid
  // (-gimp_tracking's default is cpdi2, set by readSceneOptions; a scene built in code names
  // its tracking, and with corners or cpdi2 seeds the particles' corners)
  Tracking tracking = Tracking::Stretch;
  double cornerSize = 0.5;           // fictitious corner size / initial particle size
  double separationThreshold = 0.05; // gap between former neighbours / particle size
  double massCutoff = 1e-14;         // relative to the mean particle mass
  double damping = 0;                // d of Eq. 16 [1/s]
  double cfl = 0.3;
  bool lanes = true;   // -gimp_lanes: block kernels in AVX2 lanes where the CPU has it
  bool balance = true; // -gimp_balance: level 0 split among the ranks by particles, not nodes
  /// APIC comes to exact rest only with nodes down to 1e-14 of a particle's mass active; FLIP
  /// and PIC stay quieter with the lightest nodes treated as empty (docs/method.md,
  /// *Small-mass cut-off and constraints*).
  static double defaultMassCutoff(Transfer t) { return t == Transfer::Apic ? 1e-14 : 1e-8; }
};

/// How the run is stepped, checked and stopped.
struct RunControl {
  bool multirate = false;         // a time step per level (-gimp_multirate, solver/multirate.cpp)
  bool multirateNodeRule = false; // -gimp_multirate_forces node (else impulse)
  bool stabilityCheck = false;    // critical step from the largest eigenvalue of M^-1 K (SLEPc)
  bool allowUnstableDt = false;   // accept a -ts_dt above the critical step
  int stabilityInterval = 0;      // steps between re-checks of the critical step (0: at start)
  double staticTol = 0;           // stop when kinetic < staticTol * strain energy (0: never)
  double staticTime = 0;          // ... but not before this time [s]
  double memoryLimit = 0;         // bytes the run may take (0: the physical memory of its nodes)
  Mms mms = Mms::None;            // a manufactured solution (physics/mms.hpp)
  double mmsAmplitude = 1e-4;
};

/// A level box that follows a point (-gimp_levelK_follow; solver/regrid.cpp): a crack tip (2D)
/// or a probe's particle. The box keeps its size and moves by whole cells of its parent level when
/// the point comes within `margin` of one of its faces.
struct LevelFollow {
  enum class Kind { None, CrackTip, CrackFront, Probe }; // CrackFront: a 3D crack's front
  Kind kind = Kind::None;
  int index = 0;     // the crack, or the probe
  int end = 0;       // the crack's tip: 0 its first point, 1 its last
  double margin = 0; // [m]
  bool operator==(const LevelFollow &o) const {
    return kind == o.kind && index == o.index && end == o.end;
  }
};

/// The background grid: level 0's cell size and domain, and the refined levels.
template <int D> struct GridSpec {
  BoxOf<D> domain{};
  double h = 0;                    // level-0 cell size
  bool domainGiven = false;        // -gimp_domain given (else the bodies' box padded by pad cells)
  PetscInt pad = 2;                // cells of padding around the bodies for the default domain
  std::vector<LevelBox<D>> levels; // levels[0] is the domain (moved boxes: as they are now)
  std::vector<LevelFollow> follow; // per level, what its box follows (follow[0]: nothing)
  bool followMerge = true;         // -gimp_follow_merge: merge the parts where a box moved away
  /// Whether some level's box follows a point.
  bool follows() const {
    for (const LevelFollow &f : follow)
      if (f.kind != LevelFollow::Kind::None) return true;
    return false;
  }
  /// The boxes the grid is built from: the levels, level 0 being the domain.
  std::vector<LevelBox<D>> levelBoxes() const {
    std::vector<LevelBox<D>> b = levels;
    if (!b.empty()) b[0] = {domain, 1};
    return b;
  }
};

/// The loads and constraints: body force, tractions and penalty conditions on the bodies'
/// faces, node constraints, and the probes that watch them.
template <int D> struct Loads {
  Coords<D> gravity{};
  std::vector<Traction<D>> tractions;
  std::vector<DisplacementBC<D>> dbcs;
  double penalty = 0;          // alpha of Eq. 9 [Pa/m]; 0: chosen from the material, grid and dt
  bool penaltyTraction = true; // include the traction term sigma_p n of Eq. 9
  std::vector<NodeBC<D>> bcs;
  std::vector<Probe<D>> probes;
};

/// The J-integral's default domain radius, in cells at the tip, and the smallest radius that
/// makes a domain (2D cracks).
constexpr double kJCells = 5.0, kJMinCells = 2.0;

/// The J-integral's domain at one crack tip (2D) or the front integrals' tube at one front point
/// (3D): the radius used, and whether the radius asked for (-gimp_crack_j_radius, or kJCells
/// cells) was clipped to the tip's or point's clearance (to the nearest body edge or surface,
/// hole, other crack or other part of its own crack). radius 0: no domain fits (closer than
/// kJMinCells cells to one of them), J (G and K) is not measured there.
struct JDomain {
  double radius = 0;
  bool clipped = false;
};

/// Crack growth at one 2D crack tip (-gimp_crack_growth mts), in the order of the tips (crack,
/// then end): where the tip started, the length of an increment, the longest it may grow in all
/// (the grid gives second fields to the nodes within that of the start), and whether it stopped
/// (an increment it could not take: it would leave that disk or its body, or meet a crack).
struct TipGrowth {
  int crack = 0, end = 0;
  std::array<double, 2> origin{};
  double step = 0, length = 0;
  bool stopped = false;
};

/// Crack growth along one 3D crack's front (-gimp_crack_growth mts): the polygon as given (the
/// front may advance at most `length` from it; the grid gives second fields to the nodes within
/// that of it, in its plane), the length of an increment, and whether it stopped (an increment it
/// could not take: out of that reach, kinking or twisting out of its plane, meeting a crack).
/// With a release time (-gimp_crack_growth_release), the polygon before each advance still
/// opening, with the time of the check that grew it [s]: what the advance newly cut follows from
/// it (the checkpoint keeps them).
struct FrontGrowth {
  int crack = 0;
  CrackSurface start;
  double step = 0, length = 0;
  bool stopped = false;
  std::vector<std::pair<double, CrackSurface>> opening;
};

/// The crack growth criterion: none, or a tip (2D) or front point (3D) grows when G reaches the
/// toughness, in the direction of the maximum hoop stress (docs/method.md, *Crack growth*).
enum class Growth { None, Mts };

/// What a run measures beyond energies and probes: crack tips and fronts, and a hole's hoop
/// stress (the cracks themselves are the scene's: Scene::cracks).
struct Measures {
  double crackJRadius = 0;              // -gimp_crack_j_radius [m] (0: not given, kJCells cells)
  double crackFrontSpacing = 0;         // -gimp_crack_front_spacing [m] (0: not given, 2 cells)
  std::vector<JDomain> jDomain;         // 2D: per crack tip (crack, then end); 3D: per front point
  Growth growth = Growth::None;         // -gimp_crack_growth
  int growthInterval = 10;              // -gimp_crack_growth_interval: steps between growth checks
  double growthRelease = 0;             // -gimp_crack_growth_release [s]: 0 opens at once
  std::vector<TipGrowth> tipGrowth;     // 2D: per crack tip, in order, with growth (else empty)
  std::vector<FrontGrowth> frontGrowth; // 3D: per crack, in order, with growth (else empty)
  bool holeMeasure = false; // hoop stress around a hole: centre, radius, remote stress p
  double hole[3] = {0, 0, 0};
  double holeLoad = 0;
};

template <int D>
struct Scene : OutputOptions, MethodOptions, RunControl, GridSpec<D>, Loads<D>, Measures {
  static constexpr int dim = D;
  std::vector<Body<D>> bodies;
  /// Explicit cracks: polylines with their ends classified as tips or mouths (2D), planar
  /// polygons with their edges classified as front or mouth (3D).
  std::vector<CrackOf<D>> cracks;
  Material material;       // the scene's (-gimp_E, ...): every body's unless it sets its own
  bool oneMaterial = true; // every body has the scene's material
  bool sceneE = true, sceneRho = true; // -gimp_E, -gimp_rho given (else every body gives its own)
  PetscInt64 idSlots = 1;              // particle id / idSlots = its body (set with the grid)
  /// The material of the particle with this id.
  const Material &materialOf(PetscInt64 id) const {
    return oneMaterial ? material : bodies[static_cast<size_t>(id / idSlots)].material;
  }
  /// The material of the body that holds the point (the scene's if none does).
  const Material &materialAt(const double *x) const;
  /// The cell size of the finest level whose (closed) box holds x (h, level 0's, outside every
  /// refined box) [m].
  double cellSizeAt(const double *x) const;
  /// The cell size of the finest level [m].
  double finestCell() const {
    double hk = this->h;
    for (size_t k = 1; k < this->levels.size(); ++k)
      hk /= this->levels[k].ratio;
    return hk;
  }
  /// The largest P-wave speed of the bodies' materials [m/s].
  double maxWaveSpeed() const;
  /// Whether the scene puts external forces on the nodes (body force, tractions, penalty
  /// conditions, a manufactured solution's body force).
  bool hasExternalForces() const;
};

/// The J domains of the 2D crack tips after the cracks grew (Measures::jDomain): the radius asked
/// for clipped to each tip's clearance as at input, without warnings; a crack's kinks from growth
/// do not clip it (docs/method.md, *Crack growth*).
void updateJDomains(Scene<2> &sc);

/// The front integrals' tubes of the 3D cracks after they grew (Measures::jDomain): as at input
/// (-gimp_crack_j_radius or its default, each clipped to its front point's clearance), without
/// warnings or refusals.
void updateFrontDomains(Scene<3> &sc);

/// A 3D crack polygon with its edges classified again against the bodies (after growth): cut
/// where they pass through a body's surface, each piece a front (inside the material) or a mouth.
CrackSurface classifyCrackEdges(const Scene<3> &sc, const CrackSurface &c);

/// The cell at the 3D cracks' fronts: that of the finest level whose box holds a front point
/// (sampled a cell apart), or h without cracks [m].
double frontCell(const Scene<3> &sc);

/// The largest distance between a 3D front's measuring points: -gimp_crack_front_spacing, or 2
/// cells at the front [m] (cracks::frontPoints).
double frontSpacing(const Scene<3> &sc);

/// Read and validate the scene from the options database (collective).
template <int D> PetscErrorCode readScene(MPI_Comm comm, Scene<D> &scene);

extern template struct Scene<2>;
extern template struct Scene<3>;

} // namespace gimp
