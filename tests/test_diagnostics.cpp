// The diagnostics room's energy watch (docs/validation.md, *Unstable runs*): the balance
// kinetic + strain - external work + damping of a stable run only falls (the step dissipates),
// so it never stops one, however its energy moves between kinetic and strain or flows in as
// work; a balance that rises by more than kGain of the run's largest energy stops the run, but
// not within the first kStartSteps steps (the leapfrog's half kick) and not below the floor.
#include "gimp/diagnostics/energy_watch.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using gimp::EnergyWatch;

constexpr double kMass = 2.0, kCp = 100.0; // floor: 1e-20 * 2 * 1e4 = 2e-16 J

TEST(EnergyWatch, AStableRunNeverStops) {
  EnergyWatch w;
  for (int step = 0; step <= 5000; step += 10) {
    // Energy exchanged between kinetic and strain, work flowing in, a little dissipated.
    const double work = 1e-3 * step, phase = 0.01 * step, total = 1.0 + work;
    const double lost = 1e-6 * step, damping = 0.5 * lost;
    const double kinetic = (total - lost) * std::sin(phase) * std::sin(phase);
    const double strain = (total - lost) - kinetic - damping;
    EXPECT_FALSE(w.rose(step, kinetic, strain, work, damping, kMass, kCp)) << step;
  }
}

TEST(EnergyWatch, AGrowingBalanceStopsTheRunAtItsRow) {
  EnergyWatch w;
  int stopped = -1;
  for (int step = 0; step <= 200 && stopped < 0; step += 10) {
    const double created = step < 100 ? 0.0 : 0.1 * (step - 90); // grows from step 100
    if (w.rose(step, 0.5, 0.5 + created, 0.0, 0.0, kMass, kCp)) stopped = step;
  }
  // Scale: the largest kinetic + strain so far (1 + created); stops once created > kGain of it.
  EXPECT_EQ(stopped, 110); // created 2.0 against 0.5 * 3.0
  EXPECT_NEAR(w.gained(), 2.0, 1e-15);
  EXPECT_NEAR(w.scale(), 3.0, 1e-15);
  EXPECT_NE(w.why().find("rose by 2 J"), std::string::npos) << w.why();
}

TEST(EnergyWatch, NotDuringTheFirstStepsNorBelowTheFloor) {
  EnergyWatch early;
  EXPECT_FALSE(early.rose(0, 0.0, 1.0, 0.0, 0.0, kMass, kCp));
  EXPECT_FALSE(early.rose(EnergyWatch::kStartSteps - 1, 0.0, 9.0, 0.0, 0.0, kMass, kCp));
  EXPECT_TRUE(early.rose(EnergyWatch::kStartSteps, 0.0, 9.0, 0.0, 0.0, kMass, kCp));

  EnergyWatch atRest; // round-off of a body at rest: relative growth, absolute nothing
  EXPECT_FALSE(atRest.rose(0, 0.0, 1e-18, 0.0, 0.0, kMass, kCp));
  EXPECT_FALSE(atRest.rose(100, 0.0, 1.5e-16, 0.0, 0.0, kMass, kCp));
  EXPECT_TRUE(atRest.rose(200, 0.0, 3e-16, 0.0, 0.0, kMass, kCp));
}

} // namespace
