// Setting up a run: scene, grid, particles, nodal vectors, time stepper, boundary terms, output.
#include "gimp/core/memory.hpp"
#include "gimp/input/problem_size.hpp"
#include "gimp/input/validate.hpp"
#include "gimp/io/paths.hpp"
#include "gimp/particles/seed.hpp"
#include "gimp/physics/constraints.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/physics/mms.hpp"
#include "gimp/solver/solver.hpp"
#include "gimp/transfer/lane_loops.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace gimp {

namespace {

/// What a particle and a grid node cost: the swarm's fields and a stencil (16 nodes in 2D, 27 in
/// 3D) per particle; per node, the global and window Vecs of Nodal and TS's work vectors (about
/// 24 Vecs of D components) with their index sets.
template <int D> ItemBytes itemBytes(const Scene<D> &sc) {
  constexpr double kStencilNodes = D == 2 ? 16 : 27, kNodeVecs = 24;
  ItemBytes b;
  const OptionalFields optional = optionalFieldsOf(sc);
  for (const FieldSpec<D> &f : particleFields<D>())
    if (optional.has(f.need))
      b.particle +=
          static_cast<double>(f.components) * (f.type == PETSC_INT ? sizeof(PetscInt) : 8);
  b.particle += kStencilNodes * (sizeof(PetscInt) + 2 * D * sizeof(double));
  b.node = kNodeVecs * D * sizeof(PetscScalar) + 4 * sizeof(PetscInt);
  return b;
}

/// The 2D neo-Hookean stress of the seeded F (with the out-of-plane stress).
void neoHookeanOf(const Material &mat, ParticleView<2> &p, PetscInt k) {
  Tensor<2> s;
  material::neoHookeanStress(mat, tensorAt<2>(p.F, k), s, p.szz[k]);
  setStress<2>(p.s, k, s);
}
void neoHookeanOf(const Material &mat, ParticleView<3> &p, PetscInt k) {
  Tensor<3> s;
  material::neoHookeanStress(mat, Tensor<3>(tensorAt<3>(p.F, k)), s);
  setStress<3>(p.s, k, s);
}

/// The paths the run writes and the files it reads.
template <int D> RunPaths runPaths(const Scene<D> &sc) {
  RunPaths paths{sc.outputDir, {}, {{"gimp_restart", sc.restart}}};
  if (!sc.particleDump.empty()) paths.dumps.emplace_back("gimp_particle_dump", sc.particleDump);
  if (!sc.gridDump.empty()) paths.dumps.emplace_back("gimp_grid_dump", sc.gridDump);
  for (size_t k = 0; k < sc.bodies.size(); ++k)
    paths.inputs.emplace_back("gimp_body" + std::to_string(k) + "_file", sc.bodies[k].file);
  return paths;
}

} // namespace

template <int D>
Solver<D>::Solver(MPI_Comm comm)
    : step_(s_), reporter_(s_), stability_(s_, step_, slepc_), checkpoint_(s_, step_, reporter_) {
  s_.comm = comm;
}

