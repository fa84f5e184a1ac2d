// The 3D step's particle loops with a block particle's three components in the lanes of one
// 256-bit register (AVX2): APIC's and FLIP's P2G and G2P (with the re-projection or without), the
// internal force and the velocity gradient; and the stress update four particles at a time
// (docs/method.md, *Lanes of four particles*, 3D).
//
// A 3D block particle reaches up to 3 x 3 x 3 nodes, and a node's three components are adjacent in
// the window arrays: each kernel's sums over the components c = 0, 1, 2 of a node (or of a
// particle's vector, or of a column of its D x D tensor) run as one vector of lanes 0-2 (lane 3
// zero and unused). Every lane evaluates the scalar kernel's expression for its component, in the
// same order, with products and sums fused (FMA) where the compiler finds them (the scalar kernels
// are the block branches of transfer/affine.hpp and transfer/transfer.hpp and the walk of
// Stencils::forEach), so the results are the scalar ones to round-off (tests/check_lanes.py runs
// the 3D scenes with -gimp_lanes false too). Particles that keep rows take the same kernels over
// their entries (forEach order).
//
// They are the 3D overloads of transfer/lane_loops.hpp's loops (one namespace, so a caller writes
// one call for both dimensions; FLIP's transfers have a lane form in 3D only). The functions are
// compiled for AVX2 with FMA whatever the build's flags; call them only when
// transfer::laneLoops::available() is true.
#pragma once

#include "gimp/grid/stencils.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

#include <petscsys.h>

namespace gimp::transfer::laneLoops {

/// particlesToGridAffineB<3> (transfer/affine.hpp): APIC P2G with C_p = B_p D_p^-1.
void particlesToGridAffineB(const Stencils<3> &st, PetscInt n, const double *m, const double *v,
                            const double *B, const double *xc, const double *xs, double *mom,
                            double *mass);

/// gridToParticlesAffineProjected<3>: APIC G2P, the re-projection of the new affine momenta into
/// mom, and the move by dt v_p (x may be xc).
void gridToParticlesAffineProjected(const Stencils<3> &st, PetscInt n, const double *vg,
                                    const double *xc, const double *xs, double dt, const double *m,
                                    double *v, double *B, double *x, double *mom);

/// gridToParticlesAffine<3>: APIC G2P and the move by dt v_p, no re-projection (x may be xc).
void gridToParticlesAffine(const Stencils<3> &st, PetscInt n, const double *vg, const double *xc,
                           const double *xs, double dt, double *v, double *B, double *x);

/// particlesToGrid<3> (transfer/transfer.hpp): FLIP/PIC P2G of m_p v_p (and m_p when mass is not
/// null).
void particlesToGrid(const Stencils<3> &st, PetscInt n, const double *m, const double *v,
                     double *mom, double *mass);

/// gridToParticles<3>: FLIP/PIC G2P and the move by dt v_p.
void gridToParticles(const Stencils<3> &st, PetscInt n, const double *vg, const double *ag,
                     double dt, double flip, double *v, double *x);

/// gridToParticlesProjected<3>: the same and the re-projection of the new momenta into mom.
void gridToParticlesProjected(const Stencils<3> &st, PetscInt n, const double *vg, const double *ag,
                              double dt, double flip, const double *m, double *v, double *x,
                              double *mom);

/// gridToParticlesAffineRated<3> (transfer/affine.hpp): APIC G2P of one rate class of a
/// per-level step (v_p and B_p from vg, the move by dt S wg, the re-projection into mom when it
/// is not null, about the place before the move).
void gridToParticlesAffineRated(const Stencils<3> &st, PetscInt n, const double *vg,
                                const double *wg, const double *xs, double dt, const double *m,
                                double *v, double *B, double *x, double *mom);

/// gridToParticlesRated<3> (transfer/transfer.hpp): FLIP/PIC G2P of one rate class, v_p <- flip
/// v_p + S ug, x_p += dt S wg, and the re-projection into mom when it is not null.
void gridToParticlesRated(const Stencils<3> &st, PetscInt n, const double *ug, const double *wg,
                          double dt, double flip, const double *m, double *v, double *x,
                          double *mom);

/// transfer::internalForce<3> (transfer/internal_force.hpp): f_i -= V_p sigma_p grad S_ip.
void internalForce(const Stencils<3> &st, PetscInt n, const double *V, const double *stress,
                   double *f);

/// The velocity gradients of particles k0 .. k1-1 into L (row-major 3 x 3 from L[0]), as
/// transfer::velocityGradientAt<3>.
void velocityGradients(const Stencils<3> &st, PetscInt k0, PetscInt k1, const double *vg,
                       double *L);

/// physics::updateDeformation<3> for particles k0 .. k1-1 with their velocity gradients L (from
/// L[0]): runs of four particles of one linear material, with stretch tracking or none, four at a
/// time in lanes (F += dt L F, V, the Jaumann update of material::jaumannUpdate, l = |F e_a| l0);
/// the others through the scalar update.
void updateDeformation(const Scene<3> &sc, ParticleView<3> &p, const double *L, double dt,
                       PetscInt k0, PetscInt k1);

/// Solver::checks' test of every solid particle with its x, y, z in lanes: finite position,
/// velocity and stress, 0 < V <= DBL_MAX, the domain [x - l, x + l] inside [lo, hi], 0 < l <=
/// hmax. Returns how many particles it tested (all, or none without lanes); `bad` is the first
/// of them that fails (-1 for none) and `leaving` is increased by those outside [own0, own1)
/// (the next step's migration).
PetscInt checkParticles(PetscInt n, const double *x, const double *l, const double *v,
                        const double *s, const double *V, const double *lo, const double *hi,
                        double hmax, const double *own0, const double *own1, PetscInt &bad,
                        PetscInt64 &leaving);

} // namespace gimp::transfer::laneLoops
