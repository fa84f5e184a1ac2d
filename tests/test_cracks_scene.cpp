// The cracks of a scene as readScene makes them (src/input/scene_cracks.cpp): the points in
// order, each end a tip (strictly inside a body) or a mouth (on or outside the body's edge,
// including a hole's circle, within 1e-9 of the cell size), and the one-cell distance between
// a tip and another crack measured with the finest cell at the tip; the J domain of each tip
// clipped to its clearance; crack growth (cracks::growTips): each tip's increment and length, the
// new point at the end that grew, kinked by the maximum hoop stress angle in the tip frame, no
// growth below the toughness or without J, a tip that stops at its growth length, and the J
// domain after growth not clipped by the grown kink. The error lines themselves are checked by
// tests/check_input.py and tests/bad_input/cases2d.tsv.
#include "gimp/cracks/growth.hpp"
#include "gimp/input/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

const char *const kBase = "-gimp_E 1e7 -gimp_rho 1000 -gimp_h 0.1 -gimp_body0_box 0,0,1,0.4 "
                          "-gimp_body0_holes 0.8,0.2,0.05 ";

/// readScene on the base scene plus `extra`; the InputError's text, or "" when it succeeds.
std::string read(const std::string &extra, gimp::Scene<2> &sc) {
  if (PetscOptionsClear(nullptr)) return "PetscOptionsClear failed";
  if (PetscOptionsInsertString(nullptr, (kBase + extra).c_str())) return "bad options string";
  try {
    if (gimp::readScene<2>(PETSC_COMM_WORLD, sc)) return "PETSc error";
  } catch (const gimp::InputError &e) {
    return e.what();
  }
  return "";
}

/// The tip flags of crack 0 with the given points.
std::pair<bool, bool> tips(const std::string &points) {
  gimp::Scene<2> sc;
  const std::string err = read("-gimp_cracks 1 -gimp_crack0_points " + points, sc);
  EXPECT_EQ(err, "") << points;
  if (!err.empty() || sc.cracks.size() != 1) return {false, false};
  return {sc.cracks[0].tip[0], sc.cracks[0].tip[1]};
}

TEST(CrackScene, PointsInOrder) {
  gimp::Scene<2> sc;
  ASSERT_EQ(read("-gimp_cracks 2 -gimp_crack0_points -0.1,0.2,0.3,0.2,0.4,0.25 "
                 "-gimp_crack1_points 0.6,0.05,0.6,0.35",
                 sc),
            "");
  ASSERT_EQ(sc.cracks.size(), 2u);
  ASSERT_EQ(sc.cracks[0].points.size(), 3u);
  EXPECT_EQ(sc.cracks[0].points[1][0], 0.3);
  EXPECT_EQ(sc.cracks[0].points[2][1], 0.25);
  EXPECT_EQ(sc.cracks[1].points.size(), 2u);
  gimp::Scene<2> none;
  ASSERT_EQ(read("", none), "");
  EXPECT_TRUE(none.cracks.empty()); // -gimp_cracks defaults to 0
}

TEST(CrackScene, TipsAndMouths) {
  using P = std::pair<bool, bool>;
  EXPECT_EQ(tips("-0.1,0.2,0.5,0.2"), P(false, true));        // outside -> inside
  EXPECT_EQ(tips("0.5,0.2,0.2,0.2"), P(true, true));          // wholly inside
  EXPECT_EQ(tips("0,0.2,0.5,0.2"), P(false, true));           // on the left edge
  EXPECT_EQ(tips("1e-12,0.2,0.5,0.2"), P(false, true));       // within 1e-9 h of the edge
  EXPECT_EQ(tips("1e-6,0.2,0.5,0.2"), P(true, true));         // inside by more
  EXPECT_EQ(tips("0.3,0.4,0.3,0.1"), P(false, true));         // on the top edge
  EXPECT_EQ(tips("0,0.2,1,0.2"), P(false, false));            // through the body
  EXPECT_EQ(tips("0.5,0.2,0.75,0.2"), P(true, false));        // on the hole's circle
  EXPECT_EQ(tips("0.5,0.2,0.8,0.2"), P(true, false));         // into the hole
  EXPECT_EQ(tips("0.5,0.2,0.749999,0.2"), P(true, true));     // just short of the hole
  EXPECT_EQ(tips("0.5,0.2,0.5,0.3,0.6,0.5"), P(true, false)); // kinked, out through the top
}

