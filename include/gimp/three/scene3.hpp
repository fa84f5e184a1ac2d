// The 3D scene (-gimp_dim 3): what a 3D run needs, read from the options database and checked
// before the first step. The options keep their 2D names with 3D values (boxes of 6 numbers,
// vectors of 3); what exists in 2D only is refused in one line (three/scene3.cpp).
#pragma once

#include "gimp/grid/lattice.hpp"
#include "gimp/input/scene.hpp"

#include <array>
#include <string>
#include <vector>

namespace gimp::three {

using Vec3 = std::array<double, 3>;
using Box3 = std::array<double, 6>; // x0, y0, z0, x1, y1, z1

/// A hole of a body: an open box, an open sphere (centre c, radius r) or an open cylinder along
/// `axis` through the whole body (centre c in the other two coordinates, the axial one ignored).
/// A round body's shape is a closed Round (a cylinder from lo to hi along its axis).
struct Round {
  enum Kind { Sphere, Cylinder, BoxHole } kind = Sphere;
  int axis = 2;
  Vec3 c{};
  double r = 0, lo = -1e300, hi = 1e300;
  Box3 b{}; // BoxHole: its corners
  /// In the closed shape (a sphere or a cylinder between lo and hi).
  bool contains(const double *x) const;
  /// Strictly inside (a hole: its surface belongs to the body).
  bool strictlyContains(const double *x) const;
  Box3 box() const;
};

struct Body3 {
  Material material;
  enum Shape { BoxShape, RoundShape } shape = BoxShape;
  Box3 box{};  // the body's box (a round body's bounding box)
  Round round; // the sphere or cylinder of a round body
  std::vector<Round> holes;
  int ppc = 8; // particles per cell, a perfect cube (1, 8, 27, ...)
  Vec3 velocity{};
  bool sineProfile = false; // v = velocity sin(k (X - x0)) along x
  double wavenumber = 0;
  /// In the shape and in no hole (boundaries count as inside the shape, holes are open).
  bool inside(const double *x) const;
  /// The option that gave the shape: box, sphere or cylinder.
  const char *shapeOption() const {
    return shape == BoxShape ? "box" : round.kind == Round::Sphere ? "sphere" : "cylinder";
  }
};

/// A face of a body's box: side 0..5 is x-, x+, y-, y+, z-, z+; the range is a rectangle in the
/// face's two in-face coordinates (in increasing axis order).
struct Face {
  int body = 0, side = 1;
  bool hasRange = false;
  std::array<double, 4> range{}; // from,to along the first in-face axis, then the second
  int axis() const { return side / 2; }
  double normal() const { return side % 2 ? 1.0 : -1.0; }
  /// Whether the in-face coordinates of x lie in the range (always without one).
  bool inRange(const double *x) const;
};

struct Traction3 : Face {
  Vec3 value{};
  Ramp ramp;
  bool hasDisk = false;
  std::array<double, 3> disk{}; // a, b, r: a circle in the face's in-face coordinates
  /// The area of the rectangle [a0, a1] x [b0, b1] (in-face coordinates) that the traction loads:
  /// all of it, or with a disk the part inside the circle (exact).
  double loadedArea(double a0, double a1, double b0, double b1) const;
};

struct DisplacementBC3 : Face {
  bool fix[3] = {true, true, true};
  Ramp u[3];
  double penaltyScale = 1.0;
};

/// Grid-node constraint on the plane x_axis = coord, within a rectangle of the plane.
struct NodeBC3 {
  int axis = 0;
  double coord = 0;
  bool fix[3] = {true, true, true};
  bool hasRange = false;
  std::array<double, 4> range{};
};

struct Probe3 {
  std::string name;
  Vec3 x{};
};

struct Scene3 {
  std::string name = "scene", outputDir;
  std::string particleDump; // final particles as CSV (-gimp_particle_dump)
  int outputInterval = 0, historyInterval = 10, monitorInterval = 0;
  int sortInterval = 50; // steps between orderings of each rank's particles by cell (0: never)
  Box3 domain{};
  double h = 0;
  bool domainGiven = false;
  PetscInt pad = 2;
  std::vector<LevelBox<3>> levels; // levels[0] is the domain
  std::vector<Body3> bodies;
  Material material;
  bool oneMaterial = true;
  PetscInt64 idSlots = 1;
  const Material &materialOf(PetscInt64 id) const {
    return oneMaterial ? material : bodies[static_cast<size_t>(id / idSlots)].material;
  }
  double maxWaveSpeed() const;
  Vec3 gravity{};
  std::vector<Traction3> tractions;
  std::vector<DisplacementBC3> dbcs;
  double penalty = 0;
  bool penaltyTraction = true;
  std::vector<NodeBC3> bcs;
  double damping = 0;
  Update update = Update::MUSL;
  Transfer transfer = Transfer::Apic;
  double flip = 1.0;
  bool halfStepStart = true;
  Tracking tracking = Tracking::Stretch; // none or stretch
  double massCutoff = 1e-14;
  double cfl = 0.3;
  std::vector<Probe3> probes;
  Mms mms = Mms::None; // skb1d: the 1D manufactured solution along x (physics/mms.hpp)
  double mmsAmplitude = 1e-4;
  bool help = false;
};

/// Read and check the 3D scene (collective; bad input throws InputError with one line).
PetscErrorCode readScene3(MPI_Comm comm, Scene3 &sc);

} // namespace gimp::three
