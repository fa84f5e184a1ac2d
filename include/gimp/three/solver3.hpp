// The 3D solver (-gimp_dim 3): the same explicit GIMP step as the 2D Solver, on GridT<3> with
// the dimension-generic kernels (transfer::*, physics::internalForce, Stencils<3>) and the 3D
// materials. Its step is the 2D step's phases without what 3D scenes do not model (cracks, the
// multi-rate step, corner and CPDI tracking, XPIC):
//
//   migrate -> stencils -> P2G -> forces -> grid update (TSStep) -> G2P (+ re-projection) ->
//   work -> stress -> checks -> report
//
// Nodal momentum is the TS solution (a DMComposite of 3D DMDAs of dof 3); TS euler advances it
// with RHS = kick * mask * (f_int + f_ext - d p), as in 2D.
#pragma once

#include "gimp/diagnostics/energy_watch.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"
#include "gimp/solver/step_common.hpp"

#include <petscts.h>

#include <cstdio>
#include <string>
#include <vector>

namespace gimp::three {

/// Energies, momentum and work of a 3D run (summed over ranks).
struct Energies3 {
  double kinetic = 0, strain = 0, externalWork = 0, damping = 0;
  double momentum[3] = {0, 0, 0};
  double mass = 0; // of all particles
  double total() const { return kinetic + strain - externalWork + damping; }
};

/// A probe's state: the nearest particle's displacement and stress (xx, yy, zz, yz, xz, xy).
struct ProbeState3 {
  double u[3] = {0, 0, 0}, s[6] = {0, 0, 0, 0, 0, 0};
};

class Solver3 {
public:
  explicit Solver3(MPI_Comm comm) : comm_(comm) {}
  ~Solver3();
  Solver3(const Solver3 &) = delete;
  Solver3 &operator=(const Solver3 &) = delete;

  /// Read the 3D scene, build the grid, the particles and TS (collective).
  PetscErrorCode setup();
  /// Step to TS's step or time limit or a failure; final outputs.
  PetscErrorCode run();
  bool failed() const { return failed_; }
  /// The stop signal (SIGINT or SIGTERM) that ended the run, agreed over the ranks; 0 if none.
  int interrupted() const { return interrupt_; }

private:
  static PetscErrorCode rhs(TS ts, PetscReal t, Vec X, Vec F, void *ctx);
  PetscErrorCode createNodal();
  PetscErrorCode nodeConstraints();
  PetscErrorCode step();
  PetscErrorCode migrate();
  /// Order this rank's particles by level-0 cell (x fastest), then id, as the 2D step does.
  PetscErrorCode sortParticles();
  PetscErrorCode particlesToGrid(const ParticleView<3> &p);
  PetscErrorCode forces(const ParticleView<3> &p, const StepClock &c);
  PetscErrorCode gridUpdate();
  PetscErrorCode gridToParticles(ParticleView<3> &p, const StepClock &c);
  PetscErrorCode stress(ParticleView<3> &p, double dt);
  /// Tractions, gravity and the penalty conditions (Eq. 9) into the window array fe.
  void externalForces(const ParticleView<3> &p, double t, double *fe);
  PetscErrorCode checks(const ParticleView<3> &p, PetscInt step, double t);
  PetscErrorCode report(PetscInt step, double t, bool last);
  PetscErrorCode energies(Energies3 &e);
  PetscErrorCode probes(std::vector<ProbeState3> &out);
  PetscErrorCode reactions(std::vector<double> &force);
  /// What a history row and the summary report: energies, probes and reactions (collective).
  PetscErrorCode reportState(Energies3 &e, std::vector<ProbeState3> &pr, std::vector<double> &rf);
  /// The displacement error against the manufactured solution (-gimp_mms) at time t; keeps the
  /// largest of each norm in mmsMax_.
  PetscErrorCode mmsErrors(double t, double &linf, double &rms);
  // output (three/output3.cpp)
  PetscErrorCode openOutput();
  PetscErrorCode writeHistory(PetscInt step, double t);
  PetscErrorCode writeFields(PetscInt step, double t);
  PetscErrorCode writeSummary(const std::string &status, PetscInt steps, double t);
  PetscErrorCode writeXdmf();
  struct Frame;
  void particleXdmf(FILE *f, const Frame &fr) const;
  void gridXdmf(FILE *f, const Frame &fr) const;
  PetscErrorCode writeParticleDump(); // -gimp_particle_dump, collective

  MPI_Comm comm_;
  PetscMPIInt rank_ = 0, size_ = 1;
  Scene<3> sc_;
  Grid<3> grid_;
  DM sw_ = nullptr;
  TS ts_ = nullptr;
  Stencils<3> st_;
  // Global nodal Vecs (dof 3) and window Vecs.
  Vec P_ = nullptr, mass_ = nullptr, vel_ = nullptr, acc_ = nullptr, f_ = nullptr, fext_ = nullptr,
      rhs_ = nullptr, bcMask_ = nullptr, mask_ = nullptr, invMass_ = nullptr;
  Vec sumW_ = nullptr, massW_ = nullptr, velW_ = nullptr, accW_ = nullptr, extW_ = nullptr;
  std::vector<double> slotX_;          // window coordinates of every slot (APIC, face forces)
  bool external_ = false;              // the scene has body forces, tractions or penalty conditions
  double alpha_ = 0;                   // penalty of Eq. 9 [Pa/m]
  std::vector<double> reactionsLocal_; // this rank's part of each penalty condition's force
  double powerExt0_ = 0, powerDamp0_ = 0; // external and damping power at the step's start
  double workExt_ = 0, workDamp_ = 0;
  std::vector<PetscInt64> probeIds_;
  PetscInt64 nParticles_ = 0;
  double meanParticleMass_ = 0;
  PetscInt64 migrated_ = 0;
  double mmsMax_[2] = {0, 0}; // largest L-inf and RMS errors of the manufactured solution
  std::string localFailure_;
  bool failed_ = false;
  int interrupt_ = 0;
  PetscInt64 leaving_ = -1; // particles outside their rank's cells at the last check (-1: unknown)
  std::string failure_;
  EnergyWatch energyWatch_; // the energy balance at the history rows (writeHistory)
  struct Frame {
    PetscInt step;
    double t;
    long long particles;
  };
  std::vector<Frame> frames_;
  FILE *history_ = nullptr;
  PetscLogDouble wall0_ = 0;
  StepStages stages_;
};

} // namespace gimp::three