TEST(CrackScene, TipDistanceUsesTheFinestCellThere) {
  // Tip (0.5, 0.2), the other crack 0.07 away: under one cell of h = 0.1, over one of 0.05.
  const std::string two = "-gimp_cracks 2 -gimp_crack0_points -0.1,0.2,0.5,0.2 "
                          "-gimp_crack1_points 0.57,-0.1,0.57,0.5 ";
  gimp::Scene<2> coarse, fine, elsewhere;
  EXPECT_NE(read(two, coarse).find("less than one cell (0.1 m)"), std::string::npos);
  EXPECT_EQ(read(two + "-gimp_levels 2 -gimp_level1_box 0.4,0.1,0.7,0.3", fine), "");
  EXPECT_NE(read(two + "-gimp_levels 2 -gimp_level1_box 0.7,0.1,0.9,0.3", elsewhere)
                .find("-gimp_crack0_points"),
            std::string::npos);
  // A mouth may come close to another crack: crack 1 starts 0.01 from crack 0, outside.
  gimp::Scene<2> mouth;
  EXPECT_EQ(read("-gimp_cracks 2 -gimp_crack0_points -0.1,0.2,0.5,0.2 "
                 "-gimp_crack1_points -0.1,0.21,0.3,0.35",
                 mouth),
            "");
}

/// The J domain of each tip of the base scene with a finer level around y = 0.2 and `extra`.
std::vector<gimp::JDomain> domains(const std::string &extra) {
  gimp::Scene<2> sc;
  const std::string err =
      read("-gimp_levels 2 -gimp_level1_box 0.2,0.1,0.7,0.3 -gimp_level1_ratio 4 " + extra, sc);
  EXPECT_EQ(err, "") << extra;
  return sc.jDomain;
}

TEST(CrackScene, JDomainClippedToTheTipsClearance) {
  const double h = 0.1 / 4;
  // The default, 5 cells at the tip, inside the clearance (0.2 to the top and bottom edges).
  auto d = domains("-gimp_cracks 1 -gimp_crack0_points -0.1,0.2,0.45,0.2");
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].radius, gimp::kJCells * h);
  EXPECT_FALSE(d[0].clipped);
  // A radius given past the clearance: to the other tip of an interior crack (0.15) ...
  d = domains("-gimp_crack_j_radius 0.3 -gimp_cracks 1 -gimp_crack0_points 0.3,0.2,0.45,0.2");
  ASSERT_EQ(d.size(), 2u);
  EXPECT_NEAR(d[0].radius, 0.15, 1e-12);
  EXPECT_NEAR(d[1].radius, 0.15, 1e-12);
  EXPECT_TRUE(d[0].clipped && d[1].clipped);
  // ... to the kink of its own crack (the last segment, 0.05 sqrt 2) ...
  d = domains("-gimp_crack_j_radius 0.3 -gimp_cracks 1 -gimp_crack0_points "
              "-0.1,0.2,0.5,0.2,0.55,0.25");
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NEAR(d[0].radius, 0.05 * std::sqrt(2.0), 1e-12);
  // (a vertex where the crack runs straight on is no kink: to the top and bottom edges, 0.2) ...
  d = domains("-gimp_crack_j_radius 0.3 -gimp_cracks 1 -gimp_crack0_points "
              "-0.1,0.2,0.3,0.2,0.45,0.2");
  EXPECT_NEAR(d.at(0).radius, 0.2, 1e-12);
  // ... to a hole's circle (centre 0.8, radius 0.05) ...
  d = domains("-gimp_crack_j_radius 0.3 -gimp_cracks 1 -gimp_crack0_points -0.1,0.2,0.68,0.2");
  EXPECT_NEAR(d.at(0).radius, 0.07, 1e-12);
  // ... to another crack; a radius within the clearance is kept.
  d = domains("-gimp_crack_j_radius 0.3 -gimp_cracks 2 -gimp_crack0_points -0.1,0.2,0.45,0.2 "
              "-gimp_crack1_points 0.6,-0.1,0.6,0.5");
  EXPECT_NEAR(d.at(0).radius, 0.15, 1e-12);
  d = domains("-gimp_crack_j_radius 0.1 -gimp_cracks 1 -gimp_crack0_points -0.1,0.2,0.45,0.2");
  EXPECT_EQ(d.at(0).radius, 0.1);
  EXPECT_FALSE(d.at(0).clipped);
  // The default where the tip is under 2 cells (0.1 here) from the top edge: no domain (J not
  // measured).
  d = domains("-gimp_cracks 1 -gimp_crack0_points -0.1,0.39,0.45,0.39");
  EXPECT_EQ(d.at(0).radius, 0.0);
}

