// A scene: everything a run needs, read from the PETSc options database and validated
// before the first step. Bad input raises InputError with one line naming the option,
// the value and what would be valid.
#pragma once

#include "gimp/core/errors.hpp"
#include "gimp/cracks/geometry.hpp"
#include "gimp/input/particle_file.hpp"
#include "gimp/particles/shape.hpp"

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace gimp {

enum class Update { USF, USL, MUSL };
enum class Transfer { Flip, Apic, Xpic };
enum class Tracking { None, Strain, Stretch, Corners, Cpdi, Cpdi2 };

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
enum class MaterialModel { Linear, NeoHookean };
enum class Side { Left = 0, Right = 1, Bottom = 2, Top = 3 };
enum class Mms { None, Skb1d };

using Vec2 = std::array<double, 2>;
using Box = std::array<double, 4>; // x0, y0, x1, y1

/// Piecewise-linear time table of a load factor; empty means constant 1 (dead load).
struct Ramp {
  std::vector<double> t, f;
  double at(double time) const;
  /// The table's value, or zero when it is empty (a displacement held at zero).
  double valueOr0(double time) const { return t.empty() ? 0.0 : at(time); }
};

struct Material {
  MaterialModel model = MaterialModel::Linear;
  double E = 0, nu = 0, rho = 0;
  bool planeStrain = true;
  double thickness = 1.0; // [m]
  // derived
  double lambda = 0, mu = 0;
  double lambdaStar = 0;    // lambdaEff(), stored for the stress update
  double lambdaEff() const; // lambda, or its plane-stress reduction
  double waveSpeed() const; // P-wave speed of the 2D model [m/s]
};

struct Hole {
  double cx, cy, r;
};

struct Body {
  Material material;               // the scene's, unless -gimp_bodyK_E etc. set its own
  Shape shape;                     // rectangle (the default), ellipse (circle) or polygon
  std::string shapeOption = "box"; // the option that gave it: box, circle, ellipse, polygon, file
  Box box{};                       // the shape's bounding box (a rectangle's own box)
  std::vector<Hole> holes;         // circular holes (may cross a rectangle's sides)
  std::vector<Shape> shapeHoles;   // elliptic and polygonal holes (inside the shape)
  std::vector<Shape> added;        // shapes joined to the shape (-gimp_bodyK_add_*): the union
  std::string file;                // shape file: the particle file, and its particles
  ParticleFile fromFile;
  int ppc = 4;              // particles per cell (a perfect square: 1, 4, 9, ...)
  int holePpc = 0;          // particles per cell in cells next to a hole (0: same as ppc)
  double holeBand = 0;      // width of the band next to a hole that gets holePpc [m]
  Vec2 velocity{};          // initial velocity [m/s]
  bool sineProfile = false; // v = velocity * sin(k (X - x0)) instead of uniform
  double wavenumber = 0;    // k [1/m]
  double spin = 0;          // initial rigid rotation about the box's centre [rad/s]
  /// In the union of the shape and the added shapes (boundaries count as inside).
  bool inUnion(double x, double y) const;
  /// Strictly inside one of the union's shapes.
  bool strictlyInUnion(double x, double y) const;
  /// The raw moments of the part of the rectangle inside the union (Shape::momentsIn):
  /// inclusion-exclusion over the shapes, whose pairwise intersections are exact
  /// (intersectable) and which never overlap three at a time (both checked at input).
  std::array<double, 5> unionMomentsIn(double x0, double y0, double x1, double y1, double ox,
                                       double oy) const;
  /// The union's shapes: the shape, then the added ones.
  std::vector<const Shape *> parts() const;
  /// Points on the boundaries of the union's shapes.
  std::vector<std::array<double, 2>> boundaryPoints(int perShape) const;
  /// In the shape and in no hole (boundaries count as inside the body).
  bool inside(double x, double y) const;
  /// In the shape, off its boundary, and in no hole (not even on a hole's boundary).
  bool strictlyInside(double x, double y) const;
};

/// Whether two bodies share interior (a body inside another's hole does not).
bool bodiesOverlap(const Body &a, const Body &b);

/// A part of one side of a body's rectangle: where tractions and displacement conditions act.
struct Segment {
  int body = 0;
  Side side = Side::Right;
  bool hasRange = false;
  std::array<double, 2> range{}; // along the side
  int axis() const { return side == Side::Left || side == Side::Right ? 0 : 1; }
  double normal() const { return side == Side::Left || side == Side::Bottom ? -1.0 : 1.0; }
};

struct Traction : Segment {
  Vec2 value{}; // traction vector at full load [Pa]
  Ramp ramp;
};

/// Prescribed displacement on a segment by the penalty method (Eq. 9).
struct DisplacementBC : Segment {
  bool fix[2] = {true, true}; // constrained components
  Ramp u[2];                  // prescribed displacement tables (empty: held at zero)
  double penaltyScale = 1.0;  // multiplies -gimp_penalty for this segment
};

/// Grid-node constraint on a grid line x = c (axis 0) or y = c (axis 1).
struct NodeBC {
  int axis = 0;
  double coord = 0;
  bool fix[2] = {true, true};
  bool hasRange = false;
  std::array<double, 2> range{};
};

/// A grid level: level 0 is the domain; level k > 0 is a box inside level k-1 with cell size
/// h_{k-1} / ratio.
struct LevelSpec {
  Box box{};
  int ratio = 1;
};

struct Probe {
  std::string name;
  Vec2 x{};
};

struct Scene {
  std::string name = "scene";
  std::string outputDir;
  int outputInterval = 0; // steps between field outputs (0: initial and final only)
  int historyInterval = 10;
  int monitorInterval = 0; // steps between monitor lines (0: off)
  Box domain{};
  double h = 0;                  // level-0 cell size
  bool domainGiven = false;      // -gimp_domain given (else the bodies' box padded by pad cells)
  PetscInt pad = 2;              // cells of padding around the bodies for the default domain
  double memoryLimit = 0;        // bytes the run may take (0: the physical memory of its nodes)
  std::vector<LevelSpec> levels; // levels[0] is the domain
  std::vector<Body> bodies;
  Material material;       // the scene's (-gimp_E, ...): every body's unless it sets its own
  bool oneMaterial = true; // every body has the scene's material
  bool sceneE = true, sceneRho = true; // -gimp_E, -gimp_rho given (else every body gives its own)
  PetscInt64 idSlots = 1; // particle id / idSlots = its body (bodyIdSlots, set with the grid)
  /// The material of the particle with this id.
  const Material &materialOf(PetscInt64 id) const {
    return oneMaterial ? material : bodies[static_cast<size_t>(id / idSlots)].material;
  }
  /// The material of the body that holds the point (the scene's if none does).
  const Material &materialAt(double x, double y) const;
  /// The largest P-wave speed of the bodies' materials [m/s].
  double maxWaveSpeed() const;
  Vec2 gravity{};
  std::vector<Traction> tractions;
  std::vector<DisplacementBC> dbcs;
  double penalty = 0;          // alpha of Eq. 9 [Pa/m]; 0: chosen from the material, grid and dt
  bool penaltyTraction = true; // include the traction term sigma_p n of Eq. 9
  std::vector<NodeBC> bcs;
  double damping = 0;
  Update update = Update::MUSL;
  Transfer transfer = Transfer::Apic; // particle <-> grid velocity transfer
  double flip = 1.0;                  // FLIP fraction of -gimp_transfer flip
  int xpicOrder = 2;                  // m of XPIC(m)
  bool halfStepStart = true;          // leapfrog start: half kick on the first step
  bool cutCells = true;               // particles cut by a hole take the cut's area and centroid
  Tracking tracking = Tracking::Stretch;
  double cornerSize = 0.5;           // fictitious corner size / initial particle size
  double separationThreshold = 0.05; // gap between former neighbours / particle size
  double massCutoff = 1e-14;         // relative to the mean particle mass
  /// APIC comes to exact rest only with nodes down to 1e-14 of a particle's mass active; FLIP
  /// and PIC stay quieter with the lightest nodes treated as empty (docs/method.md,
  /// *Small-mass cut-off and constraints*).
  static double defaultMassCutoff(Transfer t) { return t == Transfer::Apic ? 1e-14 : 1e-8; }
  double cfl = 0.3;
  bool multirate = false;         // a time step per level (-gimp_multirate, solver/multirate.cpp)
  bool multirateNodeRule = false; // -gimp_multirate_forces node (else impulse)
  bool stabilityCheck = false;    // critical step from the largest eigenvalue of M^-1 K (SLEPc)
  bool allowUnstableDt = false;   // accept a -ts_dt above the critical step
  int stabilityInterval = 0;      // steps between re-checks of the critical step (0: at start)
  double staticTol = 0;           // stop when kinetic < staticTol * strain energy (0: never)
  double staticTime = 0;          // ... but not before this time [s]
  std::vector<Probe> probes;
  std::vector<Crack> cracks; // explicit cracks, ends classified as tips or mouths
  double crackJRadius = 0;   // J-integral domain radius [m] (0: 5 finest cells)
  Mms mms = Mms::None;
  double mmsAmplitude = 1e-4;
  bool holeMeasure = false; // hoop stress around a hole: centre, radius, remote stress p
  double hole[3] = {0, 0, 0};
  double holeLoad = 0;
  std::string particleDump;
  std::string gridDump;
  int checkpointInterval = 0; // steps between checkpoints (0: none, but on an interrupt)
  int sortInterval = 50;      // steps between orderings of the particles by cell (0: never)
  bool lanes = true;   // -gimp_lanes: 2D block particles four at a time (AVX2) where the CPU has it
  std::string restart; // checkpoint to continue from (empty: a fresh run)
  bool help = false;
};

/// Read and validate the scene from the options database (collective).
PetscErrorCode readScene(MPI_Comm comm, Scene &scene);

} // namespace gimp
