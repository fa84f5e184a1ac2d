// The energy balance of a run watched for growth, in 2D and 3D (docs/validation.md, *Unstable
// runs*). A run can go unstable and stay finite: damping or a stiffening material stops the
// growth, and it ends in a wrong state with every value finite. What it cannot hide is the energy
// it created: the balance kinetic + strain - external work + damping is constant for the exact
// motion, and the step's numerical dissipation only lowers it. So a rise of the balance by more
// than kGain of the largest energy the run has shown (kinetic + strain, external work, damping,
// the balance itself) stops the run, at a history row. Every scene in options/ stays below 0.02
// at its history rows; within the first steps the leapfrog start (a half kick) makes the balance
// of a suddenly loaded body rise by up to 0.25, so those are not tested. The floor, 1e-20 M c_p^2
// (the strain energy of a uniform strain of 1.4e-10), keeps round-off of a body at rest from
// counting. Fed with sums over all ranks, every rank decides the same.
#pragma once

#include <petscsys.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace gimp {

class EnergyWatch {
public:
  static constexpr double kGain = 0.5;
  static constexpr PetscInt kStartSteps = 10;
  static constexpr double kFloor = 1e-20; // of M c_p^2

  /// The energies of the history row at `step` (the first row sets the reference), with the
  /// run's total mass M and largest wave speed c_p for the floor. True when the balance rose
  /// beyond the limit: gained() and scale() then say by how much, against what.
  bool rose(PetscInt step, double kinetic, double strain, double externalWork, double damping,
            double mass, double cp) {
    const double floor = kFloor * mass * cp * cp;
    const double balance = kinetic + strain - externalWork + damping;
    if (std::isnan(ref_)) ref_ = balance;
    scale_ = std::max(
        {scale_, std::fabs(ref_), kinetic + strain, std::fabs(externalWork), std::fabs(damping)});
    gained_ = balance - ref_;
    return step >= kStartSteps && gained_ > kGain * scale_ && gained_ > floor;
  }
  double gained() const { return gained_; }
  double scale() const { return scale_; }
  /// Why the run stops, in one line (after rose() returned true).
  std::string why() const {
    char text[512];
    std::snprintf(text, sizeof(text),
                  "the energy balance (kinetic + strain - external work + damping) rose by "
                  "%.6g J, %.3g of the run's largest energy %.6g J: the run went unstable (reduce "
                  "-ts_dt or -gimp_cfl; -gimp_stability_check gives the critical step)",
                  gained_, gained_ / scale_, scale_);
    return text;
  }

private:
  double ref_ = NAN;  // the balance at the first history row of this process
  double scale_ = 0;  // the largest energy of the rows so far
  double gained_ = 0; // the last row's balance less the reference
};

} // namespace gimp
