// Crack growth in 2D (-gimp_crack_growth mts; docs/method.md, *Crack growth*): the maximum hoop
// stress direction from K_I and K_II, and one growth check of every tip from its measures.
#pragma once

#include "gimp/cracks/tips.hpp"
#include "gimp/input/scene.hpp"

#include <string>
#include <vector>

namespace gimp::cracks {

/// The kink angle [rad] of the maximum hoop stress criterion in the tip frame (t along the last
/// segment toward the tip, n its left normal; counter-clockwise positive):
/// theta = 2 atan[(K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)], 0 when K_II = 0, evaluated without
/// cancellation: 2 atan[-2 K_II / (K_I + sqrt(K_I^2 + 8 K_II^2))] when K_I >= 0. Pure mode II
/// gives -70.53 degrees for K_II > 0; theta(K_I, -K_II) = -theta(K_I, K_II).
double mtsKink(double KI, double KII);

/// One increment of one tip.
struct GrowthRecord {
  double t = 0;                  // the time of the check [s]
  int crack = 0, end = 0;        // the crack and its end (0 first point, 1 last)
  double x[2] = {0, 0};          // the new tip [m]
  double G = 0, KI = 0, KII = 0; // the measures that grew it: G by J [J/m^2], K by J [Pa m^0.5]
  double kink = 0; // the new segment's angle from the previous one [deg], counter-clockwise
                   // positive in the tip frame
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

} // namespace gimp::cracks