template <int D> PetscErrorCode Solver<D>::setup() {
  RunState<D> &s = s_;
  PetscLogDouble wall0 = 0;
  PetscCall(PetscTime(&wall0));
  PetscCallMPI(MPI_Comm_rank(s.comm, &s.rank));
  PetscCallMPI(MPI_Comm_size(s.comm, &s.size));
  PetscCall(s.stages.registerAll());
  // -log_view's "Setup" stage; popped on the way out of an input error too (the in-process
  // bad-input test sets up many scenes in one process).
  struct StagePop {
    bool pushed = false;
    ~StagePop() {
      if (pushed) (void)PetscLogStagePop();
    }
  } pop;
  PetscCall(PetscLogStagePush(s.stages.setup));
  pop.pushed = true;
  PetscCall(setupInStage(wall0));
  pop.pushed = false;
  PetscCall(PetscLogStagePop());
  if (!s.sc.help) PetscCall(reporter_.markSetupEnd());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Solver<D>::setupInStage(PetscLogDouble wall0) {
  RunState<D> &s = s_;
  PetscCall(readSceneOneLine<D>(s.comm, s.sc));
  if (s.sc.help) { // list the time stepper's options too, then stop
    PetscCall(TSCreate(s.comm, &s.ts));
    PetscCall(TSSetFromOptions(s.ts));
    return PETSC_SUCCESS;
  }
  checkSceneCombinations<D>(s.sc);
  if constexpr (D == 3)
    for (size_t b = 0; b < s.sc.bodies.size() && s.sc.cutCells; ++b) {
      const std::string p = "gimp_body" + std::to_string(b) + "_";
      const std::string where = approximateCuts(s.sc.bodies[b], p);
      if (!where.empty())
        PetscCall(PetscPrintf(s.comm,
                              "gimp: warning: %s: the particles both spheres cut keep their part "
                              "only approximately (the volume off by up to 5e-4 of the body's in "
                              "the cases measured), the others exactly\n",
                              where.c_str()));
    }
  PetscCall(checkRunPaths(s.comm, runPaths(s.sc))); // before anything is computed or written
  PetscCall(checkProblemSize<D>(s.comm, s.sc, itemBytes(s.sc)));
  s.scheme = schemeFor(s.sc.update);
  // The strain energy of a report at the velocities' time (WorkLedger::strainShift).
  s.work.strainShift = s.scheme.stressBeforeGridUpdate ? 0.5 : -0.5;
  s.lanes = s.sc.lanes && transfer::laneLoops::available();
  PetscCall(
      PetscInfo(nullptr, "%s: %s\n",
                D == 2 ? "2D block kernels in lanes of four particles"
                       : "3D block kernels with a node's three components in lanes",
                s.lanes ? "yes" : (s.sc.lanes ? "no (no AVX2 here)" : "no (-gimp_lanes false)")));
  // The DMDAs (-da_*), the swarm and TS read options: a PETSc error there is one line.
  PetscCall(petscOneLine([this] { return createGrid(); }, "da_",
                         " (-da_processors_x/y/z: the ranks along each axis of level 0, their "
                         "product the number of ranks, each at most the level's nodes on it)"));
  PetscCall(petscOneLine([this] { return createParticles(); }));
  PetscCall(s.nodal.create(s.grid, s.sc.hasExternalForces(), !s.sc.cracks.empty(),
                           s.sc.transfer == Transfer::Xpic));
  setupContact(0);
  PetscCall(physics::nodeConstraints<D>(s.sc, s.grid, s.nodal.bcMask));
  PetscCall(reporter_.setup(wall0, [this] {
    s_.st.release();
    if (multirate_) multirate_->releaseStencils();
    returnFreeMemory();
  }));
  PetscCall(petscOneLine([this] { return createTimeStepper(); }, "ts_"));
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(s.ts, &dt));
  // With -gimp_stability_check the penalty bounds and the step come from the eigenvalues.
  PetscCall(s.boundary.setup(s.comm, s.sc, s.grid, dt, !s.sc.stabilityCheck));
  if (s.sc.multirate) {
    multirate_ = std::make_unique<MultiRate<D>>(s, step_);
    PetscCall(multirate_->create(s.nodal.P));
  }
  if (s.sc.stabilityCheck)
    PetscCall(petscOneLine([this] { return stability_.atStart(); }, "gimp_stability_"));
  if (s.sc.multirate) PetscCall(coarseStepLimits());
  PetscCall(checkViewerOptions(s.comm));
  PetscCall(rejectUnusedOptions());
  return openOutput();
}

