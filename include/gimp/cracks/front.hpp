// Energy release rate and stress intensity factors along a 3D crack front: the equivalent domain
// integral (the 3D J integral) and the interaction integrals with the front's auxiliary fields
// (frontField), over particles.
//
// The front. Consecutive front edges of a crack polygon form a chain (closed when every edge is a
// front edge). A point x is measured from the chain: rho its distance to the chain, y the chain's
// nearest point, s the arc length along the chain from the front point P to y (for a closed
// chain, the shorter way round). At y the local frame is the front edge's (a ahead, n the normal,
// x3 = a x n = -t); when y is a vertex between two front edges, a is the in-plane direction from
// y toward x (its sign taken toward the two edges' a), so the frame turns continuously around a
// convex corner.
//
// The weight. q(x) = q_r(rho) q_s(s), q_r = (1 - rho^2 / R^2)^2 for rho < R, q_s = (1 - s^2 /
// L^2)^2 for |s| < L, 0 elsewhere: a tube of radius R along the front, 2 L long, centred on P.
// grad q is analytic: grad rho = (x - y) / rho, grad s = t of y's edge (0 when y is a vertex),
// exact for a polygon and one nearest-point search per particle (differences would need seven, and
// a step that straddles a corner's bisector would see the jump of s there).
//
// The integrals at P, the virtual advance v(x) = q(x) a(x): each piece of the front advances along
// its own normal in the plane. a is interpolated along x's nearest front edge between the ahead
// directions of its two vertices (a vertex's: the mean of its two edges' where both are front, or
// where a mouth edge continues the front by turning less than 45 degrees, as a disk's polygon does
// past a symmetry plane or a body's surface: there the mean is the front's normal at the surface;
// otherwise the front edge's own), so that v is continuous across the bisectors between edges on
// both sides of the front and tangent to a symmetry plane that a curved front meets at a right
// angle. (A fixed advance along P's direction put K 8 % high at a quarter penny crack's ends; the
// nearest edge's own direction, jumping across the bisectors behind the front, 4 % low between
// them.)
//   G    = sum_p V_p (sigma_ij du_i/dx_k - W delta_kj) dv_k/dx_j / A_q,
//   I_m  = sum_p V_p [P^m_kj dv_k/dx_j + dP^m_kj/dx_j v_k] / A_q,
//   P^m_kj = sigma_ij du^m_i/dx_k + sigma^m_ij du_i/dx_k - sigma^m_ij eps_ij delta_kj,
//   A_q  = int_front q_s(s) ds (the area the virtual advance sweeps),
// dv_k/dx_j = a_k dq/dx_j + q da_k/dx_j. The auxiliary fields of unit K_m (m = 1, 2, 3) are taken
// at the particle's (r, theta) in the frame of its nearest front point (AuxFrame::Nearest, the
// default: the frame the advance uses) or of P (AuxFrame::Point: the exact elastic fields of the
// front's tangent at P, whose advance direction then differs from v's away from P). The second
// term, the curvature terms (nearest frame only), is zero for exact auxiliary fields; in the
// nearest point's frame on a curved front the fields turn with the front, so sigma^m is not in
// equilibrium and du^m/dx not a gradient, and with the particle's field in equilibrium and
// compatible dP^m_kj/dx_j = dsigma^m_ij/dx_j du_i/dx_k + sigma_ij (d(du^m_i/dx_k)/dx_j -
// d(du^m_i/dx_j)/dx_k), the derivatives those of the fields carried by the smooth front the
// polygon stands for (its curvature from the turn of a along each edge; front_fields.hpp).
// Without them K_II on a penny crack inclined at 45 degrees came out 0.76-0.83 of the closed form
// with R / a = 1/2, with them 0.95-1.03, and within 3.6 % for R / a from 0.3 to 0.7
// (tests/check_penny_inclined3d.py). Then
// K_I = E' I_1 / 2, K_II = E' I_2 / 2, K_III = mu I_3, E' = E / (1 - nu^2), and
// G = (K_I^2 + K_II^2) / E' + K_III^2 / (2 mu) for a linear elastic field. Signs: K_I > 0 opens the
// crack; K_II > 0 slides the normal's side ahead (along +a) against the other side; K_III > 0
// slides the normal's side along +x3 = a x n = -t. The crack faces are traction free (no face
// terms); a particle with rho = 0 is skipped.
//
// Symmetry planes. Where an end of the front's chain lies on a symmetry plane of the scene (a
// MirrorPlane: frontDomain lists them) and the crack's plane crosses it at a right angle, the
// body is half of a symmetric one: the tube at P then takes, besides the particles, their mirror
// images across the plane (x' = M x, sigma' = M sigma M, grad u' = M grad u M, M flipping the
// plane's axis), around the chain's image past that end, and A_q the image's part of the front.
// The tube is then whole where the plane would cut it, as in the full body, and no term of the
// plane's own tractions (the roller's normal stress, which the mode III auxiliary field would
// meet) enters.
#pragma once

