// One explicit GIMP run: the scene, the grid, the particles and PETSc's TS.
//
// Nodal momentum is the TS solution (a DMDA global Vec). TS type euler advances it with
// RHS = f_int + f_b + f_tau - d p (Eq. 8 and Eq. 16). Particle-to-grid runs in the TS
// pre-step, grid-to-particle and the stress update in the post-step.
#pragma once

#include "gimp/grid.hpp"
#include "gimp/particles.hpp"
#include "gimp/scene.hpp"

#include <petscts.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace gimp {

class Output;

struct Energies {
  double kinetic = 0, strain = 0, externalWork = 0, damping = 0;
  double momentum[2] = {0, 0};
  double total() const { return kinetic + strain - externalWork + damping; }
};

struct ProbeState {
  PetscInt64 id = -1;
  double X0[2] = {0, 0}, u[2] = {0, 0}, stress[4] = {0, 0, 0, 0};
};

class Simulation {
public:
  explicit Simulation(MPI_Comm comm);
  ~Simulation();
  Simulation(const Simulation &) = delete;
  Simulation &operator=(const Simulation &) = delete;

  /// Read the scene, build grid, particles and TS; validate everything (collective).
  PetscErrorCode setup();
  /// Run TSSolve and write the final outputs.
  PetscErrorCode run();

  const Scene &scene() const { return sc_; }
  /// True when the run stopped early because it went unstable.
  bool failed() const { return failed_; }

private:
  // TS callbacks
  static PetscErrorCode preStep(TS ts);
  static PetscErrorCode postStep(TS ts);
  static PetscErrorCode rhs(TS ts, PetscReal t, Vec X, Vec F, void *ctx);

  PetscErrorCode migrate();
  PetscErrorCode computeStencils(const ParticleView &p);
  PetscErrorCode particleToGrid(const ParticleView &p, bool withMass, Vec P);
  PetscErrorCode nodalVelocity(Vec P, Vec Vout);
  PetscErrorCode internalAndExternalForces(const ParticleView &p, double t, Vec F);
  PetscErrorCode penaltyForces(const ParticleView &p, double t, double *fe);
  PetscErrorCode gridToParticle(ParticleView &p, double dt);
  PetscErrorCode moveCorners(ParticleView &p, double dt, Vec velocity);
  PetscErrorCode updateStress(ParticleView &p, Vec Vlocal, double dt);
  PetscErrorCode checkParticles(const ParticleView &p, PetscInt step, double t);
  PetscErrorCode applyConstraintMask();
  PetscErrorCode setConstraints();

public:
  // Diagnostics used by monitors and output.
  PetscErrorCode energies(Energies &e);
  PetscErrorCode probes(std::vector<ProbeState> &out);
  PetscErrorCode mmsErrors(double t, double &linf, double &rms);
  PetscErrorCode particleCount(PetscInt64 &n);
  /// Concatenate every rank's rows on rank 0.
  PetscErrorCode gatherToRoot(const std::vector<double> &loc, std::vector<double> &all);
  /// Largest gap between former neighbours / particle size, and the engineering strain of the
  /// particles' extent along x; warns once when the gap first exceeds the threshold.
  PetscErrorCode separation(double t, PetscInt step, double &gap, double &strain);
  /// Force of each penalty displacement condition on the body at the last RHS (fx, fy per
  /// condition, summed over ranks) and its largest constraint violation |u - u_bar| there.
  PetscErrorCode reactionForces(std::vector<double> &out, std::vector<double> &gaps);
  PetscErrorCode writeParticleDump(const std::string &file);
  /// Hoop stress / p of the particles next to the hole (-gimp_hole_measure), by angle from
  /// the load axis, written to hoop.csv; kt at 90 degrees: the nearest particle's value and
  /// its linear extrapolation to the hole edge along the 90-degree ray.
  PetscErrorCode holeMeasure(const std::string &dir, double &kt, double &ktEdge);

private:
  MPI_Comm comm_;
  PetscMPIInt rank_ = 0, size_ = 1;
  Scene sc_;
  Grid grid_;
  DM sw_ = nullptr;
  TS ts_ = nullptr;

  // Nodal vectors: global (composite of the levels, dof 2) and window (W) vectors.
  Vec P_ = nullptr;       // momentum: the TS solution
  Vec mass_ = nullptr;    // nodal mass, in component 0 (dof layout of the momentum)
  Vec vel_ = nullptr;     // nodal velocity
  Vec acc_ = nullptr;     // nodal acceleration
  Vec force_ = nullptr;   // last RHS (total nodal force incl. damping)
  Vec fext_ = nullptr;    // external nodal force (tractions + body force), if the scene has any
  Vec bcMask_ = nullptr;  // 1 free, 0 constrained, per dof
  Vec mask_ = nullptr;    // bcMask_ times (node has mass)
  Vec invMass_ = nullptr; // mask_ / mass
  Vec massW_ = nullptr, sumW_ = nullptr, velW_ = nullptr, accW_ = nullptr, extW_ = nullptr;
  Vec massW2_ = nullptr; // nodal mass on the window (corner tracking)

  Stencils st_;           // particle -> node weights, rebuilt each step
  std::vector<double> L_; // velocity gradient per particle (xx, xy, yx, yy)

  // Energy accounting.
  double extWork_ = 0, dampWork_ = 0;
  double alpha_ = 0;              // penalty of Eq. 9 in use [Pa/m]
  std::vector<double> reactions_; // this rank's part of each condition's force (fx, fy)
  std::vector<double> gaps_;      // this rank's largest |u - u_bar| per condition
  std::vector<double> maxGap_;    // largest violation per condition over the history rows
  double kick_ = 1.0;
  Stencils cst_;                   // corner stencils (corner tracking)
  std::vector<double> cornerSize_; // fictitious corner half-sizes
  std::vector<double> centre_;     // centres of the corner rectangles (particle domains)
  double separationStrain_ = std::numeric_limits<double>::quiet_NaN();
  double maxStrain_ = 0,
         maxSeparation_ = 0; // fraction of the force applied this step (0.5 on a leapfrog start)
  double extPowerStart_ = 0, dampPowerStart_ = 0;
  double meanParticleMass_ = 0;
  bool hasExternal_ = false;

  std::vector<ProbeState> probeIds_;
  double mmsLinf_ = 0, mmsRms_ = 0;
  PetscInt64 nParticles_ = 0;
  PetscInt64 migrated_ = 0; // particles that changed rank, summed over the run
  std::unique_ptr<Output> out_;
  PetscLogStage stageP2G_ = 0, stageForces_ = 0, stageGrid_ = 0, stageG2P_ = 0, stageStress_ = 0,
                stageOutput_ = 0;
  PetscLogDouble wall0_ = 0;
  bool failed_ = false;
  bool atRest_ = false;                 // stopped by the rest criterion (-gimp_static_tol)
  static constexpr int kHoopAngles = 7; // hoop stress samples at 0, 15, ..., 90 degrees
  std::vector<double> hoopByAngle_;
  friend class Output;
};

} // namespace gimp
