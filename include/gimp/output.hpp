// Run output (DESIGN.md contract): HDF5 particle and grid fields with XDMF for ParaView,
// history.csv (time series) and summary.json, all in the scene's output directory.
#pragma once

#include "gimp/petsc_compat.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace gimp {

class Simulation;

class Output {
public:
  explicit Output(Simulation &sim) : sim_(sim) {}
  ~Output();
  Output(const Output &) = delete;
  Output &operator=(const Output &) = delete;

  PetscErrorCode open();
  PetscErrorCode writeHistory(PetscInt step, double t);
  PetscErrorCode writeFields(PetscInt step, double t);
  PetscErrorCode writeSummary(PetscInt steps, double t, double wall);

private:
  PetscErrorCode writeXdmf() const;

  Simulation &sim_;
  std::string dir_;
  FILE *history_ = nullptr;
  struct Frame {
    PetscInt step;
    double t;
    long long particles;
  };
  std::vector<Frame> frames_;
};

} // namespace gimp
