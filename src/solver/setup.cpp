// Setting up a run: scene, grid, particles, nodal vectors, time stepper, output.
#include "gimp/input/problem_size.hpp"
#include "gimp/input/validate.hpp"
#include "gimp/particles/seed.hpp"
#include "gimp/physics/constraints.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/physics/mms.hpp"
#include "gimp/solver/solver.hpp"
#include "gimp/transfer/lanes2.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace gimp {

namespace {

/// What a particle and a grid node cost: the swarm's fields and a stencil of up to 16 nodes
/// per particle; per node, the global and window Vecs of Nodal and TS's work vectors (about
/// 24 Vecs of 2 components) with their index sets.
ItemBytes itemBytes(const Scene<2> &sc) {
  constexpr double kStencilNodes = 16, kNodeVecs = 24, kDof = 2;
  ItemBytes b;
  const OptionalFields optional = optionalFieldsOf(sc);
  for (const FieldSpec<2> &f : particleFields<2>())
    if (optional.has(f.need))
      b.particle +=
          static_cast<double>(f.components) * (f.type == PETSC_INT ? sizeof(PetscInt) : 8);
  b.particle += kStencilNodes * (sizeof(PetscInt) + 2 * kDim * sizeof(double));
  b.node = kNodeVecs * kDof * sizeof(PetscScalar) + 4 * sizeof(PetscInt);
  return b;
}

} // namespace

Solver::Solver(MPI_Comm comm) : comm_(comm) {}

Solver::~Solver() {
  if (ts_) (void)TSDestroy(&ts_);
  if (sw_) (void)DMDestroy(&sw_);
}

PetscErrorCode Solver::setup() {
  PetscCall(PetscTime(&wall0_));
  PetscCallMPI(MPI_Comm_rank(comm_, &rank_));
  PetscCallMPI(MPI_Comm_size(comm_, &size_));
  PetscCall(stages_.registerAll());

  PetscCall(readSceneOneLine(comm_, sc_));
  if (sc_.help) { // list the time stepper's options too, then stop
    PetscCall(TSCreate(comm_, &ts_));
    PetscCall(TSSetFromOptions(ts_));
    return PETSC_SUCCESS;
  }
  checkSceneCombinations(sc_);
  PetscCall(checkProblemSize(comm_, sc_, itemBytes(sc_)));
  scheme_ = schemeFor(sc_.update);
  lanes_ = sc_.lanes && transfer::lanes2::available();
  PetscCall(
      PetscInfo(nullptr, "2D block kernels in lanes of four particles: %s\n",
                lanes_ ? "yes" : (sc_.lanes ? "no (no AVX2 here)" : "no (-gimp_lanes false)")));
  PetscCall(grid_.create(comm_, sc_));
  sc_.idSlots = bodyIdSlots<2>(grid_);
  if (!sc_.gridDump.empty()) PetscCall(writeGridDump());
  PetscCall(createParticles());
  PetscCall(nodal_.create(grid_,
                          !sc_.tractions.empty() || !sc_.dbcs.empty() || sc_.gravity[0] != 0 ||
                              sc_.gravity[1] != 0 || sc_.mms != Mms::None,
                          !sc_.cracks.empty(), sc_.transfer == Transfer::Xpic));
  contact_.setup(grid_, sc_.cracks);
  PetscCall(physics::nodeConstraints(sc_, grid_, nodal_.bcMask));
  PetscCall(findProbes(comm_, sc_, sw_, probeIds_));
  PetscCall(createTimeStepper());
  if (sc_.multirate) {
    // Reports, checkpoints and the step limit act at coarse-step ends (R fine steps).
    PetscInt maxSteps = 0;
    PetscBool given = PETSC_FALSE;
    PetscCall(TSGetMaxSteps(ts_, &maxSteps));
    PetscCall(PetscOptionsHasName(nullptr, nullptr, "-ts_max_steps", &given));
    if (!given && maxSteps % stride() != 0) { // the default: the next whole coarse step
      maxSteps += stride() - maxSteps % stride();
      PetscCall(TSSetMaxSteps(ts_, maxSteps));
    }
    if (maxSteps % stride() != 0)
      throw InputError("option -ts_max_steps " + std::to_string(maxSteps) +
                       ": with -gimp_multirate true it must be a multiple of the coarse step, " +
                       std::to_string(stride()) + " fine steps (h0 / h_min)");
  }
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts_, &dt));
  // With -gimp_stability_check the penalty bounds and the step come from the eigenvalues.
  PetscCall(boundary_.setup(comm_, sc_, grid_, dt, !sc_.stabilityCheck));
  if (sc_.multirate)
    PetscCall(rate_.create(grid_, nodal_.P, boundary_.active(), sc_.multirateNodeRule));
  if (sc_.stabilityCheck) PetscCall(stabilityAtStart());
  if (sc_.multirate) PetscCall(checkCoarseTimeLimit());
  PetscCall(rejectUnusedOptions(2));
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

