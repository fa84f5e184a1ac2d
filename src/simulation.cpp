#include "gimp/simulation.hpp"

#include "gimp/material.hpp"
#include "gimp/mms.hpp"
#include "gimp/output.hpp"
#include "gimp/shape.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>

namespace gimp {

namespace {

/// Id slots per body: ids encode body, level, cell and sub-cell (see seedParticles).
PetscInt64 bodySlots(const Grid &g) {
  PetscInt64 cells = 0;
  for (const Level &L : g.levels)
    cells = std::max<PetscInt64>(cells, static_cast<PetscInt64>(L.M) * L.N);
  return static_cast<PetscInt64>(g.levels.size()) * cells * 64 * 64;
}

std::string boxText(const Box &b) {
  return formatNumber(b[0]) + "," + formatNumber(b[1]) + "," + formatNumber(b[2]) + "," +
         formatNumber(b[3]);
}

/// While the scene is read, PETSc's own parsing errors (a number that is not one, an unknown
/// logical value) are kept as one message instead of a trace.
PetscErrorCode keepInputError(MPI_Comm, int, const char *, const char *, PetscErrorCode n,
                              PetscErrorType p, const char *mess, void *ctx) {
  if (p == PETSC_ERROR_INITIAL && mess) *static_cast<std::string *>(ctx) = mess;
  return n;
}

/// The option whose value appears in PETSc's message ("Input string abc has ...",
/// "Unknown logical value: maybe"), to name it in the one-line error.
std::string optionWithValueIn(const std::string &message) {
  char *all = nullptr;
  if (PetscOptionsGetAll(nullptr, &all) || !all) return "";
  std::istringstream in(all);
  std::string tok, name, found;
  while (in >> tok) {
    if (tok.size() > 1 && tok[0] == '-' && !std::isdigit(static_cast<unsigned char>(tok[1])) &&
        tok[1] != '.') {
      name = tok;
      continue;
    }
    const bool atEnd = message.size() >= tok.size() &&
                       message.compare(message.size() - tok.size(), tok.size(), tok) == 0;
    if (!name.empty() && (message.find(" " + tok + " ") != std::string::npos || atEnd))
      found = name + " " + tok;
  }
  (void)PetscFree(all);
  return found;
}

/// Centre along axis d of the rectangle spanned by a particle's four corners (x,y pairs).
double cornerBoxCentre(const double *c, int d) {
  return 0.5 * (std::min({c[d], c[d + 2], c[d + 4], c[d + 6]}) +
                std::max({c[d], c[d + 2], c[d + 4], c[d + 6]}));
}

Simulation *fromTS(TS ts) {
  void *ctx = nullptr;
  (void)TSGetApplicationContext(ts, &ctx);
  return static_cast<Simulation *>(ctx);
}

} // namespace

Simulation::Simulation(MPI_Comm comm) : comm_(comm) {}

Simulation::~Simulation() {
  Vec *vecs[] = {&P_,       &mass_,  &vel_,  &acc_,  &force_, &fext_, &bcMask_, &mask_,
                 &invMass_, &massW_, &sumW_, &velW_, &accW_,  &extW_, &massW2_};
  for (Vec *v : vecs)
    if (*v) (void)VecDestroy(v);
  if (ts_) (void)TSDestroy(&ts_);
  if (sw_) (void)DMDestroy(&sw_);
}

PetscErrorCode Simulation::setup() {
  PetscCall(PetscTime(&wall0_));
  PetscCallMPI(MPI_Comm_rank(comm_, &rank_));
  PetscCallMPI(MPI_Comm_size(comm_, &size_));
  PetscCall(PetscLogStageRegister("P2G", &stageP2G_));
  PetscCall(PetscLogStageRegister("Forces", &stageForces_));
  PetscCall(PetscLogStageRegister("Grid update", &stageGrid_));
  PetscCall(PetscLogStageRegister("G2P", &stageG2P_));
  PetscCall(PetscLogStageRegister("Stress", &stageStress_));
  PetscCall(PetscLogStageRegister("Output", &stageOutput_));

  {
    std::string petscMessage;
    PetscCall(PetscPushErrorHandler(keepInputError, &petscMessage));
    const PetscErrorCode ierr = readScene(comm_, sc_);
    PetscCall(PetscPopErrorHandler());
    if (ierr) {
      const std::string opt = optionWithValueIn(petscMessage);
      throw InputError((opt.empty() ? std::string("options: ") : "option " + opt + ": ") +
                       petscMessage);
    }
  }
  if (sc_.help) {
    PetscCall(TSCreate(comm_, &ts_));
    PetscCall(TSSetFromOptions(ts_));
    return PETSC_SUCCESS;
  }
  if (sc_.material.model == MaterialModel::NeoHookean && !sc_.material.planeStrain)
    throw InputError("option -gimp_material neohookean: needs -gimp_plane strain (the plane-stress "
                     "neo-Hookean model is not implemented)");
  for (size_t b = 0; b < sc_.bodies.size(); ++b)
    if (std::max(sc_.bodies[b].ppc, sc_.bodies[b].holePpc) > 64 * 64)
      throw InputError("option -gimp_body" + std::to_string(b) +
                       "_ppc: at most 4096 particles per cell (64 x 64)");

  PetscCall(grid_.create(comm_, sc_));
  if (!sc_.gridDump.empty()) PetscCall(grid_.dump(comm_, sc_.gridDump));

  // Particles.
  PetscCall(createSwarm(comm_, sc_.tracking == Tracking::Corners, &sw_));
  PetscCall(seedParticles(sc_, grid_, sw_));
  {
    ParticleView p;
    PetscCall(p.get(sw_));
    // Count particles per body; an empty body is an input error.
    const PetscInt64 slots = bodySlots(grid_);
    std::vector<PetscInt64> count(sc_.bodies.size(), 0), total(sc_.bodies.size(), 0);
    double msum = 0;
    for (PetscInt k = 0; k < p.n; ++k) {
      ++count[p.id[k] / slots];
      msum += p.m[k];
    }
    PetscCallMPI(MPI_Allreduce(count.data(), total.data(), static_cast<int>(count.size()),
                               MPI_INT64_T, MPI_SUM, comm_));
    double mtot = 0;
    PetscCallMPI(MPI_Allreduce(&msum, &mtot, 1, MPI_DOUBLE, MPI_SUM, comm_));
    nParticles_ = 0;
    for (size_t b = 0; b < total.size(); ++b) {
      if (total[b] == 0)
        throw InputError("option -gimp_body" + std::to_string(b) + "_box " +
                         boxText(sc_.bodies[b].box) +
                         ": the body holds no particle (its cells are all removed by holes "
                         "or it is thinner than a particle); enlarge it or refine -gimp_h");
      nParticles_ += total[b];
    }
    meanParticleMass_ = mtot / static_cast<double>(nParticles_);

    // A traction or displacement condition that reaches no particle edge would act on nothing.
    const size_t nt = sc_.tractions.size(), nd = sc_.dbcs.size();
    std::vector<PetscInt64> hits(nt + nd, 0), gHits(nt + nd, 0);
    for (PetscInt k = 0; k < p.n; ++k)
      for (int a = 0; a < 2; ++a) {
        if (p.trac[2 * k + a] >= 0) ++hits[p.trac[2 * k + a]];
        if (p.dbc[2 * k + a] >= 0) ++hits[nt + p.dbc[2 * k + a]];
      }
    if (!hits.empty())
      PetscCallMPI(MPI_Allreduce(hits.data(), gHits.data(), static_cast<int>(hits.size()),
                                 MPI_INT64_T, MPI_SUM, comm_));
    for (size_t q = 0; q < gHits.size(); ++q)
      if (gHits[q] == 0) {
        const bool isTraction = q < nt;
        const Segment &seg = isTraction ? static_cast<const Segment &>(sc_.tractions[q])
                                        : static_cast<const Segment &>(sc_.dbcs[q - nt]);
        const std::string name =
            (isTraction ? "gimp_traction" : "gimp_dbc") + std::to_string(isTraction ? q : q - nt);
        const char *sides[] = {"left", "right", "bottom", "top"};
        throw InputError("option -" + name + "_side " + sides[static_cast<int>(seg.side)] +
                         ": no particle edge of body " + std::to_string(seg.body) +
                         " lies on that side" +
                         (seg.hasRange ? " within -" + name + "_range" : "") +
                         " (particles fill whole sub-cells: put the body's edges on grid lines)");
      }

    if (sc_.mms == Mms::Skb1d) {
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
        material::neoHookeanStress(sc_.material, &p.F[4 * k], &p.s[4 * k]);
    PetscInt64 outside = INT64_MAX, gOutside = INT64_MAX;
    for (PetscInt k = 0; k < p.n; ++k) {
      const double x = p.x[2 * k], y = p.x[2 * k + 1];
      if (x - p.l[2 * k] < sc_.domain[0] || x + p.l[2 * k] > sc_.domain[2] ||
          y - p.l[2 * k + 1] < sc_.domain[1] || y + p.l[2 * k + 1] > sc_.domain[3])
        outside = std::min(outside, p.id[k]);
    }
    PetscCallMPI(MPI_Allreduce(&outside, &gOutside, 1, MPI_INT64_T, MPI_MIN, comm_));
    if (gOutside != INT64_MAX)
      throw InputError("option -gimp_domain " + formatNumber(sc_.domain[0]) + "," +
                       formatNumber(sc_.domain[1]) + "," + formatNumber(sc_.domain[2]) + "," +
                       formatNumber(sc_.domain[3]) + ": particle " + std::to_string(gOutside) +
                       " of body " + std::to_string(gOutside / slots) +
                       " is not inside the grid; enlarge the domain or -gimp_pad");
    PetscCall(p.restore(sw_));
  }

  // Nodal vectors.
  PetscCall(DMCreateGlobalVector(grid_.dm, &P_));
  PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(P_), "momentum"));
  Vec *globals[] = {&mass_, &vel_, &acc_, &force_, &bcMask_, &mask_, &invMass_};
  for (Vec *v : globals)
    PetscCall(VecDuplicate(P_, v));
  Vec *windows[] = {&massW_, &sumW_, &velW_, &accW_};
  for (Vec *v : windows)
    PetscCall(grid_.createWindowVec(v));
  hasExternal_ = !sc_.tractions.empty() || !sc_.dbcs.empty() || sc_.gravity[0] != 0 ||
                 sc_.gravity[1] != 0 || sc_.mms != Mms::None;
  if (hasExternal_) {
    PetscCall(VecDuplicate(P_, &fext_));
    PetscCall(grid_.createWindowVec(&extW_));
  }
  PetscCall(setConstraints());

