// Crack-tip energy release rates: VCCT (the paper's Eq. 20, with its mode II counterpart) and
// the J-integral in its domain form, and the stress intensity factors from them.
#pragma once

#include "gimp/cracks/williams.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/input/material.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

#include <vector>

namespace gimp::cracks {

/// One crack tip's measures (SI units). The tip frame: t along the crack's last segment toward
/// the tip, n its left normal; mode I opens along n, mode II slides along t.
struct TipMeasure {
  int crack = 0, end = 0; // which crack, and which end of its polyline (0 first, 1 last)
  double tip[2] = {0, 0};
  double h = 0;               // the cell at the tip (finest level holding it) [m]
  double opening[2] = {0, 0}; // opening (n) and sliding (t) one cell behind the tip [m]
  double G_vcct = 0, GII_vcct = 0, G_J = 0;
  double KI_vcct = 0, KII_vcct = 0, KI_J = 0, KII_J = 0;
  double jRadius = 0;    // the J domain's radius (Scene::jDomain; 0: none fits, J not measured)
  bool jClipped = false; // the radius asked for was clipped to the tip's clearance
};

/// The tips of all cracks, in order (crack, then end), with their J domains (Scene::jDomain).
std::vector<TipMeasure> tipsOf(const Scene<2> &sc);

/// The tip fields' constants of a material.
TipElastic tipElastic(const Material &m);

/// Adds the domain integrals of the tip at `tip` (crack direction t toward the tip) over this
/// rank's particles within R of it, q = (1 - r^2 / R^2)^2, in the tip frame (t, n = left normal of
/// t): out[0] += sum_p V_p (sigma_ij du_i/dx_1 - W delta_1j) dq/dx_j (J times thickness) and out[m]
/// += sum_p V_p (sigma_ij du^m_i/dx_1 + sigma^m_ij du_i/dx_1 - sigma^m_ij eps_ij delta_1j) dq/dx_j
/// for the unit mode m = 1, 2 tip fields (williamsField): the interaction integrals, 2 K_m / E'
/// times thickness. Stress from p.s, displacement gradient from p.F - I. With the crack and the
/// end the tip is, the auxiliary fields' angle is unwrapped so that their cut follows the crack
/// (a kinked crack: the straight fields' cut would lie in the material past the kink); without,
/// their cut is the straight line behind the tip.
void addDomainIntegrals(const Material &mat, const ParticleView<2> &p, const double tip[2],
                        const double t[2], double R, double out[3], const Crack *crack = nullptr,
                        int end = 0);

/// Adds the crack-face terms of the same domain integrals (addDomainIntegrals) for the crack's
/// segments behind the tip segment of end `end` (kinks: faces not along x1, where the actual
/// field's W n_1 and the auxiliary fields' tractions do not vanish): out[0] += int W n_1 q ds
/// and out[m] -= int (sigma^m_ij n_j du_i/dx_1 - sigma^m_ij eps_ij n_1) q ds over both faces of
/// each such segment within R, n the material's outward normal (into the crack), the auxiliary
/// fields at the face point. Each face is a band one particle wide on its side: a particle whose
/// centre lies within its width across the face, w = 2 (|l_x n_x| + |l_y n_y|), of the segment
/// (its foot on the segment) adds V_p / w times its integrand, with q and the auxiliary fields
/// at its foot.
void addFaceTerms(const Material &mat, const ParticleView<2> &p, const Crack &crack, int end,
                  const double tip[2], const double t[2], double R, double out[3]);

/// VCCT and J at every tip (anywhere, any direction), with h the cell of the finest level
/// holding the tip. VCCT is crack closure over one cell: G_I = F_n du_n / (2 t h),
/// G_II = F_t du_t / (2 t h). F is the internal force that the particles on the tip frame's n
/// side put on a node at the tip (the grid's regular GIMP kernel of cell h centred on the tip:
/// one side's grip on the tip). du is the opening at the point one cell behind the tip: the
/// nodal displacement there of each side's field, n side minus the other, recovered by the
/// mass-weighted least-squares fit of the nodal values of a lattice of cell h around that point
/// (the same kernel, two fields per node joined as crossing() decides, as for the grid's
/// fields) to the particles' displacements p.us (integrated from the velocity that updates F;
/// x - X0 where the swarm has no us). J by the domain integral over the particles within the tip's
/// jRadius (Scene::jDomain, set at input: -gimp_crack_j_radius or kJCells cells, clipped to
/// the tip's clearance), J = sum_p V_p (sigma_ij du_i/dx_1 - W delta_1j) dq/dx_j in the tip
/// frame, q = (1 - r^2 / R^2)^2; K_I and K_II "by J" from the interaction integrals over the same
/// domain (addDomainIntegrals), K_m = E' I_m / 2. VCCT's K = sqrt(G E'), signed by G_I and du_t;
/// E' = E (plane stress) or E / (1 - nu^2) (plane strain). A tip without a J domain (jRadius 0)
/// has G_J, KI_J and KII_J NaN (null in summary.json). Collective.
PetscErrorCode measureTips(MPI_Comm comm, const Scene<2> &sc, const Grid<2> &g,
                           const ParticleView<2> &p, std::vector<TipMeasure> &tips);

} // namespace gimp::cracks
