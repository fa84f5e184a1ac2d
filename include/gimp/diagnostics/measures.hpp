// What a run measures besides energies: probes, the manufactured solution's error, the
// separation of former neighbours, and the hoop stress around a hole. Each is a collective
// function of the particles; the results go into the io reports.
#pragma once

#include "gimp/cracks/growth.hpp"
#include "gimp/grid/lattice.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

#include <petscdm.h>

#include <array>
#include <limits>
#include <string>
#include <vector>

namespace gimp {

/// A probe's particle: its id, initial position and displacement (D components each) and stress
/// (stressComponents<D>() of them: 2D sxx, syy, sxy, szz; 3D sxx, syy, szz, syz, sxz, sxy).
struct ProbeState {
  PetscInt64 id = -1;
  double X0[3] = {0, 0, 0}, u[3] = {0, 0, 0};
  double stress[6] = {0, 0, 0, 0, 0, 0};
};

/// The stress components a probe, a history row and the particle dump report, by name (xx, ...):
/// 2D the in-plane ones and the out-of-plane szz, 3D the six of the symmetric tensor (Voigt
/// order).
template <int D> const std::vector<const char *> &stressComponents();

/// What a regrid must keep, over all particles: mass, momentum, the angular momentum about the
/// origin sum m (x × v) + m ε:Bᵀ (APIC's B; z only in 2D), kinetic + strain energy.
struct Conserved {
  double mass = 0, momentum[3] = {0, 0, 0}, angular[3] = {0, 0, 0}, energy = 0;
};

/// A move of a level box that follows a point (-gimp_levelK_follow): when, which level, its new
/// box (D low then D high coordinates), the particles split where it moved, and the particles'
/// conserved sums just before and just after.
struct RegridRecord {
  double t = 0;
  PetscInt64 step = 0;
  int level = 0;
  std::array<double, 6> box{}, previous{}; // the box after the move, and before it
  PetscInt64 added = 0;
  Conserved before, after;
};

/// Measures kept over the whole run.
struct RunMeasures {
  double separationStrain = std::numeric_limits<double>::quiet_NaN(); // strain at first warning
  double maxStrain = 0, maxSeparation = 0;
  double mmsLinf = 0, mmsRms = 0; // largest errors over the history rows
  PetscInt64 migrated = 0;        // particles that changed rank, summed over the run
  double dtCritical = std::numeric_limits<double>::quiet_NaN(); // smallest critical step computed
  std::vector<cracks::GrowthRecord> growth; // 2D crack growth: every increment, in order
  std::vector<RegridRecord> regrids;        // moves of level boxes that follow a point
};

/// The hole measure (-gimp_hole_measure): the hoop stress / p at the hole's edge as a curve over
/// the angle from the load axis. At every angle bin (5 degrees apart, a window of +-5 degrees)
/// the hoop stress of the particles within three particle sizes of the edge is fitted by least
/// squares, quadratic in the distance from the edge and in the angle, and the fit's value at the
/// edge and the bin's angle is the curve's (`curve`: angle [deg], edge value, Kirsch's edge value
/// 1 - 2 cos 2 theta, particles in the fit). kt is the curve at 90 degrees, hoopByAngle at 0, 15,
/// ..., 90 degrees, maxError the largest distance of the curve from Kirsch's edge values (the
/// infinite plate's). ktParticle is the particle on the 90-degree ray nearest to the edge. rows:
/// the first layer of particles (angle [deg], r, hoop / p, Kirsch's value at r). On rank 0 only:
/// rows and curve; every rank: the numbers.
struct HoleMeasure {
  static constexpr int kAngles = 7;
  double kt = std::numeric_limits<double>::quiet_NaN();
  double ktParticle = std::numeric_limits<double>::quiet_NaN();
  double maxError = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> hoopByAngle;
  std::vector<std::vector<double>> rows;
  std::vector<std::array<double, 4>> curve;
};

/// Ids of the particles nearest to each probe's initial position (ties: smallest id).
template <int D>
PetscErrorCode findProbes(MPI_Comm comm, const Scene<D> &sc, DM sw, std::vector<PetscInt64> &ids);
/// Displacement and stress of the probe particles.
template <int D>
PetscErrorCode probeStates(MPI_Comm comm, DM sw, const std::vector<PetscInt64> &ids,
                           std::vector<ProbeState> &out);
/// Largest and volume-weighted RMS displacement error against the manufactured solution at t.
template <int D>
PetscErrorCode mmsErrors(MPI_Comm comm, const Scene<D> &sc, DM sw, double t, double &linf,
                         double &rms);
/// particle k's stress components (stressComponents<D>() order) into out.
template <int D> void stressOf(const ParticleView<D> &p, PetscInt k, double *out);
/// Largest gap between particles that started as neighbours, relative to their size, and the
/// engineering strain of the particles' extent along x. Neighbours that a crack separates (the
/// segment between their initial positions crosses one of `cracks`) are not compared: their
/// gap is the crack opening.
template <int D>
PetscErrorCode separation(MPI_Comm comm, const Lattice<D> &grid, DM sw,
                          const std::vector<CrackOf<D>> &cracks, double &gap, double &strain);
/// The hole measure. In 3D the hole is a cylinder along z through (cx, cy) and the fit takes the
/// particles of the layers nearest the mid-thickness (holeLayers): the hoop stress at the hole's
/// surface halfway through the body.
template <int D>
PetscErrorCode holeMeasure(MPI_Comm comm, const Scene<D> &sc, DM sw, HoleMeasure &out);

} // namespace gimp