  // Probes: the particle nearest to each requested initial position (ties: smallest id).
  {
    ParticleView p;
    PetscCall(p.get(sw_));
    for (const Probe &pr : sc_.probes) {
      double best = 1e300;
      PetscInt64 bestId = INT64_MAX;
      for (PetscInt k = 0; k < p.n; ++k) {
        const double dx = p.X0[2 * k] - pr.x[0], dy = p.X0[2 * k + 1] - pr.x[1];
        const double d2 = dx * dx + dy * dy;
        if (d2 < best || (d2 == best && p.id[k] < bestId)) {
          best = d2;
          bestId = p.id[k];
        }
      }
      double gbest = 0;
      PetscCallMPI(MPI_Allreduce(&best, &gbest, 1, MPI_DOUBLE, MPI_MIN, comm_));
      PetscInt64 mine = best == gbest ? bestId : INT64_MAX, gid = 0;
      PetscCallMPI(MPI_Allreduce(&mine, &gid, 1, MPI_INT64_T, MPI_MIN, comm_));
      ProbeState ps;
      ps.id = gid;
      probeIds_.push_back(ps);
    }
    PetscCall(p.restore(sw_));
  }

  // Time stepping: TS euler on the nodal momentum.
  PetscCall(TSCreate(comm_, &ts_));
  PetscCall(TSSetDM(ts_, grid_.dm));
  PetscCall(TSSetType(ts_, TSEULER));
  PetscCall(TSSetProblemType(ts_, TS_NONLINEAR));
  PetscCall(TSSetApplicationContext(ts_, this));
  PetscCall(TSSetRHSFunction(ts_, nullptr, &Simulation::rhs, this));
  PetscCall(TSSetPreStep(ts_, &Simulation::preStep));
  PetscCall(TSSetPostStep(ts_, &Simulation::postStep));
  const double cp = sc_.material.waveSpeed();
  const double dtStable = grid_.hMin() / cp;
  PetscCall(TSSetTimeStep(ts_, sc_.cfl * dtStable));
  PetscCall(TSSetMaxSteps(ts_, 1000));
  PetscCall(TSSetMaxTime(ts_, 1e300));
  PetscCall(TSSetExactFinalTime(ts_, TS_EXACTFINALTIME_STEPOVER));
  {
    std::string petscMessage;
    PetscCall(PetscPushErrorHandler(keepInputError, &petscMessage));
    const PetscErrorCode ierr = TSSetFromOptions(ts_);
    PetscCall(PetscPopErrorHandler());
    if (ierr) {
      const std::string opt = optionWithValueIn(petscMessage);
      throw InputError((opt.empty() ? std::string("options: ") : "option " + opt + ": ") +
                       petscMessage);
    }
  }
  {
    TSType type;
    TSAdapt adapt;
    TSAdaptType atype;
    PetscCall(TSGetType(ts_, &type));
    PetscCall(TSGetAdapt(ts_, &adapt));
    PetscCall(TSAdaptGetType(adapt, &atype));
    if (std::string(type) != TSEULER)
      throw InputError(
          "option -ts_type " + std::string(type) +
          ": gimp advances the nodal momentum with euler (Eq. 16); use -ts_type euler");
    if (std::string(atype) != TSADAPTNONE)
      throw InputError("option -ts_adapt_type " + std::string(atype) +
                       ": the time step is fixed (-ts_dt); use -ts_adapt_type none");
  }
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts_, &dt));
  if (!(dt > 0)) throw InputError("option -ts_dt " + formatNumber(dt) + ": must be > 0 [s]");
  if (dt > dtStable)
    throw InputError("option -ts_dt " + formatNumber(dt) + ": exceeds the stable limit h / c_p = " +
                     formatNumber(dtStable) + " s (finest h = " + formatNumber(grid_.hMin()) +
                     " m, c_p = " + formatNumber(cp) +
                     " m/s); choose -ts_dt <= " + formatNumber(dtStable));
  PetscCall(TSSetSolution(ts_, P_));

  // Penalty of Eq. 9. Its spring on a boundary node (alpha h per unit thickness against a mass
  // of about rho h^2 / 2) is stable for alpha < 2 rho h / dt^2.
  if (!sc_.dbcs.empty()) {
    const double M = sc_.material.lambdaStar + 2.0 * sc_.material.mu, h = grid_.hMin();
    // Measured on the slab: stable at 0.83 of 2 rho h / dt^2, unstable at 0.92 of it.
    const double limit = 1.6 * sc_.material.rho * h / (dt * dt);
    if (sc_.penalty == 0) {
      alpha_ = std::min(100.0 * M / h, 0.5 * sc_.material.rho * h / (dt * dt));
    } else {
      alpha_ = sc_.penalty;
      double worst = 0;
      for (const DisplacementBC &d : sc_.dbcs)
        worst = std::max(worst, d.penaltyScale);
      if (alpha_ * worst > limit)
        throw InputError("option -gimp_penalty " + formatNumber(sc_.penalty) +
                         ": with the largest segment scale " + formatNumber(worst) +
                         " it exceeds the stable limit 1.6 rho h_min / dt^2 = " +
                         formatNumber(limit) + " Pa/m for -ts_dt " + formatNumber(dt));
    }
    if (sc_.penaltyTraction) {
      // Without its symmetric counterpart, the traction term of Eq. 9 needs a penalty that
      // dominates it: measured unstable at 1 M / h_min and stable from 2 M / h_min on.
      double weakest = 1e300;
      for (const DisplacementBC &d : sc_.dbcs)
        weakest = std::min(weakest, d.penaltyScale);
      if (alpha_ * weakest < 4.0 * M / h)
        throw InputError("option -gimp_penalty " + formatNumber(alpha_) +
                         ": with the smallest segment "
                         "scale " +
                         formatNumber(weakest) +
                         " it is below 4 M / h_min = " + formatNumber(4.0 * M / h) +
                         " Pa/m, where the traction term of Eq. 9 goes "
                         "unstable; raise it, or use -gimp_penalty_traction false");
    }
    reactions_.assign(2 * sc_.dbcs.size(), 0.0);
    gaps_.assign(sc_.dbcs.size(), 0.0);
    maxGap_.assign(sc_.dbcs.size(), 0.0);
    PetscCall(PetscPrintf(comm_, "gimp: penalty alpha = %.6g Pa/m (%.3g M / h_min)\n", alpha_,
                          alpha_ * h / M));
  }

  // Unknown or misspelled options stop the run here (options read at exit are allowed).
  {
    PetscInt nleft = 0;
    char **names = nullptr, **values = nullptr;
    PetscCall(PetscOptionsLeftGet(nullptr, &nleft, &names, &values));
    std::string unknown;
    const char *lateOptions[] = {
        "log_view",        "log_all",     "log_trace",   "options_left", "options_view",
        "malloc_dump",     "malloc_view", "memory_view", "objects_dump", "check_pointer_intensity",
        "log_view_memory", "info"};
    for (PetscInt i = 0; i < nleft && unknown.empty(); ++i) {
      bool late = false;
      for (const char *o : lateOptions)
        if (std::string(names[i]).rfind(o, 0) == 0) late = true;
      if (!late) unknown = std::string(names[i]) + (values[i] ? std::string(" ") + values[i] : "");
    }
    PetscCall(PetscOptionsLeftRestore(nullptr, &nleft, &names, &values));
    if (!unknown.empty())
      throw InputError("option -" + unknown +
                       ": unknown option (misspelled, or not used by this scene); see -help and "
                       "docs/options.md");
  }

  out_ = std::make_unique<Output>(*this);
  PetscCall(out_->open());
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::run() {
  if (sc_.help) return PETSC_SUCCESS;
  PetscCall(out_->writeFields(0, 0.0));
  PetscCall(out_->writeHistory(0, 0.0));
  PetscCall(TSSolve(ts_, P_));
  PetscInt steps = 0;
  PetscReal t = 0;
  PetscCall(TSGetStepNumber(ts_, &steps));
  PetscCall(TSGetTime(ts_, &t));
  PetscCall(PetscLogStagePush(stageOutput_));
  if (!failed_) {
    if (sc_.outputInterval == 0 || steps % sc_.outputInterval != 0)
      PetscCall(out_->writeFields(steps, t));
    if (steps % sc_.historyInterval != 0) PetscCall(out_->writeHistory(steps, t));
  }
  if (!sc_.particleDump.empty()) PetscCall(writeParticleDump(sc_.particleDump));
  PetscLogDouble wall1 = 0;
  PetscCall(PetscTime(&wall1));
  PetscCall(out_->writeSummary(steps, t, wall1 - wall0_));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

// ---------------------------------------------------------------------------------------------
// Time step phases

PetscErrorCode Simulation::preStep(TS ts) {
  Simulation *s = fromTS(ts);
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts, &dt));
  PetscCall(PetscLogStagePush(s->stageP2G_));
  PetscCall(s->migrate());
  ParticleView p;
  PetscCall(p.get(s->sw_));
  PetscCall(s->computeStencils(p));
  PetscCall(s->particleToGrid(p, true, s->P_));
  PetscCall(s->applyConstraintMask());
  PetscCall(VecPointwiseMult(s->P_, s->P_, s->mask_));
  PetscCall(VecPointwiseMult(s->vel_, s->P_, s->invMass_));
  PetscCall(PetscLogStagePop());
  if (s->sc_.update == Update::USF) {
    PetscCall(PetscLogStagePush(s->stageStress_));
    PetscCall(s->grid_.toWindow(s->vel_, s->velW_));
    PetscCall(s->updateStress(p, s->velW_, dt));
    PetscCall(PetscLogStagePop());
  }
  PetscCall(p.restore(s->sw_));
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::rhs(TS ts, PetscReal t, Vec X, Vec F, void *ctx) {
  Simulation *s = static_cast<Simulation *>(ctx);
  PetscInt step = 0;
  PetscCall(TSGetStepNumber(ts, &step));
  // Leapfrog start: the first step kicks by half the force, so particle velocities stand at
  // half steps and the update x += dt v, v += dt a is second order in time.
  s->kick_ = step == 0 && s->sc_.halfStepStart ? 0.5 : 1.0;
  PetscCall(PetscLogStagePush(s->stageForces_));
  ParticleView p;
  PetscCall(p.get(s->sw_));
  PetscCall(s->internalAndExternalForces(p, t, F));
  PetscCall(p.restore(s->sw_));
  if (s->sc_.damping > 0) {
    PetscCall(VecAXPY(F, -s->sc_.damping, X));
    PetscScalar pv = 0;
    PetscCall(VecDot(X, s->vel_, &pv));
    s->dampPowerStart_ = s->sc_.damping * pv;
  }
  PetscCall(VecPointwiseMult(F, F, s->mask_));
  if (s->kick_ != 1.0) PetscCall(VecScale(F, s->kick_));
  PetscCall(VecCopy(F, s->force_));
  if (s->hasExternal_) {
    PetscScalar fv = 0;
    PetscCall(VecDot(s->fext_, s->vel_, &fv));
    s->extPowerStart_ = fv;
  }
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::postStep(TS ts) {
  Simulation *s = fromTS(ts);
  PetscReal dt = 0, t = 0;
  PetscInt step = 0;
  PetscCall(TSGetTimeStep(ts, &dt));
  PetscCall(TSGetTime(ts, &t));
  PetscCall(TSGetStepNumber(ts, &step));
  const Scene &sc = s->sc_;

  PetscCall(PetscLogStagePush(s->stageGrid_));
  PetscCall(VecPointwiseMult(s->vel_, s->P_, s->invMass_));
  PetscCall(VecPointwiseMult(s->acc_, s->force_, s->invMass_));
  PetscCall(s->grid_.toWindow(s->vel_, s->velW_));
  PetscCall(s->grid_.toWindow(s->acc_, s->accW_));
  PetscCall(PetscLogStagePop());

  ParticleView p;
  PetscCall(p.get(s->sw_));
  PetscCall(PetscLogStagePush(s->stageG2P_));
  PetscCall(s->gridToParticle(p, dt));
  if (sc.update == Update::MUSL || sc.tracking == Tracking::Corners) {
    // Re-project the updated particle momentum (acc_ is free now): the velocity field of
    // MUSL's stress update, and the one the corners follow. Unlike p^n+1 / m it is a weighted
    // mean of particle velocities, so a node that a particle barely touches (tiny mass, huge
    // F / m) cannot throw a corner away.
    PetscCall(s->particleToGrid(p, false, s->acc_));
    PetscCall(VecPointwiseMult(s->acc_, s->acc_, s->invMass_));
    PetscCall(s->grid_.toWindow(s->acc_, s->accW_));
    if (sc.update == Update::MUSL) {
      PetscCall(VecCopy(s->acc_, s->vel_));
      PetscCall(VecCopy(s->accW_, s->velW_));
    }
    if (sc.tracking == Tracking::Corners) PetscCall(s->moveCorners(p, dt, s->accW_));
  }
  PetscCall(PetscLogStagePop());
  // Work of the external and damping forces over the step: force times the mean of the grid
  // velocities at its start and end. With MUSL the end velocity is the re-projection of the
  // particles' velocities, so nodal force residuals that move no particle do no work.
  if (s->hasExternal_) {
    PetscScalar fv = 0;
    PetscCall(VecDot(s->fext_, s->vel_, &fv));
    s->extWork_ += 0.5 * s->kick_ * dt * (s->extPowerStart_ + fv);
  }
  if (sc.damping > 0) {
    // The damping force is -d p^n, and p^n = p^n+1 - dt F.
    PetscScalar pv = 0, fv = 0;
    PetscCall(VecDot(s->P_, s->vel_, &pv));
    PetscCall(VecDot(s->force_, s->vel_, &fv));
    s->dampWork_ += 0.5 * s->kick_ * dt * (s->dampPowerStart_ + sc.damping * (pv - dt * fv));
  }
  if (sc.update != Update::USF) {
    PetscCall(PetscLogStagePush(s->stageStress_));
    PetscCall(s->updateStress(p, s->velW_, dt));
    PetscCall(PetscLogStagePop());
  }
  PetscCall(s->checkParticles(p, step, t));
  PetscCall(p.restore(s->sw_));
  PetscBool anyFailed = PETSC_FALSE, failed = s->failed_ ? PETSC_TRUE : PETSC_FALSE;
  PetscCallMPI(MPI_Allreduce(&failed, &anyFailed, 1, MPIU_BOOL, MPI_LOR, s->comm_));
  if (anyFailed) {
    s->failed_ = true;
    PetscCall(TSSetConvergedReason(ts, TS_DIVERGED_STEP_REJECTED));
    return PETSC_SUCCESS;
  }

  PetscCall(PetscLogStagePush(s->stageOutput_));
  if (step % sc.historyInterval == 0) PetscCall(s->out_->writeHistory(step, t));
  if (sc.staticTol > 0 && step % sc.historyInterval == 0 && t >= sc.staticTime) {
    // Energy-based rest criterion for runs damped to a static state.
    Energies e;
    PetscCall(s->energies(e));
    if (e.strain > 0 && e.kinetic < sc.staticTol * e.strain) {
      s->atRest_ = true;
      PetscCall(PetscPrintf(s->comm_,
                            "gimp: at rest at step %" PetscInt_FMT " t %.6g s: kinetic / strain "
                            "energy %.3g < %.3g\n",
                            step, (double)t, e.kinetic / e.strain, sc.staticTol));
      PetscCall(TSSetConvergedReason(ts, TS_CONVERGED_USER));
    }
  }
  if (sc.outputInterval > 0 && step % sc.outputInterval == 0)
    PetscCall(s->out_->writeFields(step, t));
  if (sc.monitorInterval > 0 && step % sc.monitorInterval == 0) {
    Energies e;
    PetscCall(s->energies(e));
    PetscCall(PetscPrintf(s->comm_,
                          "%6" PetscInt_FMT " t %.6e  KE %.6e  SE %.6e  Wext %.6e  Wdamp %.6e  "
                          "E %.6e  p (%.6e, %.6e)\n",
                          step, (double)t, e.kinetic, e.strain, e.externalWork, e.damping,
                          e.total(), e.momentum[0], e.momentum[1]));
  }
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::migrate() {
  if (size_ == 1) return PETSC_SUCCESS;
  ParticleView p;
  PetscCall(p.get(sw_));
  PetscInt64 moved = 0, any = 0;
  double box[4];
  grid_.ownedBox(rank_, box);
  for (PetscInt k = 0; k < p.n; ++k) {
    const double x = p.x[2 * k], y = p.x[2 * k + 1];
    if (x >= box[0] && x < box[2] && y >= box[1] && y < box[3]) continue; // stays here
    const PetscMPIInt r = grid_.ownerOf(x, y);
    p.rank[k] = r;
    if (r != rank_) ++moved;
  }
  PetscCall(p.restore(sw_));
  PetscCallMPI(MPI_Allreduce(&moved, &any, 1, MPI_INT64_T, MPI_SUM, comm_));
  if (any) PetscCall(DMSwarmMigrate(sw_, PETSC_TRUE));
  migrated_ += any;
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::computeStencils(const ParticleView &p) {
  if (sc_.tracking != Tracking::Corners) {
    grid_.buildStencils(p.n, p.x, p.l, st_);
    return PETSC_SUCCESS;
  }
  // With corner tracking the particle's domain (chi_p of Eq. 10) is the rectangle its corners
  // span: the weights integrate over that rectangle, whose centre may differ from the
  // material point's position by a fraction of its size.
  centre_.resize(2 * static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k) {
    const double *c = &p.corners[8 * k];
    centre_[2 * k] = cornerBoxCentre(c, 0);
    centre_[2 * k + 1] = cornerBoxCentre(c, 1);
  }
  grid_.buildStencils(p.n, centre_.data(), p.l, st_);
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::particleToGrid(const ParticleView &p, bool withMass, Vec P) {
  PetscScalar *mom = nullptr, *mass = nullptr;
  PetscCall(VecZeroEntries(sumW_));
  PetscCall(VecGetArray(sumW_, &mom));
  if (withMass) {
    PetscCall(VecZeroEntries(massW_));
    PetscCall(VecGetArray(massW_, &mass));
  }
  const PetscInt *start = st_.start.data(), *node = st_.node.data();
  const double *wx = st_.wx.data(), *wy = st_.wy.data();
  for (PetscInt k = 0; k < p.n; ++k) {
    const double mp = p.m[k], px = mp * p.v[2 * k], py = mp * p.v[2 * k + 1];
    for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
      const double w = wx[e] * wy[e];
      const PetscInt n = node[e];
      mom[2 * n] += w * px;
      mom[2 * n + 1] += w * py;
      if (mass) mass[2 * n] += w * mp;
    }
  }
  PetscCall(VecRestoreArray(sumW_, &mom));
  PetscCall(VecZeroEntries(P));
  PetscCall(grid_.addFromWindow(sumW_, P));
  if (withMass) {
    PetscCall(VecRestoreArray(massW_, &mass));
    PetscCall(VecZeroEntries(mass_));
    PetscCall(grid_.addFromWindow(massW_, mass_));
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::setConstraints() {
  // Grid-node constraints on level-0 grid lines, applied to the active nodes of every level.
  const int K = static_cast<int>(grid_.levels.size());
  std::vector<Vec> sub(K);
  PetscCall(VecSet(bcMask_, 1.0));
  PetscCall(DMCompositeGetAccessArray(grid_.dm, bcMask_, K, nullptr, sub.data()));
  for (size_t b = 0; b < sc_.bcs.size(); ++b) {
    const NodeBC &bc = sc_.bcs[b];
    const PetscInt line = grid_.lineIndex(bc.axis, bc.coord);
    if (line < 0) {
      const double o = bc.axis == 0 ? grid_.x0 : grid_.y0;
      PetscCall(DMCompositeRestoreAccessArray(grid_.dm, bcMask_, K, nullptr, sub.data()));
      throw InputError("option -gimp_bc" + std::to_string(b) + (bc.axis == 0 ? "_x " : "_y ") +
                       formatNumber(bc.coord) +
                       ": not on a level-0 grid line inside the domain (lines at " +
                       formatNumber(o) + " + i * " + formatNumber(grid_.h0()) + ")");
    }
    const Level &L0 = grid_.levels[0];
    const std::int64_t lineUnits = (bc.axis == 0 ? L0.u0 : L0.v0) + line * L0.step;
    for (int k = 0; k < K; ++k) {
      const Level &L = grid_.levels[k];
      PetscInt xs, ys, xm, ym;
      PetscScalar ***mk;
      PetscCall(DMDAGetCorners(L.da, &xs, &ys, nullptr, &xm, &ym, nullptr));
      PetscCall(DMDAVecGetArrayDOF(L.da, sub[k], &mk));
      for (PetscInt j = ys; j < ys + ym; ++j)
        for (PetscInt i = xs; i < xs + xm; ++i) {
          const std::int64_t u = bc.axis == 0 ? L.u0 + i * L.step : L.v0 + j * L.step;
          if (u != lineUnits || !grid_.nodeActive(k, i, j)) continue;
          const double along = bc.axis == 0 ? grid_.y0 + (L.v0 + j * L.step) * grid_.unit
                                            : grid_.x0 + (L.u0 + i * L.step) * grid_.unit;
          const double tol = 1e-9 * L.h;
          if (bc.hasRange && (along < bc.range[0] - tol || along > bc.range[1] + tol)) continue;
          for (int c = 0; c < 2; ++c)
            if (bc.fix[c]) mk[j][i][c] = 0.0;
        }
      PetscCall(DMDAVecRestoreArrayDOF(L.da, sub[k], &mk));
    }
  }
  PetscCall(DMCompositeRestoreAccessArray(grid_.dm, bcMask_, K, nullptr, sub.data()));
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::applyConstraintMask() {
  // mask = bcMask * (m > cutoff); invMass = mask / m. The mass sits in component 0.
  const PetscScalar *m = nullptr, *bc = nullptr;
  PetscScalar *mk = nullptr, *im = nullptr;
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(mass_, &nloc));
  PetscCall(VecGetArrayRead(mass_, &m));
  PetscCall(VecGetArrayRead(bcMask_, &bc));
  PetscCall(VecGetArray(mask_, &mk));
  PetscCall(VecGetArray(invMass_, &im));
  const double cut = sc_.massCutoff * meanParticleMass_;
  for (PetscInt i = 0; i < nloc; i += 2) {
    const bool has = m[i] > cut;
    for (int c = 0; c < 2; ++c) {
      mk[i + c] = has ? bc[i + c] : 0.0;
      im[i + c] = has && bc[i + c] != 0.0 ? 1.0 / m[i] : 0.0;
    }
  }
  PetscCall(VecRestoreArray(invMass_, &im));
  PetscCall(VecRestoreArray(mask_, &mk));
  PetscCall(VecRestoreArrayRead(bcMask_, &bc));
  PetscCall(VecRestoreArrayRead(mass_, &m));
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::internalAndExternalForces(const ParticleView &p, double t, Vec F) {
  PetscScalar *f = nullptr, *fe = nullptr;
  PetscCall(VecZeroEntries(sumW_));
  PetscCall(VecGetArray(sumW_, &f));
  const PetscInt *start = st_.start.data(), *node = st_.node.data();
  const double *wx = st_.wx.data(), *wy = st_.wy.data(), *gx = st_.gx.data(), *gy = st_.gy.data();
  // Internal force, Eq. 8: f_i = -sum_p sigma_p . grad S_ip V_p.
  for (PetscInt k = 0; k < p.n; ++k) {
    const double V = p.V[k], sxx = -V * p.s[4 * k], syy = -V * p.s[4 * k + 1],
                 sxy = -V * p.s[4 * k + 2];
    for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
      const double Sx = gx[e] * wy[e], Sy = wx[e] * gy[e];
      const PetscInt n = node[e];
      f[2 * n] += sxx * Sx + sxy * Sy;
      f[2 * n + 1] += sxy * Sx + syy * Sy;
    }
  }
  if (hasExternal_) {
    PetscCall(VecZeroEntries(extW_));
    PetscCall(VecGetArray(extW_, &fe));
    const double gxv = sc_.gravity[0], gyv = sc_.gravity[1];
    const bool gravity = gxv != 0 || gyv != 0;
    std::unique_ptr<mms::Skb1d> ex;
    if (sc_.mms == Mms::Skb1d) ex = std::make_unique<mms::Skb1d>(sc_);
    std::vector<double> factor(sc_.tractions.size());
    for (size_t q = 0; q < factor.size(); ++q)
      factor[q] = sc_.tractions[q].ramp.at(t);
    for (PetscInt k = 0; k < p.n; ++k) {
      // Body force, Eq. 8: f_i = sum_p m_p b S_ip.
      if (gravity || ex) {
        const double bx = gxv + (ex ? ex->bodyForce(p.X0[2 * k], t) : 0.0);
        const double fx = p.m[k] * bx, fy = p.m[k] * gyv;
        for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
          const double w = wx[e] * wy[e];
          fe[2 * node[e]] += w * fx;
          fe[2 * node[e] + 1] += w * fy;
        }
      }
      // Tractions, Eq. 8: tau S_i integrated exactly along the particle's loaded edge; the
      // tent across the edge is taken at the edge, the weight along it is the 1D weight. The
      // load is dead: its resultant is the traction times the initial edge length.
      for (int axis = 0; axis < 2; ++axis) {
        const PetscInt q = p.trac[2 * k + axis];
        if (q < 0) continue;
        const Traction &tr = sc_.tractions[q];
        const bool low = tr.side == Side::Left || tr.side == Side::Bottom;
        const double edge = p.x[2 * k + axis] + (low ? -1.0 : 1.0) * p.l[2 * k + axis];
        const double len = 2.0 * p.l0[2 * k + 1 - axis] * sc_.material.thickness;
        const double tx = tr.value[0] * factor[q] * len, ty = tr.value[1] * factor[q] * len;
        for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
          const PetscInt n = node[e];
          const double *z = &grid_.zone[4 * n];
          const double w = axis == 0 ? shape::tent(edge - grid_.X[n], z[0], z[1]) * wy[e]
                                     : wx[e] * shape::tent(edge - grid_.Y[n], z[2], z[3]);
          fe[2 * n] += w * tx;
          fe[2 * n + 1] += w * ty;
        }
      }
    }
    if (!sc_.dbcs.empty()) PetscCall(penaltyForces(p, t, fe));
    for (PetscInt i = 0; i < 2 * grid_.nWindow; ++i)
      f[i] += fe[i];
    PetscCall(VecRestoreArray(extW_, &fe));
    PetscCall(VecZeroEntries(fext_));
    PetscCall(grid_.addFromWindow(extW_, fext_));
  }
  PetscCall(VecRestoreArray(sumW_, &f));
  PetscCall(VecZeroEntries(F));
  PetscCall(grid_.addFromWindow(sumW_, F));
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::penaltyForces(const ParticleView &p, double t, double *fe) {
  // Eq. 9 on each particle edge that lies on a constrained segment: the traction sigma_p n and
  // the penalty -alpha (u - u_bar), per constrained component, integrated along the edge with
  // S_i (the tent across the edge at the edge, the 1D weight along it). u is the displacement
  // of the edge, u_p + (F - I) n l0: exact for a uniformly strained particle.
  const PetscInt *start = st_.start.data(), *node = st_.node.data();
  const double *wx = st_.wx.data(), *wy = st_.wy.data();
  std::vector<double> ubar(2 * sc_.dbcs.size());
  for (size_t q = 0; q < sc_.dbcs.size(); ++q)
    for (int c = 0; c < 2; ++c)
      ubar[2 * q + c] = sc_.dbcs[q].u[c].valueOr0(t);
  std::fill(reactions_.begin(), reactions_.end(), 0.0);
  std::fill(gaps_.begin(), gaps_.end(), 0.0);
  for (PetscInt k = 0; k < p.n; ++k)
    for (int a = 0; a < 2; ++a) {
      const PetscInt q = p.dbc[2 * k + a];
      if (q < 0) continue;
      const DisplacementBC &d = sc_.dbcs[q];
      const double n = d.normal();
      const double edge = p.x[2 * k + a] + n * p.l[2 * k + a];
      const double len = 2.0 * p.l[2 * k + 1 - a] * sc_.material.thickness;
      const double *F = &p.F[4 * k], *sg = &p.s[4 * k];
      const double alpha = alpha_ * d.penaltyScale;
      double force[2] = {0, 0};
      for (int c = 0; c < 2; ++c) {
        if (!d.fix[c]) continue;
        const double u = p.x[2 * k + c] - p.X0[2 * k + c] +
                         (F[2 * c + a] - (c == a ? 1.0 : 0.0)) * n * p.l0[2 * k + a];
        const double sigmaCA = !sc_.penaltyTraction ? 0.0 : c == a ? sg[c] : sg[2];
        force[c] = (sigmaCA * n - alpha * (u - ubar[2 * q + c])) * len;
        gaps_[q] = std::max(gaps_[q], std::fabs(u - ubar[2 * q + c]));
        reactions_[2 * q + c] += force[c];
      }
      for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
        const PetscInt nd = node[e];
        const double *z = &grid_.zone[4 * nd];
        const double w = a == 0 ? shape::tent(edge - grid_.X[nd], z[0], z[1]) * wy[e]
                                : wx[e] * shape::tent(edge - grid_.Y[nd], z[2], z[3]);
        fe[2 * nd] += w * force[0];
        fe[2 * nd + 1] += w * force[1];
      }
    }
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::reactionForces(std::vector<double> &out, std::vector<double> &gaps) {
  out.assign(reactions_.size(), 0.0);
  gaps.assign(gaps_.size(), 0.0);
  if (!reactions_.empty()) {
    PetscCallMPI(MPI_Allreduce(reactions_.data(), out.data(), static_cast<int>(out.size()),
                               MPI_DOUBLE, MPI_SUM, comm_));
    PetscCallMPI(MPI_Allreduce(gaps_.data(), gaps.data(), static_cast<int>(gaps.size()), MPI_DOUBLE,
                               MPI_MAX, comm_));
    for (size_t q = 0; q < gaps.size(); ++q)
      maxGap_[q] = std::max(maxGap_[q], gaps[q]);
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::moveCorners(ParticleView &p, double dt, Vec velocity) {
  // Each corner moves with the grid velocity interpolated at it, as a particle of the
  // fictitious size -gimp_corner_size times the particle's (the same velocity that moves the
  // particle centres, re-projected from the particles). Neighbours' shared corners get the
  // same velocity and stay together.
  const size_t n4 = 4 * static_cast<size_t>(p.n);
  cornerSize_.resize(2 * n4);
  for (PetscInt k = 0; k < p.n; ++k)
    for (int q = 0; q < 4; ++q) {
      cornerSize_[8 * k + 2 * q] = sc_.cornerSize * p.l0[2 * k];
      cornerSize_[8 * k + 2 * q + 1] = sc_.cornerSize * p.l0[2 * k + 1];
    }
  grid_.buildStencils(static_cast<PetscInt>(n4), p.corners, cornerSize_.data(), cst_);
  if (!massW2_) PetscCall(grid_.createWindowVec(&massW2_));
  PetscCall(grid_.toWindow(mass_, massW2_));
  const PetscScalar *vg = nullptr, *mg = nullptr;
  PetscCall(VecGetArrayRead(velocity, &vg));
  PetscCall(VecGetArrayRead(massW2_, &mg));
  const double cut = sc_.massCutoff * meanParticleMass_;
  const PetscInt *start = cst_.start.data(), *node = cst_.node.data();
  const double *wx = cst_.wx.data(), *wy = cst_.wy.data();
  for (size_t c = 0; c < n4; ++c) {
    double vx = 0, vy = 0, wsum = 0;
    for (PetscInt e = start[c]; e < start[c + 1]; ++e) {
      if (!(mg[2 * node[e]] > cut)) continue;
      const double w = wx[e] * wy[e];
      vx += w * vg[2 * node[e]];
      vy += w * vg[2 * node[e] + 1];
      wsum += w;
    }
    if (wsum > 0) {
      p.corners[2 * c] += dt * vx / wsum;
      p.corners[2 * c + 1] += dt * vy / wsum;
    }
  }
  PetscCall(VecRestoreArrayRead(massW2_, &mg));
  PetscCall(VecRestoreArrayRead(velocity, &vg));
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::separation(double t, PetscInt step, double &gap, double &strain) {
  // Gap between particles that started as neighbours (same size, side by side), relative to
  // their size, and the body's engineering strain along x (extent of all particles).
  ParticleView p;
  PetscCall(p.get(sw_));
  constexpr int kCols = 9;
  std::vector<double> loc(static_cast<size_t>(p.n) * kCols);
  for (PetscInt k = 0; k < p.n; ++k) {
    double *r = &loc[static_cast<size_t>(k) * kCols];
    r[0] = static_cast<double>(p.id[k]);
    for (int d = 0; d < 2; ++d) {
      // The particle's domain: centred on the material point, or the corners' rectangle.
      double centre = p.x[2 * k + d];
      if (p.hasCorners) centre = cornerBoxCentre(&p.corners[8 * k], d);
      r[1 + d] = p.X0[2 * k + d];
      r[3 + d] = centre;
      r[5 + d] = p.l[2 * k + d];
      r[7 + d] = p.l0[2 * k + d];
    }
  }
  PetscCall(p.restore(sw_));
  std::vector<double> all;
  PetscCall(gatherToRoot(loc, all));
  double res[2] = {0, 0};
  if (rank_ == 0) {
    const size_t n = all.size() / kCols;
    const double q = grid_.unit / 512.0; // initial positions lie on a lattice of this step
    auto key = [q](double x, double y) {
      return std::make_pair(std::llround(x / q), std::llround(y / q));
    };
    std::map<std::pair<long long, long long>, size_t> at;
    double lo = 1e300, hi = -1e300, lo0 = 1e300, hi0 = -1e300;
    for (size_t i = 0; i < n; ++i) {
      const double *r = &all[i * kCols];
      at[key(r[1], r[2])] = i;
      lo = std::min(lo, r[3] - r[5]);
      hi = std::max(hi, r[3] + r[5]);
      lo0 = std::min(lo0, r[1] - r[7]);
      hi0 = std::max(hi0, r[1] + r[7]);
    }
    double worst = 0;
    for (size_t i = 0; i < n; ++i) {
      const double *r = &all[i * kCols];
      for (int d = 0; d < 2; ++d) {
        const auto it = at.find(key(r[1] + (d == 0) * 2 * r[7], r[2] + (d == 1) * 2 * r[8]));
        if (it == at.end()) continue;
        const double *o = &all[it->second * kCols];
        if (o[7 + d] != r[7 + d]) continue; // neighbours of another size (another level)
        const double g = ((o[3 + d] - o[5 + d]) - (r[3 + d] + r[5 + d])) / (2.0 * r[7 + d]);
        worst = std::max(worst, g);
      }
    }
    res[0] = worst;
    res[1] = (hi - lo) / (hi0 - lo0) - 1.0;
  }
  PetscCallMPI(MPI_Bcast(res, 2, MPI_DOUBLE, 0, comm_));
  gap = res[0];
  strain = res[1];
  maxStrain_ = std::max(maxStrain_, strain);
  maxSeparation_ = std::max(maxSeparation_, gap);
  if (gap > sc_.separationThreshold && std::isnan(separationStrain_)) {
    separationStrain_ = strain;
    PetscCall(PetscPrintf(comm_,
                          "gimp: warning: step %" PetscInt_FMT " t %.6g s: particles separated: "
                          "a gap of %.3g particle sizes between former neighbours (threshold "
                          "%.3g) at engineering strain %.4g\n",
                          step, t, gap, sc_.separationThreshold, strain));
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::gridToParticle(ParticleView &p, double dt) {
  const PetscScalar *vg = nullptr, *ag = nullptr;
  PetscCall(VecGetArrayRead(velW_, &vg));
  PetscCall(VecGetArrayRead(accW_, &ag));
  const PetscInt *start = st_.start.data(), *node = st_.node.data();
  const double *wx = st_.wx.data(), *wy = st_.wy.data();
  const double flip = sc_.flip;
  for (PetscInt k = 0; k < p.n; ++k) {
    double vx = 0, vy = 0, ax = 0, ay = 0;
    for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
      const double w = wx[e] * wy[e];
      const PetscInt n = node[e];
      vx += w * vg[2 * n];
      vy += w * vg[2 * n + 1];
      ax += w * ag[2 * n];
      ay += w * ag[2 * n + 1];
    }
    p.v[2 * k] = flip * (p.v[2 * k] + dt * ax) + (1.0 - flip) * vx;
    p.v[2 * k + 1] = flip * (p.v[2 * k + 1] + dt * ay) + (1.0 - flip) * vy;
    p.x[2 * k] += dt * vx;
    p.x[2 * k + 1] += dt * vy;
  }
  PetscCall(VecRestoreArrayRead(accW_, &ag));
  PetscCall(VecRestoreArrayRead(velW_, &vg));
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::updateStress(ParticleView &p, Vec Vwindow, double dt) {
  const PetscScalar *vg = nullptr;
  L_.resize(4 * static_cast<size_t>(p.n));
  PetscCall(VecGetArrayRead(Vwindow, &vg));
  const PetscInt *start = st_.start.data(), *node = st_.node.data();
  const double *wx = st_.wx.data(), *wy = st_.wy.data(), *gx = st_.gx.data(), *gy = st_.gy.data();
  for (PetscInt k = 0; k < p.n; ++k) {
    double lxx = 0, lxy = 0, lyx = 0, lyy = 0;
    for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
      const double Sx = gx[e] * wy[e], Sy = wx[e] * gy[e];
      const PetscInt n = node[e];
      lxx += vg[2 * n] * Sx;
      lxy += vg[2 * n] * Sy;
      lyx += vg[2 * n + 1] * Sx;
      lyy += vg[2 * n + 1] * Sy;
    }
    L_[4 * k] = lxx;
    L_[4 * k + 1] = lxy;
    L_[4 * k + 2] = lyx;
    L_[4 * k + 3] = lyy;
  }
  PetscCall(VecRestoreArrayRead(Vwindow, &vg));
  const Material &mat = sc_.material;
  for (PetscInt k = 0; k < p.n; ++k) {
    const double *Lk = &L_[4 * k];
    double *F = &p.F[4 * k];
    const double f0 = F[0], f1 = F[1], f2 = F[2], f3 = F[3];
    F[0] = f0 + dt * (Lk[0] * f0 + Lk[1] * f2);
    F[1] = f1 + dt * (Lk[0] * f1 + Lk[1] * f3);
    F[2] = f2 + dt * (Lk[2] * f0 + Lk[3] * f2);
    F[3] = f3 + dt * (Lk[2] * f1 + Lk[3] * f3);
    p.V[k] = (F[0] * F[3] - F[1] * F[2]) * p.V0[k];
    if (mat.model == MaterialModel::Linear)
      material::jaumannUpdate(mat, Lk, dt, &p.s[4 * k]);
    else
      material::neoHookeanStress(mat, F, &p.s[4 * k]);
    switch (sc_.tracking) {
    case Tracking::None:
      break;
    case Tracking::Strain:
      p.eps[2 * k] += dt * Lk[0];
      p.eps[2 * k + 1] += dt * Lk[3];
      p.l[2 * k] = (1.0 + p.eps[2 * k]) * p.l0[2 * k];
      p.l[2 * k + 1] = (1.0 + p.eps[2 * k + 1]) * p.l0[2 * k + 1];
      break;
    case Tracking::Stretch:
      p.l[2 * k] = std::sqrt(F[0] * F[0] + F[2] * F[2]) * p.l0[2 * k];
      p.l[2 * k + 1] = std::sqrt(F[1] * F[1] + F[3] * F[3]) * p.l0[2 * k + 1];
      break;
    case Tracking::Corners: {
      p.eps[2 * k] += dt * Lk[0];
      p.eps[2 * k + 1] += dt * Lk[3];
      double *c = &p.corners[8 * k];
      // Exterior corners of a particle on a loaded edge follow its strain (the paper, 4.2).
      for (int a = 0; a < 2; ++a) {
        if (p.trac[2 * k + a] < 0) continue;
        const double n = sc_.tractions[p.trac[2 * k + a]].normal();
        for (int q = 0; q < 4; ++q) {
          const double sx = (q == 1 || q == 2) ? 1.0 : -1.0, sy = q >= 2 ? 1.0 : -1.0;
          if ((a == 0 ? sx : sy) != n) continue;
          c[2 * q] = p.x[2 * k] + sx * (1.0 + p.eps[2 * k]) * p.l0[2 * k];
          c[2 * q + 1] = p.x[2 * k + 1] + sy * (1.0 + p.eps[2 * k + 1]) * p.l0[2 * k + 1];
        }
      }
      // The particle is the axis-aligned rectangle spanned by its corners; its volume is the
      // area of the quadrilateral they form.
      const double xmin = std::min({c[0], c[2], c[4], c[6]}),
                   xmax = std::max({c[0], c[2], c[4], c[6]});
      const double ymin = std::min({c[1], c[3], c[5], c[7]}),
                   ymax = std::max({c[1], c[3], c[5], c[7]});
      p.l[2 * k] = 0.5 * (xmax - xmin);
      p.l[2 * k + 1] = 0.5 * (ymax - ymin);
      const double area = 0.5 * ((c[0] * c[3] - c[2] * c[1]) + (c[2] * c[5] - c[4] * c[3]) +
                                 (c[4] * c[7] - c[6] * c[5]) + (c[6] * c[1] - c[0] * c[7]));
      p.V[k] = area * sc_.material.thickness;
      break;
    }
    }
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::checkParticles(const ParticleView &p, PetscInt step, double t) {
  const double *d = sc_.domain.data();
  const double h0 = grid_.h0();
  PetscInt bad = -1;
  for (PetscInt k = 0; k < p.n; ++k) {
    const double x = p.x[2 * k], y = p.x[2 * k + 1], lx = p.l[2 * k], ly = p.l[2 * k + 1];
    const double s = p.s[4 * k] + p.s[4 * k + 1] + p.s[4 * k + 2];
    // NaN fails every comparison: the test is written so that it lands in the bad branch.
    const bool ok = std::isfinite(x + y + s) && x - lx >= d[0] && x + lx <= d[2] &&
                    y - ly >= d[1] && y + ly <= d[3] && lx > 0 && ly > 0 && lx <= h0 && ly <= h0;
    if (!ok) {
      bad = k;
      break;
    }
  }
  if (bad >= 0) {
    const PetscInt k = bad;
    const double x = p.x[2 * k], y = p.x[2 * k + 1], lx = p.l[2 * k], ly = p.l[2 * k + 1];
    std::string why;
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(p.s[4 * k]) ||
        !std::isfinite(p.s[4 * k + 1]) || !std::isfinite(p.s[4 * k + 2]))
      why = "its position or stress is not finite: the run went unstable (reduce -ts_dt)";
    else if (x - lx < d[0] || x + lx > d[2] || y - ly < d[1] || y + ly > d[3])
      why = "it left the grid domain (enlarge -gimp_domain or -gimp_pad)";
    else
      why = "its half-size (" + formatNumber(lx) + ", " + formatNumber(ly) +
            ") is not in (0, h0]: the particle is inverted or stretched beyond one level-0 cell";
    failed_ = true;
    PetscCall(PetscSynchronizedFPrintf(comm_, PETSC_STDERR,
                                       "gimp: error: step %" PetscInt_FMT
                                       " t %.9g s: particle %" PetscInt64_FMT
                                       " at (%.9g, %.9g): %s\n",
                                       step, t, p.id[k], x, y, why.c_str()));
  }
  PetscCall(PetscSynchronizedFlush(comm_, PETSC_STDERR));
  return PETSC_SUCCESS;
}

// ---------------------------------------------------------------------------------------------
// Diagnostics

PetscErrorCode Simulation::energies(Energies &e) {
  ParticleView p;
  PetscCall(p.get(sw_));
  double loc[4] = {0, 0, 0, 0}, glob[4];
  for (PetscInt k = 0; k < p.n; ++k) {
    const double vx = p.v[2 * k], vy = p.v[2 * k + 1];
    loc[0] += 0.5 * p.m[k] * (vx * vx + vy * vy);
    loc[1] += material::strainEnergy(sc_.material, &p.s[4 * k], &p.F[4 * k], p.V0[k], p.V[k]);
    loc[2] += p.m[k] * vx;
    loc[3] += p.m[k] * vy;
  }
  PetscCall(p.restore(sw_));
  PetscCallMPI(MPI_Allreduce(loc, glob, 4, MPI_DOUBLE, MPI_SUM, comm_));
  e.kinetic = glob[0];
  e.strain = glob[1];
  e.momentum[0] = glob[2];
  e.momentum[1] = glob[3];
  e.externalWork = extWork_;
  e.damping = dampWork_;
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::probes(std::vector<ProbeState> &out) {
  ParticleView p;
  PetscCall(p.get(sw_));
  out = probeIds_;
  std::vector<double> loc(out.size() * 8, 0.0), glob(out.size() * 8, 0.0);
  for (PetscInt k = 0; k < p.n; ++k)
    for (size_t q = 0; q < out.size(); ++q)
      if (p.id[k] == out[q].id) {
        double *r = &loc[8 * q];
        r[0] = p.X0[2 * k];
        r[1] = p.X0[2 * k + 1];
        r[2] = p.x[2 * k] - p.X0[2 * k];
        r[3] = p.x[2 * k + 1] - p.X0[2 * k + 1];
        for (int c = 0; c < 4; ++c)
          r[4 + c] = p.s[4 * k + c];
      }
  PetscCall(p.restore(sw_));
  PetscCallMPI(MPI_Allreduce(loc.data(), glob.data(), static_cast<int>(loc.size()), MPI_DOUBLE,
                             MPI_SUM, comm_));
  for (size_t q = 0; q < out.size(); ++q) {
    const double *r = &glob[8 * q];
    out[q].X0[0] = r[0];
    out[q].X0[1] = r[1];
    out[q].u[0] = r[2];
    out[q].u[1] = r[3];
    for (int c = 0; c < 4; ++c)
      out[q].stress[c] = r[4 + c];
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::mmsErrors(double t, double &linf, double &rms) {
  linf = rms = 0;
  if (sc_.mms == Mms::None) return PETSC_SUCCESS;
  const mms::Skb1d ex(sc_);
  ParticleView p;
  PetscCall(p.get(sw_));
  double loc[3] = {0, 0, 0}, glob[3];
  for (PetscInt k = 0; k < p.n; ++k) {
    const double X = p.X0[2 * k];
    const double ex_ = p.x[2 * k] - X - ex.u(X, t), ey = p.x[2 * k + 1] - p.X0[2 * k + 1];
    const double e2 = ex_ * ex_ + ey * ey;
    loc[0] = std::max(loc[0], std::sqrt(e2));
    loc[1] += e2 * p.V0[k];
    loc[2] += p.V0[k];
  }
  PetscCall(p.restore(sw_));
  PetscCallMPI(MPI_Allreduce(&loc[0], &glob[0], 1, MPI_DOUBLE, MPI_MAX, comm_));
  PetscCallMPI(MPI_Allreduce(&loc[1], &glob[1], 2, MPI_DOUBLE, MPI_SUM, comm_));
  linf = glob[0];
  rms = std::sqrt(glob[1] / glob[2]);
  mmsLinf_ = std::max(mmsLinf_, linf);
  mmsRms_ = std::max(mmsRms_, rms);
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::gatherToRoot(const std::vector<double> &loc, std::vector<double> &all) {
  // Every rank's rows, concatenated on rank 0 (empty elsewhere): for dumps and measures that
  // need all particles at once.
  const int mine = static_cast<int>(loc.size());
  std::vector<int> counts(size_), displs(size_, 0);
  PetscCallMPI(MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_));
  all.clear();
  if (rank_ == 0) {
    for (int r = 1; r < size_; ++r)
      displs[r] = displs[r - 1] + counts[r - 1];
    all.resize(static_cast<size_t>(displs.back() + counts.back()));
  }
  PetscCallMPI(MPI_Gatherv(loc.data(), mine, MPI_DOUBLE, all.data(), counts.data(), displs.data(),
                           MPI_DOUBLE, 0, comm_));
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::particleCount(PetscInt64 &n) {
  PetscInt nl = 0;
  PetscCall(DMSwarmGetLocalSize(sw_, &nl));
  PetscInt64 loc = nl;
  PetscCallMPI(MPI_Allreduce(&loc, &n, 1, MPI_INT64_T, MPI_SUM, comm_));
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::holeMeasure(const std::string &dir, double &kt, double &ktEdge) {
  const double cx = sc_.hole[0], cy = sc_.hole[1], r = sc_.hole[2], pload = sc_.holeLoad;
  ParticleView p;
  PetscCall(p.get(sw_));
  std::vector<double> loc; // angle [deg], distance to the centre, hoop / p, particle half-size
  for (PetscInt k = 0; k < p.n; ++k) {
    const double dx = p.x[2 * k] - cx, dy = p.x[2 * k + 1] - cy, d = std::hypot(dx, dy);
    const double l = std::max(p.l[2 * k], p.l[2 * k + 1]);
    if (d - r > 3.0 * l) continue; // the first few layers of particles next to the hole
    const double c = dx / d, s = dy / d;
    const double *sg = &p.s[4 * k];
    const double hoop = sg[0] * s * s - 2.0 * sg[2] * s * c + sg[1] * c * c;
    loc.insert(loc.end(), {std::atan2(dy, dx) * 180.0 / M_PI, d, hoop / pload, l});
  }
  PetscCall(p.restore(sw_));
  std::vector<double> all;
  PetscCall(gatherToRoot(loc, all));
  double res[2] = {std::numeric_limits<double>::quiet_NaN(),
                   std::numeric_limits<double>::quiet_NaN()};
  if (rank_ == 0 && !all.empty()) {
    const size_t n = all.size() / 4;
    // First layer: particles within one particle size of the edge (their domains touch it).
    std::vector<size_t> first, ray;
    for (size_t i = 0; i < n; ++i) {
      if (all[4 * i + 1] - r <= 1.5 * all[4 * i + 3]) first.push_back(i);
      // On the 90-degree ray: distance to it within one particle half-size (and a half).
      if (std::fabs(std::sin((all[4 * i] - 90.0) * M_PI / 180.0)) * all[4 * i + 1] <=
          1.5 * all[4 * i + 3])
        ray.push_back(i);
    }
    std::sort(first.begin(), first.end(),
              [&](size_t a, size_t b) { return all[4 * a] < all[4 * b]; });
    FILE *f = std::fopen((dir + "/hoop.csv").c_str(), "w");
    if (f) {
      std::fprintf(f, "angle_deg,r,hoop_over_p,kirsch\n");
      for (size_t i : first) {
        const double th = all[4 * i] * M_PI / 180.0, rr = all[4 * i + 1];
        const double a2 = r * r / (rr * rr);
        const double kirsch = 0.5 * (1 + a2) - 0.5 * (1 + 3 * a2 * a2) * std::cos(2 * th);
        std::fprintf(f, "%.6f,%.9e,%.9e,%.9e\n", all[4 * i], rr, all[4 * i + 2], kirsch);
      }
      std::fclose(f);
    }
    // kt: the particle on the 90-degree ray nearest to the edge, and the linear extrapolation
    // to the edge from the two nearest distinct radii on that ray.
    std::sort(ray.begin(), ray.end(),
              [&](size_t a, size_t b) { return all[4 * a + 1] < all[4 * b + 1]; });
    if (!ray.empty()) {
      res[0] = all[4 * ray[0] + 2];
      for (size_t j = 1; j < ray.size(); ++j) {
        const double r1 = all[4 * ray[0] + 1], r2 = all[4 * ray[j] + 1];
        if (r2 - r1 < 0.5 * all[4 * ray[0] + 3]) continue;
        const double s1 = res[0], s2 = all[4 * ray[j] + 2];
        res[1] = s1 + (s1 - s2) * (r1 - r) / (r2 - r1);
        break;
      }
    }
  }
  // The hoop stress by angle: the first-layer particle nearest to 0, 15, ..., 90 degrees.
  double hoop[kHoopAngles];
  for (int a = 0; a < kHoopAngles; ++a)
    hoop[a] = std::numeric_limits<double>::quiet_NaN();
  if (rank_ == 0 && !all.empty()) {
    const size_t n = all.size() / 4;
    for (int a = 0; a < kHoopAngles; ++a) {
      double best = 1e300;
      for (size_t i = 0; i < n; ++i) {
        if (all[4 * i + 1] - r > 1.5 * all[4 * i + 3]) continue; // first layer only
        const double d = std::fabs(all[4 * i] - 15.0 * a);
        if (d < best) {
          best = d;
          hoop[a] = all[4 * i + 2];
        }
      }
    }
  }
  PetscCallMPI(MPI_Bcast(res, 2, MPI_DOUBLE, 0, comm_));
  PetscCallMPI(MPI_Bcast(hoop, kHoopAngles, MPI_DOUBLE, 0, comm_));
  kt = res[0];
  ktEdge = res[1];
  hoopByAngle_.assign(hoop, hoop + kHoopAngles);
  return PETSC_SUCCESS;
}

PetscErrorCode Simulation::writeParticleDump(const std::string &file) {
  // Gather id and state on rank 0, sorted by id: rank-independent for comparisons.
  constexpr int kCols = 12;
  ParticleView p;
  PetscCall(p.get(sw_));
  std::vector<double> loc(static_cast<size_t>(p.n) * kCols);
  for (PetscInt k = 0; k < p.n; ++k) {
    double *r = &loc[static_cast<size_t>(k) * kCols];
    r[0] = static_cast<double>(p.id[k]);
    r[1] = p.x[2 * k];
    r[2] = p.x[2 * k + 1];
    r[3] = p.v[2 * k];
    r[4] = p.v[2 * k + 1];
    for (int c = 0; c < 4; ++c)
      r[5 + c] = p.s[4 * k + c];
    r[9] = p.V[k];
    r[10] = p.l[2 * k];
    r[11] = p.l[2 * k + 1];
  }
  PetscCall(p.restore(sw_));
  std::vector<double> all;
  PetscCall(gatherToRoot(loc, all));
  if (rank_ != 0) return PETSC_SUCCESS;
  const size_t n = all.size() / kCols;
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return all[a * kCols] < all[b * kCols]; });
  FILE *f = std::fopen(file.c_str(), "w");
  if (!f) throw InputError("option -gimp_particle_dump " + file + ": cannot open for writing");
  std::fprintf(f, "id,x,y,vx,vy,sxx,syy,sxy,szz,V,lx,ly\n");
  for (size_t i : order) {
    const double *r = &all[i * kCols];
    std::fprintf(f, "%.0f", r[0]);
    for (int c = 1; c < kCols; ++c)
      std::fprintf(f, ",%.17g", r[c]);
    std::fprintf(f, "\n");
  }
  std::fclose(f);
  return PETSC_SUCCESS;
}

} // namespace gimp