template <int D> PetscErrorCode Solver<D>::createGrid() {
  RunState<D> &s = s_;
  reserveCrackGrowth();
  if (s.sc.balance) // the particles a leaf cell will hold: the bodies' particles per cell
    s.grid.cellWork = [&sc = s.sc](const double *centre, double) {
      double w = 0;
      for (const Body<D> &b : sc.bodies)
        if (b.inside(centre)) w += b.ppc;
      return w;
    };
  PetscCall(s.grid.create(s.comm, s.sc.h, s.sc.levelBoxes(), s.sc.cracks));
  s.sc.idSlots = bodyIdSlots<D>(s.grid);
  if (!s.sc.gridDump.empty()) PetscCall(writeGridDump());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Solver<D>::openOutput() {
  if (s_.sc.restart.empty()) return reporter_.open(nullptr);
  OutputResume resume;
  PetscCall(checkpoint_.load(resume, [this](const std::vector<LevelBox<D>> &boxes) {
    PetscInt64 added = 0;
    return regrid(boxes, false, added);
  }));
  double t = 0;
  PetscCall(TSGetTime(s_.ts, &t));
  PetscCall(followCracks(t)); // the checkpoint's cracks may have grown
  return reporter_.open(&resume);
}

template <int D> PetscErrorCode Solver<D>::writeGridDump() {
  // Rank 0 writes; a failure to open or to write (a full disk) ends every rank with one line
  // and removes what was written of a regular file.
  const RunState<D> &s = s_;
  const std::string &file = s.sc.gridDump;
  std::string error;
  if (s.rank == 0) {
    errno = 0;
    std::FILE *f = std::fopen(file.c_str(), "w");
    if (!f) {
      error = std::string("cannot open the file for writing (") + std::strerror(errno) + ")";
    } else {
      const std::string text = s.grid.activeNodesCsv();
      const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
      int e = written ? 0 : errno;
      if (std::fclose(f) != 0 && !e) e = errno;
      if (!written || e) {
        error = std::string("cannot write the file (") + std::strerror(e ? e : EIO) + ")";
        std::error_code ec;
        if (std::filesystem::is_regular_file(file, ec)) std::filesystem::remove(file, ec);
      }
    }
  }
  return agree(s.comm, error.empty() ? error : "option -gimp_grid_dump " + file + ": " + error);
}

template <int D> PetscErrorCode Solver<D>::createParticles() {
  RunState<D> &s = s_;
  PetscCall(createSwarm<D>(s.comm, optionalFieldsOf(s.sc), &s.sw));
  LoadConflict conflict;
  PetscCall(seedParticles<D>(s.sc, s.grid, s.sw, conflict));
  PetscCall(conflict.agree(s.comm, s.sc));
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  PetscCall(checkSeeding<D>(s.comm, s.sc, s.grid, p, s.nParticles, s.meanParticleMass));
  PetscCall(initialState(p));
  PetscCall(p.restore(s.sw));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Solver<D>::initialState(ParticleView<D> &p) {
  const Scene<D> &sc = s_.sc;
  if (sc.mms == Mms::AxialWave) { // start displaced and pre-stressed, at rest
    const mms::AxialWave ex(sc);
    for (PetscInt k = 0; k < p.n; ++k) {
      const double X = p.X0[D * k], F = ex.F(X, 0.0);
      p.x[D * k] = X + ex.u(X, 0.0);
      for (int a = 0; a < D; ++a)
        p.v[D * k + a] = 0.0;
      p.F[D * D * k] = F;
      p.V[k] = F * p.V0[k];
      if (D == 2 || sc.tracking == Tracking::Stretch) p.l[D * k] = F * p.l0[D * k];
      if (p.hasCorners)
        for (int q = 0; q < (1 << D); ++q) {
          double &cx = p.corners[D * ((1 << D) * k + q)];
          cx += ex.u(cx, 0.0);
        }
    }
  }
  for (PetscInt k = 0; k < p.n; ++k) {
    const Material &mat = sc.materialOf(p.id[k]);
    if (mat.model == MaterialModel::NeoHookean) neoHookeanOf(mat, p, k);
  }
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Solver<D>::createTimeStepper() {
  // TS euler on the nodal momentum; the steps are driven by run(), one TSStep per step.
  RunState<D> &s = s_;
  PetscCall(TSCreate(s.comm, &s.ts));
  PetscCall(TSSetDM(s.ts, s.grid.dm));
  PetscCall(TSSetType(s.ts, TSEULER));
  PetscCall(TSSetProblemType(s.ts, TS_NONLINEAR));
  PetscCall(TSSetApplicationContext(s.ts, &s));
  PetscCall(TSSetRHSFunction(s.ts, nullptr, &Step<D>::rhs, &s));
  PetscCall(TSSetTimeStep(s.ts, s.sc.cfl * (s.grid.hMin() / s.sc.maxWaveSpeed())));
  PetscCall(TSSetMaxSteps(s.ts, 1000));
  PetscCall(TSSetMaxTime(s.ts, 1e300));
  PetscCall(TSSetExactFinalTime(s.ts, TS_EXACTFINALTIME_STEPOVER));
  PetscCall(timeStepFromOptions<D>(s.ts, s.sc, s.grid));
  PetscCall(TSSetSolution(s.ts, s.nodal.P));
  PetscCall(TSSetUp(s.ts));
  if (!s.sc.multirate) return PETSC_SUCCESS;
  // Reports, checkpoints and the step limit act at coarse-step ends (R fine steps).
  PetscInt maxSteps = 0;
  PetscBool given = PETSC_FALSE;
  PetscCall(TSGetMaxSteps(s.ts, &maxSteps));
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-ts_max_steps", &given));
  const PetscInt R = s.stride();
  if (!given && maxSteps % R != 0) { // the default: the next whole coarse step
    maxSteps += R - maxSteps % R;
    PetscCall(TSSetMaxSteps(s.ts, maxSteps));
  }
  if (maxSteps % R != 0)
    throw InputError("option -ts_max_steps " + std::to_string(maxSteps) +
                     ": with -gimp_multirate true it must be a multiple of the coarse step, " +
                     std::to_string(R) + " fine steps (h0 / h_min)");
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Solver<D>::coarseStepLimits() {
  // A time limit that TS must meet exactly (matchstep) has to fall on a coarse-step
  // end: every class's impulses of a coarse step are taken with the full fine step.
  const RunState<D> &s = s_;
  TSExactFinalTimeOption exact;
  PetscReal maxTime = 0, dt = 0;
  PetscCall(TSGetExactFinalTime(s.ts, &exact));
  PetscCall(TSGetMaxTime(s.ts, &maxTime));
  PetscCall(TSGetTimeStep(s.ts, &dt));
  if (exact == TS_EXACTFINALTIME_STEPOVER || !(maxTime < 1e299)) return PETSC_SUCCESS;
  const double coarse = static_cast<double>(s.stride()) * dt, n = std::round(maxTime / coarse);
  if (n < 1 || std::fabs(n * coarse - maxTime) > 1e-9 * maxTime)
    throw InputError("option -ts_max_time " + formatNumber(maxTime) +
                     ": with -gimp_multirate true and an exact final time it must be a whole "
                     "number of coarse steps of " +
                     formatNumber(coarse) + " s (" + std::to_string(s.stride()) +
                     " x -ts_dt); or use -ts_exact_final_time stepover");
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template Solver<D>::Solver(MPI_Comm);                                                            \
  template PetscErrorCode Solver<D>::setup();
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
