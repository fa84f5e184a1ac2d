// The 2D step's particle loops with four block particles at a time (AVX2), for the phases that
// cost most per particle: APIC's P2G, the internal force, APIC's G2P (with its re-projection or
// without), the velocity gradient and the linear-elastic stress update (docs/method.md, *Lanes of
// four particles*; the stencils' blocks are built four at a time by GridT::blockRun).
//
// Each loop takes the stencils' lane groups, aligned groups of four 3-node block particles that
// the stencil build (GridT::buildStencils with lanes) made in lanes and marked in
// Stencils::laneGroup (stencils built without lanes have none, and everything runs scalar), and
// does the per-particle arithmetic of the scalar kernel of
// transfer/block_kernels.hpp in four lanes of a 256-bit register, each lane evaluating the scalar
// expression in its order with products and sums fused (FMA) where the compiler finds them; the
// other particles, and the tail, go through the scalar kernels. Scatters add each particle's
// contributions to the nodes in particle order, as the scalar loop does, so the results are the
// scalar ones to round-off (tests/check_lanes.py compares every scene kind with -gimp_lanes
// false).
//
// The functions are compiled for AVX2 with FMA whatever the build's flags; call them only when
// available() is true (the processor and the operating system support AVX2 and FMA). On other
// processors, or other architectures, available() is false and the scalar loops run.
#pragma once

#include "gimp/grid/stencils.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

#include <petscsys.h>

namespace gimp::transfer::laneLoops {

/// True when the lane kernels can run here (x86-64 with AVX2 and FMA enabled by the OS).
bool available();

/// particlesToGridAffineB<2> (transfer/affine.hpp): APIC P2G with C_p = B_p D_p^-1.
void particlesToGridAffineB(const Stencils<2> &st, PetscInt n, const double *m, const double *v,
                            const double *B, const double *xc, const double *xs, double *mom,
                            double *mass);

/// transfer::internalForce<2> (transfer/internal_force.hpp): f_i -= V_p sigma_p grad S_ip.
void internalForce(const Stencils<2> &st, PetscInt n, const double *V, const double *stress,
                   double *f);

/// gridToParticlesAffineProjected<2> (transfer/affine.hpp): APIC G2P, the re-projection of the
/// new affine momenta into mom, and the move by dt v_p (x may be xc).
void gridToParticlesAffineProjected(const Stencils<2> &st, PetscInt n, const double *vg,
                                    const double *xc, const double *xs, double dt, const double *m,
                                    double *v, double *B, double *x, double *mom);

/// gridToParticlesAffine<2> (transfer/affine.hpp): APIC G2P and the move by dt v_p, without a
/// re-projection (USL and USF); x may be xc and must not be null.
void gridToParticlesAffine(const Stencils<2> &st, PetscInt n, const double *vg, const double *xc,
                           const double *xs, double dt, double *v, double *B, double *x);

/// gridToParticlesAffineRated<2> (transfer/affine.hpp): APIC G2P of one rate class of a
/// per-level step, centred on the positions x, the move by dt S wg (with wg == vg, dt v_p) and,
/// when mom is not null, the re-projection about the place before the move.
void gridToParticlesAffineRated(const Stencils<2> &st, PetscInt n, const double *vg,
                                const double *wg, const double *xs, double dt, const double *m,
                                double *v, double *B, double *x, double *mom);

/// The FLIP/PIC transfers (transfer/transfer.hpp; src/transfer/lane_loops_flip.cpp, built without
/// contraction: bit for bit the scalar loops): particlesToGrid<2> (P2G of momentum and, with
/// mass, mass), gridToParticles<2> (G2P and the move), gridToParticlesProjected<2> (G2P, the
/// move and the re-projection of m_p v_p into mom) and gridToParticlesRated<2> (the G2P of a rate
/// class of a per-level step).
void particlesToGrid(const Stencils<2> &st, PetscInt n, const double *m, const double *v,
                     double *mom, double *mass);
void gridToParticles(const Stencils<2> &st, PetscInt n, const double *vg, const double *ag,
                     double dt, double flip, double *v, double *x);
void gridToParticlesProjected(const Stencils<2> &st, PetscInt n, const double *vg, const double *ag,
                              double dt, double flip, const double *m, double *v, double *x,
                              double *mom);
void gridToParticlesRated(const Stencils<2> &st, PetscInt n, const double *ug, const double *wg,
                          double dt, double flip, const double *m, double *v, double *x,
                          double *mom);

/// The velocity gradients of particles k0 .. k1-1 into L (row-major 2 x 2 from L[0]), as
/// transfer::velocityGradientAt<2>; k0 a multiple of 4 (the lane groups are aligned).
void velocityGradients(const Stencils<2> &st, PetscInt k0, PetscInt k1, const double *vg,
                       double *L);

/// physics::updateDeformation (2D) for particles k0 .. k1-1 with their velocity gradients L (from
/// L[0]): runs of four particles of one linear material, with stretch tracking or none, in lanes
/// (F += dt L F, V, the Jaumann update of material::jaumannUpdate, l = |F e_a| l0); the others
/// through the scalar update.
void updateDeformation(const Scene<2> &sc, ParticleView<2> &p, const double *L, double dt,
                       PetscInt k0, PetscInt k1);

/// Solver::checks' test of each particle, for the first 4 floor(n / 4) particles in lanes of
/// four: finite position and stress (x + y + s_xx + s_yy + s_xy), V > 0, the domain
/// [x - l, x + l] inside [lo, hi], 0 < l <= hmax. Returns how many particles it tested; `bad` is
/// the first of them that fails (-1 for none) and, with `count`, `leaving` is increased by those
/// outside [own0, own1) (the next step's migration).
PetscInt checkParticles(PetscInt n, const double *x, const double *l, const double *s,
                        const double *V, const double *lo, const double *hi, double hmax,
                        const double *own0, const double *own1, bool count, PetscInt &bad,
                        PetscInt64 &leaving);

} // namespace gimp::transfer::laneLoops
