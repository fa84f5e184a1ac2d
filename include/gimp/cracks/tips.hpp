// Crack-tip energy release rates: VCCT (the paper's Eq. 20, with its mode II counterpart) and
// the J-integral in its domain form, and the stress intensity factors from them.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/particles/swarm.hpp"

#include <vector>

namespace gimp::cracks {

/// One crack tip's measures (SI units). The tip frame: t along the crack's last segment toward
/// the tip, n its left normal; mode I opens along n, mode II slides along t.
struct TipMeasure {
  int crack = 0, end = 0; // which crack, and which end of its polyline (0 first, 1 last)
  double tip[2] = {0, 0};
  double G_vcct = 0, GII_vcct = 0, G_J = 0;
  double KI_vcct = 0, KII_vcct = 0, KI_J = 0;
};

/// The tips of all cracks, in order (crack, then end).
std::vector<TipMeasure> tipsOf(const Scene &sc);

/// VCCT at every tip (on a grid node; VCCT is 0 elsewhere): G_I = F_n du_n / (2 t da), G_II = F_t
/// du_t / (2 t da), with F the internal force that the particles on the tip frame's n side put on
/// the node nearest the tip (one side's grip on the tip), du the displacement of particle 1 (behind
/// the tip, n side) minus particle 2 (behind the tip, other side), the particles chosen by their
/// initial position nearest to the tip - l0 t +- l0 n, and da the distance from particle 1 to the
/// tip along t. J by the domain integral over the particles within jRadius of the tip: J = sum_p
/// V_p (sigma_ij du_i/dx_1 - W delta_1j) dq/dx_j in the tip frame, q = 1 - r / jRadius. K = sqrt(G
/// E') with E' = E (plane stress) or E / (1 - nu^2) (plane strain). Collective.
PetscErrorCode measureTips(MPI_Comm comm, const Scene &sc, const Grid &g, const Stencils<kDim> &st,
                           const ParticleView &p, double jRadius, std::vector<TipMeasure> &tips);

} // namespace gimp::cracks
