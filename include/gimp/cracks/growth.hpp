// Crack growth (-gimp_crack_growth mts; docs/method.md, *Crack growth*): the maximum hoop stress
// direction from K_I and K_II, and one growth check of every 2D tip or 3D front from its measures.
#pragma once

#include "gimp/cracks/fields.hpp"
#include "gimp/cracks/front.hpp"
#include "gimp/cracks/tips.hpp"
#include "gimp/input/scene.hpp"

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace gimp::cracks {

/// The kink angle [rad] of the maximum hoop stress criterion in the tip frame (t along the last
/// segment toward the tip, n its left normal; counter-clockwise positive):
/// theta = 2 atan[(K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)], 0 when K_II = 0, evaluated without
/// cancellation: 2 atan[-2 K_II / (K_I + sqrt(K_I^2 + 8 K_II^2))] when K_I >= 0. Pure mode II
/// gives -70.53 degrees for K_II > 0; theta(K_I, -K_II) = -theta(K_I, K_II).
double mtsKink(double KI, double KII);

/// The twist angle [rad] about the direction ahead of the plane of largest principal stress at
/// a 3D front under K_I and K_III: psi = atan[2 K_III / ((1 - 2 nu) K_I)] / 2, 0 when K_III = 0.
double twistAngle(double KI, double KIII, double nu);

/// The largest kink (mtsKink) or twist (twistAngle) with which a 3D front point grows in its
/// crack's plane [rad]: 5 degrees. A point that would turn more stops its crack's growth.
constexpr double kPlanarGrowthAngle = 5.0 * M_PI / 180.0;

/// One increment of one 2D tip or one 3D front point.
struct GrowthRecord {
  double t = 0;            // the time of the check [s]
  int crack = 0, end = 0;  // the crack and its end (2D: 0 first point, 1 last; 3D: front point)
  double x[3] = {0, 0, 0}; // the new tip, or the front point advanced [m]
  double G = 0, KI = 0, KII = 0; // the measures that grew it: G [J/m^2], K [Pa m^0.5] (2D: by J)
  double KIII = 0;               // 3D
  double kink = 0; // 2D: the new segment's angle from the previous one [deg], counter-clockwise
                   // positive in the tip frame; 3D: the maximum hoop stress kink (within
                   // kPlanarGrowthAngle: the front grows in the crack's plane)
};

/// One growth check at time t with every tip's measures (measureTips: the same on every rank):
/// each tip whose G_J reaches the toughness of the material at it grows by its increment
/// (Scene::tipGrowth) at the kink mtsKink(KI_J, KII_J); the polyline gains the point at that end.
/// An increment that would take the tip past its growth length, out of its body, or within a
/// cell of another crack or across its own stops that tip for the rest of the run; `stops` gets a
/// line for each. Returns the increments taken, in the order of the tips. The J domains are not
/// updated here (updateJDomains).
std::vector<GrowthRecord> growTips(Scene<2> &sc, const std::vector<TipMeasure> &tips, double t,
                                   std::vector<std::string> &stops);

/// The increments of 2D tips still being released at time t (-gimp_crack_growth_release: grown
/// at a check t0 with t - t0 < release), each with its segment from the tip before it (the
/// polyline's point next to the record's, toward the crack) to the new tip. Empty without a
/// release time.
std::vector<Release<2>> releasing(const Scene<2> &sc, const std::vector<GrowthRecord> &grown,
                                  double t);

/// The advances of 3D fronts still being released at time t (grown at a check t0 with t - t0 <
/// release), each with its crack's polygon before it (FrontGrowth::opening). Empty without a
/// release time.
std::vector<Release<3>> releasing(const Scene<3> &sc, double t);

/// The vertices of 3D crack c after its front advanced: each front edge cut into the pieces of
/// frontPoints(c, spacing), piece j moved by advance[j] along its ahead direction (a vertex
/// between two pieces by their mean along chain::vertexAhead, so that equal advances move every
/// piece by exactly that much); where the front meets a mouth, the mouth edge's far vertex is
/// carried along too (the crack keeps reaching past the body's surface) and mouth vertices
/// between collinear mouth edges are dropped; so are front vertices between two front edges that
/// would leave an edge shorter than a quarter of the largest advance or fold the front back (a
/// turn over 120 degrees). The front flags of the new edges go to `front` when given (for the
/// scene to set again: classifyCrackEdges).
std::vector<std::array<double, 3>> advanceFront(const CrackSurface &c, double spacing,
                                                const std::vector<double> &advance,
                                                std::vector<char> *front = nullptr);

/// A convex planar polygon in c's plane holding every point of the plane within 1.25 `length` of
/// c's front (and c itself): where the front may go when its points grow at most `length` (a
/// vertex where the front meets a mouth moves up to 1.08 times as far; its nodes get second fields
/// at setup: Grid::crackReserveSurfaces).
CrackSurface growthReach(const CrackSurface &c, double length);

/// One growth check of the 3D cracks at time t with every front point's measures (measureFronts:
/// the same on every rank, in its order): the front points of a crack whose G reaches the
/// toughness of the material there advance by its increment in the crack's plane (advanceFront);
/// the vertices where the front meets a mouth are put back on the bodies' surface along their
/// front edge's line, and the polygon's edges are classified again. A crack stops growing for the
/// rest of the run, with a line in `stops`, when a growing point would kink or twist by more than
/// kPlanarGrowthAngle, a point has no measure, or the new polygon would cross itself, reach farther
/// than the growth length from the crack as given, meet another crack or keep no front. Returns the
/// increments taken, one per front point advanced. With a release time, each advance keeps the
/// polygon before it (FrontGrowth::opening, those older than the release dropped). The front
/// domains are not updated here (updateFrontDomains).
std::vector<GrowthRecord> growFronts(Scene<3> &sc, const std::vector<FrontMeasure> &front, double t,
                                     std::vector<std::string> &stops);

} // namespace gimp::cracks
