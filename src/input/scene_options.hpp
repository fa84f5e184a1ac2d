// The readers of the scene's parts (src/input only), each from the options by their declarations
// (input/options.hpp).
#pragma once

#include "gimp/input/options.hpp"
#include "gimp/input/scene.hpp"

#include <limits>
#include <string>

namespace gimp::input {

bool isPerfectSquare(int n);

/// Every gimp option given that exists in the other dimension only (or a choice of it) is
/// refused with the feature table's reason, before anything is read.
void refuseOtherDimension(int dim);

/// mu, lambda and the model's lambda* from E and nu.
void deriveMaterial(Material &m);
/// The scene's material (-gimp_material, _E, _nu, _rho; 2D: _plane, _thickness).
template <int D> void readMaterial(const Options &o, Scene<D> &sc);
/// A body's own material (-gimp_bodyK_material, _E, _nu, _rho), each the scene's unless given;
/// p is "gimp_bodyK_".
void readBodyMaterial(const Options &o, const std::string &p, const Material &scene, bool sceneE,
                      bool sceneRho, Material &m);

/// The bodies: plane bodies (bodies_plane.cpp) or solids (bodies_solid.cpp).
void readBodies(const Options &o, Scene<2> &sc);
void readBodies(const Options &o, Scene<3> &sc);
/// Bodies do not overlap (2D: from their shapes) and lie in the domain; the manufactured
/// solution fits the material.
void checkBodies(const Scene<2> &sc);
void checkBodies(const Scene<3> &sc);
/// The default domain: the bodies' bounding box padded by -gimp_pad cells, whole cells from its
/// low corner (2D) or on the grid lines through the origin (3D).
void domainAroundBodies(Scene<2> &sc);
void domainAroundBodies(Scene<3> &sc);
/// A body of shape file (bodies_file.cpp; q is "gimp_bodyK_", `file` its -gimp_bodyK_file): its
/// particles read into `out` (2D: V over `thickness`), and the bounding box of their domains.
template <int D>
BoxOf<D> readFileBody(const Options &o, const std::string &q, double thickness, std::string &file,
                      ParticleFile<D> &out);
/// Every particle of body k's file inside the grid domain (seeding places each on the rank that
/// owns its point; none may be lost) and none larger than a level-0 cell.
template <int D> void checkFileParticles(const Scene<D> &sc, size_t k);
/// -gimp_hole_measure and its load (in 3D the hole is a cylinder along z).
void readHoleMeasure(const Options &o, Measures &sc);

/// Body force, tractions, penalty conditions, node constraints and probes (loads.cpp).
template <int D> void readLoads(const Options &o, Scene<D> &sc);

/// After the levels and bodies (scene_cracks.cpp): -gimp_cracks and each -gimp_crackK_points,
/// checked; each end classified as a tip (strictly inside a body) or a mouth.
void readCracks(const Options &o, Scene<2> &sc);
/// The same in 3D (scene_cracks3d.cpp): -gimp_crackK_polygon or _disk, each polygon checked,
/// each edge classified as a front (inside a body) or a mouth (on or outside its surface).
void readCracks(const Options &o, Scene<3> &sc);
/// After the cracks (crack_domains.cpp): the J-integral's domain at each tip, sc.jDomain, from
/// -gimp_crack_j_radius (radiusGiven) or the default; refused, clipped or left out as
/// docs/method.md's *Crack tips* says.
void setJDomains(Scene<2> &sc, bool radiusGiven);

/// A crack tip's or front point's clearance, the distance to the nearest thing its domain may not
/// reach, and what that is.
struct Clearance {
  double d = std::numeric_limits<double>::infinity();
  std::string what;
  void take(double v, const std::string &w) {
    if (v < d) {
      d = v;
      what = w;
    }
  }
};

/// The crack growth options both dimensions share (scene_cracks.cpp): the criterion and the
/// check interval into m, the increment and length asked for; refuses growth options without
/// cracks or growth, and a toughness without growth.
struct GrowthAsked {
  bool grows = false, stepGiven = false, lengthGiven = false;
  double step = 0, length = 0;
};
GrowthAsked readGrowthOptions(const Options &o, Measures &m, size_t bodies, PetscInt nc);

/// Where a crack grows (a 2D tip, a 3D front point) and the words for its measure's domain:
/// refuseGrowthAt refuses growth where no domain fits (R <= 0) and a step past its radius R.
struct GrowthPlace {
  std::string at;                             // "the tip x,y of crack K", "front point ..."
  const char *domain, *radius, *near, *needs; // "J domain", "J radius", "an edge or crack", ...
};
void refuseGrowthAt(const GrowthPlace &p, double R, double step);

/// After the 3D cracks (front_domains.cpp): the tube of the front integrals at each front point,
/// sc.jDomain in measureFronts' order (crack, then front point), from -gimp_crack_j_radius (given
/// or not) against each point's clearance; refuses a given radius that fits no tube.
void setFrontDomains(Scene<3> &sc, bool radiusGiven, bool quiet = false);

} // namespace gimp::input