/// A tip measure of tip q of sc with G_J, K_I and K_II by J.
gimp::cracks::TipMeasure measure(const gimp::Scene<2> &sc, size_t q, double G, double KI,
                                 double KII) {
  gimp::cracks::TipMeasure m = gimp::cracks::tipsOf(sc).at(q);
  m.G_J = G;
  m.KI_J = KI;
  m.KII_J = KII;
  return m;
}

TEST(CrackScene, GrowthIncrements) {
  gimp::Scene<2> sc;
  // An interior crack along y = 0.2 with two tips; cell 0.05, J radius 0.2 (the top and bottom
  // edges are 0.2 away).
  ASSERT_EQ(read("-gimp_h 0.05 -gimp_cracks 1 -gimp_crack0_points 0.3,0.2,0.5,0.2 "
                 "-gimp_crack_growth mts -gimp_Gc 2",
                 sc),
            "");
  ASSERT_EQ(sc.tipGrowth.size(), 2u);
  EXPECT_EQ(sc.tipGrowth[0].end, 0);
  EXPECT_EQ(sc.tipGrowth[1].end, 1);
  EXPECT_NEAR(sc.tipGrowth[0].step, 0.05, 1e-15);  // one cell at the tip
  EXPECT_NEAR(sc.tipGrowth[0].length, 1.0, 1e-14); // 20 increments
  EXPECT_EQ(sc.growthInterval, 10);
  const double th = gimp::cracks::mtsKink(1.0, 0.5), c = std::cos(th), s = std::sin(th);
  std::vector<std::string> stops;
  // Tip 0 below the toughness, tip 1 at it with K_II / K_I = 0.5: only tip 1 grows.
  auto grown = gimp::cracks::growTips(
      sc, {measure(sc, 0, 1.99, 1.0, 0.0), measure(sc, 1, 2.0, 1.0, 0.5)}, 1e-3, stops);
  ASSERT_EQ(grown.size(), 1u);
  EXPECT_TRUE(stops.empty());
  // At end 1 the tip frame is t = (1, 0), n = (0, 1): the new point is tip + 0.05 (cos, sin).
  ASSERT_EQ(sc.cracks[0].points.size(), 3u);
  EXPECT_NEAR(sc.cracks[0].points[2][0], 0.5 + 0.05 * c, 1e-15);
  EXPECT_NEAR(sc.cracks[0].points[2][1], 0.2 + 0.05 * s, 1e-15);
  EXPECT_EQ(sc.cracks[0].grown[1], 1);
  EXPECT_EQ(grown[0].end, 1);
  EXPECT_EQ(grown[0].t, 1e-3);
  EXPECT_NEAR(grown[0].kink, th * 180.0 / 3.141592653589793, 1e-12);
  EXPECT_LT(grown[0].kink, 0.0); // K_II > 0: clockwise
  // Tip 0 with the same K: at end 0 the frame is t = (-1, 0), n = (0, -1), so a clockwise kink
  // turns the crack toward +y there (the tip frame turned by 180 degrees).
  grown = gimp::cracks::growTips(
      sc, {measure(sc, 0, 2.5, 1.0, 0.5), measure(sc, 1, std::nan(""), 1.0, 0.0)}, 2e-3, stops);
  ASSERT_EQ(grown.size(), 1u); // (G_J null at tip 1: no growth)
  ASSERT_EQ(sc.cracks[0].points.size(), 4u);
  EXPECT_NEAR(sc.cracks[0].points[0][0], 0.3 - 0.05 * c, 1e-15);
  EXPECT_NEAR(sc.cracks[0].points[0][1], 0.2 - 0.05 * s, 1e-15);
  EXPECT_EQ(sc.cracks[0].grown[0], 1);
  // The J domains after growth: the grown kinks, one increment (under 2 cells) behind each tip,
  // do not clip them; the nearest edge does (the bottom one for tip 1, the top for tip 0).
  gimp::updateJDomains(sc);
  ASSERT_EQ(sc.jDomain.size(), 2u);
  EXPECT_NEAR(sc.jDomain[0].radius, 0.2 + 0.05 * s, 1e-12);
  EXPECT_NEAR(sc.jDomain[1].radius, 0.2 + 0.05 * s, 1e-12);
  EXPECT_TRUE(sc.jDomain[0].clipped && sc.jDomain[1].clipped);
}