#include "gimp/cracks/williams.hpp"
#include "gimp/geometry/crack_surface.hpp"
#include "gimp/input/material.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

#include <array>
#include <vector>

namespace gimp::cracks {

/// A symmetry plane x_axis = coord: the bodies lie on one side of it and touch it, and every node
/// on it has its normal velocity held and only that (a roller over the whole plane).
struct MirrorPlane {
  int axis = 0;
  double coord = 0;
};

/// One front point's measures (SI units): G [J/m^2], K [Pa m^0.5], the domain's R and L [m]. A
/// point where no tube fits (Scene::jDomain radius 0) has NaN measures and R = L = 0.
struct FrontMeasure {
  int crack = 0, edge = 0;   // the crack and its front edge
  int images = 0;            // ends of the front's chain on a symmetry plane (0, 1 or 2)
  std::array<double, 3> x{}; // the front point [m]
  double G = 0, KI = 0, KII = 0, KIII = 0;
  double R = 0, L = 0;  // tube radius and half length (L as used: clipped on a closed front)
  double asked = 0;     // the radius asked for (-gimp_crack_j_radius, or kJCells cells) [m]
  bool clipped = false; // R was clipped to the point's clearance (Scene::jDomain)
};

/// Where and how a 3D scene measures its fronts: the finest cell h along the fronts (the finest
/// level whose box holds a front point), the tube radius and half length R (-gimp_crack_j_radius,
/// or kJCells cells), the front points' spacing (-gimp_crack_front_spacing, or 2 cells), and a
/// front point `at` whose material the integrals take, and the symmetry planes.
struct FrontDomain {
  double h = 0, R = 0, spacing = 0;
  std::array<double, 3> at{};
  std::vector<MirrorPlane> mirrors; // the scene's symmetry planes (MirrorPlane)
};
FrontDomain frontDomain(const Scene<3> &sc);

/// The frame of the auxiliary fields: the particle's nearest front point's, or the front point P's.
enum class AuxFrame { Nearest, Point };

/// The front fields' constants of a material: mu and the plane-strain kappa = 3 - 4 nu.
TipElastic frontElastic(const Material &m);

/// The half length actually used at f: L, clipped to half the front's length when the front is a
/// closed chain.
double frontHalfLength(const CrackSurface &c, const FrontPoint &f, double L);

/// A_q = int_front q_s(s) ds at front point f, exact for the polygon, with the chain's mirror
/// images across the planes its ends lie on (within 1e-6 R) [m].
double frontArea(const CrackSurface &c, const FrontPoint &f, double L, double R = 0,
                 const std::vector<MirrorPlane> &mirrors = {});

/// Adds this rank's particle sums at front point f to out: out[0] = G A_q [J/m], out[m] = I_m A_q
/// [J/m per Pa m^0.5] for m = 1, 2, 3 (see the file's comment), over the particles with 0 < rho <
/// R and |s| < L (L clipped as frontHalfLength), and their mirror images across the planes of
/// `mirrors` that an end of f's chain lies on.
void addFrontIntegrals(const Material &m, const ParticleView<3> &p, const CrackSurface &c,
                       const FrontPoint &f, double R, double L, double out[4],
                       AuxFrame aux = AuxFrame::Nearest,
                       const std::vector<MirrorPlane> &mirrors = {});

/// The first edge of the open chain of front edges that holds f, or -1 when the chain is closed
/// (every edge a front edge).
int openChainStart(const CrackSurface &c, const FrontPoint &f);

/// addFrontIntegrals at several front points of one open chain at once (pts, each with its tube
/// radius R = L, its sums at out + 4 q): each particle's nearest point on the chain and its state
/// are found once for all the points. The same sums, bit for bit, as one addFrontIntegrals per
/// point (AuxFrame::Nearest).
void addChainIntegrals(const Material &m, const ParticleView<3> &p, const CrackSurface &c,
                       const std::vector<FrontPoint> &pts, const std::vector<double> &R,
                       double *out, const std::vector<MirrorPlane> &mirrors = {});

/// G and K at front point f from the summed numerators (all ranks'). crack is left 0.
FrontMeasure finishFront(const Material &m, const CrackSurface &c, const FrontPoint &f, double R,
                         double L, const double sums[4],
                         const std::vector<MirrorPlane> &mirrors = {});

/// G and K at every front point (cracks::frontPoints(c, spacing)) of every crack, in order (crack,
/// then front point), with one MPI_Allreduce; tubes: each point's radius R, also its tube's half
/// length L (Scene::jDomain, in the same order; radius 0: not measured), asked: the radius asked
/// for. Collective.
PetscErrorCode measureFronts(MPI_Comm comm, const std::vector<CrackSurface> &cracks,
                             const Material &m, const ParticleView<3> &p, double spacing,
                             const std::vector<JDomain> &tubes, double asked,
                             const std::vector<MirrorPlane> &mirrors,
                             std::vector<FrontMeasure> &out);

} // namespace gimp::cracks
