// Setting up a run: scene, grid, particles, nodal vectors, time stepper, output.
#include "gimp/input/validate.hpp"
#include "gimp/particles/seed.hpp"
#include "gimp/physics/constraints.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/physics/mms.hpp"
#include "gimp/solver/solver.hpp"

namespace gimp {

Solver::Solver(MPI_Comm comm) : comm_(comm) {}

Solver::~Solver() {
  if (ts_) (void)TSDestroy(&ts_);
  if (sw_) (void)DMDestroy(&sw_);
}

PetscErrorCode Solver::setup() {
  PetscCall(PetscTime(&wall0_));
  PetscCallMPI(MPI_Comm_rank(comm_, &rank_));
  PetscCallMPI(MPI_Comm_size(comm_, &size_));
  PetscCall(PetscLogStageRegister("P2G", &stages_.p2g));
  PetscCall(PetscLogStageRegister("Forces", &stages_.forces));
  PetscCall(PetscLogStageRegister("Grid update", &stages_.grid));
  PetscCall(PetscLogStageRegister("G2P", &stages_.g2p));
  PetscCall(PetscLogStageRegister("Stress", &stages_.stress));
  PetscCall(PetscLogStageRegister("Output", &stages_.output));

  PetscCall(readSceneOneLine(comm_, sc_));
  if (sc_.help) { // list the time stepper's options too, then stop
    PetscCall(TSCreate(comm_, &ts_));
    PetscCall(TSSetFromOptions(ts_));
    return PETSC_SUCCESS;
  }
  checkSceneCombinations(sc_);
  scheme_ = schemeFor(sc_.update);
  PetscCall(grid_.create(comm_, sc_));
  if (!sc_.gridDump.empty()) {
    std::FILE *f = rank_ == 0 ? std::fopen(sc_.gridDump.c_str(), "w") : nullptr;
    PetscCall(agree(comm_, rank_ == 0 && !f ? "option -gimp_grid_dump " + sc_.gridDump +
                                                  ": cannot open the file for writing"
                                            : std::string()));
    if (f) {
      std::fputs(grid_.activeNodesCsv().c_str(), f);
      std::fclose(f);
    }
  }
  PetscCall(createParticles());
  PetscCall(nodal_.create(grid_,
                          !sc_.tractions.empty() || !sc_.dbcs.empty() || sc_.gravity[0] != 0 ||
                              sc_.gravity[1] != 0 || sc_.mms != Mms::None,
                          !sc_.cracks.empty()));
  contact_.setup(grid_, sc_.cracks);
  PetscCall(physics::nodeConstraints(sc_, grid_, nodal_.bcMask));
  PetscCall(findProbes(comm_, sc_, sw_, probeIds_));
  PetscCall(createTimeStepper());
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts_, &dt));
  PetscCall(boundary_.setup(comm_, sc_, grid_, dt));
  PetscCall(rejectUnusedOptions());
  out_ = std::make_unique<Output>(comm_, sc_, grid_);
  if (sc_.restart.empty()) {
    PetscCall(out_->open());
  } else {
    Output::Resume resume;
    PetscCall(loadCheckpoint(resume));
    PetscCall(out_->open(&resume));
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::createParticles() {
  PetscCall(createSwarm(comm_, sc_.tracking == Tracking::Corners, &sw_));
  PetscCall(seedParticles(sc_, grid_, sw_));
  ParticleView p;
  PetscCall(p.get(sw_));
  PetscCall(checkSeeding(comm_, sc_, grid_, p, nParticles_, meanParticleMass_));
  if (sc_.mms == Mms::Skb1d) { // start displaced and pre-stressed, at rest
    const mms::Skb1d ex(sc_);
    for (PetscInt k = 0; k < p.n; ++k) {
      const double X = p.X0[2 * k];
      const double F = ex.F(X, 0.0);
      p.x[2 * k] = X + ex.u(X, 0.0);
      p.v[2 * k] = p.v[2 * k + 1] = 0.0;
      p.F[4 * k] = F;
      p.V[k] = F * p.V0[k];
      p.l[2 * k] = F * p.l0[2 * k];
      if (p.hasCorners)
        for (int q = 0; q < 4; ++q)
          p.corners[8 * k + 2 * q] += ex.u(p.corners[8 * k + 2 * q], 0.0);
    }
  }
  if (sc_.material.model == MaterialModel::NeoHookean)
    for (PetscInt k = 0; k < p.n; ++k)
      material::neoHookeanStress(sc_.material, tensorAt<2>(p.F, k), tensorAt<2>(p.s, k), p.szz[k]);
  PetscCall(p.restore(sw_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::createTimeStepper() {
  // TS euler on the nodal momentum; the steps are driven by run(), one TSStep per step().
  PetscCall(TSCreate(comm_, &ts_));
  PetscCall(TSSetDM(ts_, grid_.dm));
  PetscCall(TSSetType(ts_, TSEULER));
  PetscCall(TSSetProblemType(ts_, TS_NONLINEAR));
  PetscCall(TSSetApplicationContext(ts_, this));
  PetscCall(TSSetRHSFunction(ts_, nullptr, &Solver::rhs, this));
  PetscCall(TSSetTimeStep(ts_, sc_.cfl * (grid_.hMin() / sc_.material.waveSpeed())));
  PetscCall(TSSetMaxSteps(ts_, 1000));
  PetscCall(TSSetMaxTime(ts_, 1e300));
  PetscCall(TSSetExactFinalTime(ts_, TS_EXACTFINALTIME_STEPOVER));
  PetscCall(timeStepFromOptions(ts_, sc_, grid_));
  PetscCall(TSSetSolution(ts_, nodal_.P));
  PetscCall(TSSetUp(ts_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::rhs(TS ts, PetscReal, Vec X, Vec F, void *ctx) {
  // F = kick * mask * (f - d p): the forces of this step (computed by the forces phase), the
  // damping of Eq. 16, no force on constrained or empty nodes.
  const Solver *s = static_cast<const Solver *>(ctx);
  StepClock c;
  PetscCall(clockOf(ts, s->sc_, c));
  PetscCall(VecCopy(s->nodal_.f, F));
  if (s->sc_.damping > 0) PetscCall(VecAXPY(F, -s->sc_.damping, X));
  PetscCall(VecPointwiseMult(F, F, s->nodal_.mask));
  if (c.kick != 1.0) PetscCall(VecScale(F, c.kick));
  PetscCall(VecCopy(F, s->nodal_.rhs));
  return PETSC_SUCCESS;
}

} // namespace gimp