TEST(CrackScene, RoundOffModeIIGrowsStraight) {
  // K_II at the round-off of the interaction integrals' sums (1e-11 of K_I on a mode-I tip) does
  // not kink the crack: the new tip stays on the crack's line exactly, so a tip on a line of nodes
  // does not drift off it increment by increment. Just above 1e-8 of K_I the kink is applied.
  gimp::Scene<2> sc;
  ASSERT_EQ(read("-gimp_h 0.05 -gimp_cracks 1 -gimp_crack0_points 0.3,0.2,0.5,0.2 "
                 "-gimp_crack_growth mts -gimp_Gc 2",
                 sc),
            "");
  std::vector<std::string> stops;
  auto grown = gimp::cracks::growTips(
      sc, {measure(sc, 0, 1.0, 1.0, 0.0), measure(sc, 1, 2.0, 4.7e4, -2.8e-7)}, 1e-3, stops);
  ASSERT_EQ(grown.size(), 1u);
  EXPECT_EQ(sc.cracks[0].points.back()[1], 0.2);
  EXPECT_EQ(grown[0].kink, 0.0);
  EXPECT_EQ(grown[0].KII, -2.8e-7); // (recorded as measured)
  grown = gimp::cracks::growTips(
      sc, {measure(sc, 0, 1.0, 1.0, 0.0), measure(sc, 1, 2.0, 1.0, -1.1e-8)}, 2e-3, stops);
  ASSERT_EQ(grown.size(), 1u);
  EXPECT_GT(sc.cracks[0].points.back()[1], 0.2); // K_II < 0: counter-clockwise, toward +y
  EXPECT_NEAR(grown[0].kink, gimp::cracks::mtsKink(1.0, -1.1e-8) * 180.0 / 3.141592653589793,
              1e-20);
}

TEST(CrackScene, GrowthStopsAtItsLength) {
  gimp::Scene<2> sc;
  ASSERT_EQ(read("-gimp_cracks 1 -gimp_crack0_points -0.1,0.2,0.5,0.2 -gimp_crack_growth mts "
                 "-gimp_Gc 2 -gimp_crack_growth_step 0.05 -gimp_crack_growth_length 0.1",
                 sc),
            "");
  ASSERT_EQ(sc.tipGrowth.size(), 1u); // (end 0 is a mouth)
  std::vector<std::string> stops;
  for (int k = 0; k < 2; ++k)
    EXPECT_EQ(gimp::cracks::growTips(sc, {measure(sc, 0, 3.0, 1.0, 0.0)}, k, stops).size(), 1u);
  EXPECT_NEAR(sc.cracks[0].points.back()[0], 0.6, 1e-15); // straight on: no K_II
  EXPECT_EQ(sc.cracks[0].points.back()[1], 0.2);
  EXPECT_TRUE(gimp::cracks::growTips(sc, {measure(sc, 0, 3.0, 1.0, 0.0)}, 2, stops).empty());
  ASSERT_EQ(stops.size(), 1u);
  EXPECT_NE(stops[0].find("it has grown its growth length 0.1 m"), std::string::npos) << stops[0];
  EXPECT_TRUE(sc.tipGrowth[0].stopped);
  EXPECT_TRUE(gimp::cracks::growTips(sc, {measure(sc, 0, 3.0, 1.0, 0.0)}, 3, stops).empty());
  EXPECT_EQ(stops.size(), 1u); // stopped for good: said once
}

} // namespace
