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

/// VCCT at every tip (on a grid node; VCCT is 0 elsewhere), crack closure over one cell h
/// (the tip node's zone on the side the crack comes from): G_I = F_n du_n / (2 t h),
/// G_II = F_t du_t / (2 t h), with F the internal force that the particles on the tip frame's n
/// side put on the tip node (one side's grip on the tip) and du the opening one cell behind the
/// tip: the displacement of the n-side particle minus the other side's, for the two pairs whose
/// centres started nearest to 3 l0 and 5 l0 behind the tip (h = 4 l0 with 2 x 2 particles per
/// cell), interpolated linearly to h. J by the domain integral over the particles within jRadius
/// of the tip: J = sum_p V_p (sigma_ij du_i/dx_1 - W delta_1j) dq/dx_j in the tip frame,
/// q = 1 - r / jRadius. K = sqrt(G E') with E' = E (plane stress) or E / (1 - nu^2) (plane
/// strain). Collective.
PetscErrorCode measureTips(MPI_Comm comm, const Scene &sc, const Grid &g, const Stencils<kDim> &st,
                           const ParticleView &p, double jRadius, std::vector<TipMeasure> &tips);

} // namespace gimp::cracks