PetscErrorCode Solver::writeGridDump() {
  // Rank 0 writes; a failure to open or to write (a full disk) ends every rank with one line
  // and removes what was written of a regular file.
  std::string error;
  if (rank_ == 0) {
    errno = 0;
    std::FILE *f = std::fopen(sc_.gridDump.c_str(), "w");
    if (!f) {
      error = std::string("cannot open the file for writing (") + std::strerror(errno) + ")";
    } else {
      const std::string text = grid_.activeNodesCsv();
      const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
      int e = written ? 0 : errno;
      if (std::fclose(f) != 0 && !e) e = errno;
      if (!written || e) {
        error = std::string("cannot write the file (") + std::strerror(e ? e : EIO) + ")";
        std::error_code ec;
        if (std::filesystem::is_regular_file(sc_.gridDump, ec))
          std::filesystem::remove(sc_.gridDump, ec);
      }
    }
  }
  return agree(comm_,
               error.empty() ? error : "option -gimp_grid_dump " + sc_.gridDump + ": " + error);
}

PetscErrorCode Solver::createParticles() {
  PetscCall(createSwarm<2>(comm_, optionalFieldsOf(sc_), &sw_));
  LoadConflict conflict;
  PetscCall(seedParticles(sc_, grid_, sw_, conflict));
  PetscCall(conflict.agree(comm_, sc_));
  ParticleView<2> p;
  PetscCall(p.get(sw_));
  PetscCall(checkSeeding(comm_, sc_, grid_, p, nParticles_, meanParticleMass_));
  if (sc_.mms == Mms::AxialWave) { // start displaced and pre-stressed, at rest
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
  for (PetscInt k = 0; k < p.n; ++k) {
    const Material &mat = sc_.materialOf(p.id[k]);
    if (mat.model == MaterialModel::NeoHookean)
      material::neoHookeanStress(mat, tensorAt<2>(p.F, k), tensorAt<2>(p.s, k), p.szz[k]);
  }
  PetscCall(p.restore(sw_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::checkCoarseTimeLimit() {
  // A time limit that TS must meet exactly (matchstep) has to fall on a coarse-step
  // end: every class's impulses of a coarse step are taken with the full fine step.
  TSExactFinalTimeOption exact;
  PetscReal maxTime = 0, dt = 0;
  PetscCall(TSGetExactFinalTime(ts_, &exact));
  PetscCall(TSGetMaxTime(ts_, &maxTime));
  PetscCall(TSGetTimeStep(ts_, &dt));
  if (exact == TS_EXACTFINALTIME_STEPOVER || !(maxTime < 1e299)) return PETSC_SUCCESS;
  const double coarse = static_cast<double>(stride()) * dt, n = std::round(maxTime / coarse);
  if (n < 1 || std::fabs(n * coarse - maxTime) > 1e-9 * maxTime)
    throw InputError("option -ts_max_time " + formatNumber(maxTime) +
                     ": with -gimp_multirate true and an exact final time it must be a whole "
                     "number of coarse steps of " +
                     formatNumber(coarse) + " s (" + std::to_string(stride()) +
                     " x -ts_dt); or use -ts_exact_final_time stepover");
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
  PetscCall(TSSetTimeStep(ts_, sc_.cfl * (grid_.hMin() / sc_.maxWaveSpeed())));
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
