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
  double h = 0;               // the cell at the tip (finest level holding it) [m]
  double opening[2] = {0, 0}; // opening (n) and sliding (t) one cell behind the tip [m]
  double G_vcct = 0, GII_vcct = 0, G_J = 0;
  double KI_vcct = 0, KII_vcct = 0, KI_J = 0, KII_J = 0;
};

/// The tips of all cracks, in order (crack, then end).
std::vector<TipMeasure> tipsOf(const Scene &sc);

/// J's default domain radius in cells at the tip.
constexpr double kJCells = 5.0;

/// VCCT and J at every tip (anywhere, any direction), with h the cell of the finest level
/// holding the tip. VCCT is crack closure over one cell: G_I = F_n du_n / (2 t h),
/// G_II = F_t du_t / (2 t h). F is the internal force that the particles on the tip frame's n
/// side put on a node at the tip (the grid's regular GIMP kernel of cell h centred on the tip:
/// one side's grip on the tip). du is the opening at the point one cell behind the tip: the
/// mass projection of each side's particle displacement with the same kernel, n side minus the
/// other (a particle's side is the one crossing() gives it against that point, as for the two
/// fields of a grid node). J by the domain integral over the particles within jRadius of the
/// tip (0: kJCells cells), J = sum_p V_p (sigma_ij du_i/dx_1 - W delta_1j) dq/dx_j in the tip
/// frame, q = 1 - r / R; J is the total G, split into modes by the opening's ratio
/// (K_II / K_I = du_t / du_n). K = sqrt(G E') with E' = E (plane stress) or E / (1 - nu^2)
/// (plane strain), signed by G_I and du_t. Collective.
PetscErrorCode measureTips(MPI_Comm comm, const Scene &sc, const Grid &g, const ParticleView &p,
                           double jRadius, std::vector<TipMeasure> &tips);

} // namespace gimp::cracks
