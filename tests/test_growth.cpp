// Unit tests of the maximum hoop stress kink (mtsKink in include/gimp/cracks/growth.hpp).
//
//   1. Pure mode I: no kink. Pure mode II: -arccos(1/3) = -70.53 degrees for K_II > 0 (the
//      root of K_I sin theta + K_II (3 cos theta - 1) = 0 with K_I = 0).
//   2. Antisymmetry in K_II: theta(K_I, -K_II) = -theta(K_I, K_II); scale invariance.
//   3. At every ratio the angle is a root of the hoop stress's stationarity condition,
//      K_I sin theta + K_II (3 cos theta - 1) = 0, and the hoop stress there is a maximum.
//   4. Small K_II: no cancellation: theta = -2 K_II / K_I to first order, with full relative
//      accuracy at K_II / K_I = 1e-12.
#include "gimp/cracks/growth.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using gimp::cracks::mtsKink;

constexpr double kPi = 3.141592653589793;

double deg(double rad) {
  return rad * 180.0 / kPi;
}

/// The hoop stress at angle theta (times sqrt(2 pi r)), of the tip's K fields.
double hoop(double KI, double KII, double th) {
  const double c = std::cos(0.5 * th);
  return c * (KI * c * c - 1.5 * KII * std::sin(th));
}

TEST(MtsKink, PureModes) {
  EXPECT_EQ(mtsKink(1.0, 0.0), 0.0);
  EXPECT_EQ(mtsKink(3.7e5, 0.0), 0.0);
  EXPECT_NEAR(deg(mtsKink(0.0, 1.0)), -70.528779365509, 1e-9);
  EXPECT_NEAR(mtsKink(0.0, 2.5e6), -std::acos(1.0 / 3.0), 1e-14);
  EXPECT_NEAR(deg(mtsKink(0.0, -1.0)), 70.528779365509, 1e-9);
}

TEST(MtsKink, AntisymmetricAndScaleFree) {
  for (double r : {-3.0, -0.4, 0.01, 0.577, 1.0, 5.0, 100.0}) {
    const double a = mtsKink(1.0, r);
    EXPECT_EQ(mtsKink(1.0, -r), -a) << r;
    EXPECT_NEAR(mtsKink(2.0e5, 2.0e5 * r), a, 1e-15) << r;
    EXPECT_LT(a * r, 0.0) << "K_II > 0 kinks clockwise (negative), K_II < 0 counter-clockwise";
  }
}

TEST(MtsKink, StationaryMaximumOfTheHoopStress) {
  for (double KI : {1.0, 0.3, 0.0, -0.2}) // (a closed crack, K_I < 0, too)
    for (double KII : {-2.0, -0.5, -1e-3, 1e-3, 0.5, 1.0, 2.0}) {
      const double th = mtsKink(KI, KII);
      EXPECT_NEAR(KI * std::sin(th) + KII * (3.0 * std::cos(th) - 1.0), 0.0,
                  1e-13 * (std::fabs(KI) + std::fabs(KII)))
          << KI << " " << KII;
      const double d = 1e-4;
      EXPECT_GT(hoop(KI, KII, th), hoop(KI, KII, th + d)) << KI << " " << KII;
      EXPECT_GT(hoop(KI, KII, th), hoop(KI, KII, th - d)) << KI << " " << KII;
    }
}

TEST(MtsKink, InclinedCrackUnderTension) {
  // K_II / K_I = tan(beta) for a crack at beta to the plane normal to the load.
  EXPECT_NEAR(deg(mtsKink(std::cos(kPi / 6), std::sin(kPi / 6))), -43.2213451190, 1e-8);
  EXPECT_NEAR(deg(mtsKink(1.0, 1.0)), -53.1301023542, 1e-8);
  EXPECT_NEAR(deg(mtsKink(1.0, std::sqrt(3.0))), -60.0, 1e-9);
}

TEST(MtsKink, SmallModeIINoCancellation) {
  const double r = 1e-12;
  EXPECT_NEAR(mtsKink(1.0, r) / (-2.0 * r), 1.0, 1e-12);
}

} // namespace
