// Frictionless contact between the two velocity fields of explicit cracks after the grid update
// (which field a particle joins: grid/crack_fields.hpp).
#pragma once

#include "gimp/geometry/crack.hpp"
#include "gimp/geometry/crack_surface.hpp"
#include "gimp/grid/crack_fields.hpp"
#include "gimp/grid/grid.hpp"

#include <array>
#include <vector>

namespace gimp::cracks {

/// An increment still being released (-gimp_crack_growth_release), grown at the check of time t0
/// [s]. 2D: the segment it added, from the tip before it to the new tip. 3D: its crack and the
/// crack's polygon before it (the front advances point by point, so what it added is the new
/// polygon less this one).
template <int D> struct Release;
template <> struct Release<2> {
  std::array<double, 2> from{}, to{};
  double t0 = 0;
};
template <> struct Release<3> {
  int crack = 0;
  CrackSurface before;
  double t0 = 0;
};

/// Contact between the two fields of every cracked node of a window.
template <int D> class Contact {
public:
  /// The direction d of each cracked window node, from field 1's material toward field 2's:
  /// field 1 is on the node's side of the nearest crack, field 2 across it. With a release time
  /// (> 0) and increments being released: the nodes each increment newly cut are bonded from its
  /// time t0 on (see apply). Newly cut: the node's nearest point on its crack lies on the
  /// increment's segment at or beyond the tip before it (2D), or not inside the polygon before it
  /// farther than round-off from that polygon's front (3D).
  void setup(const Grid<D> &g, const std::vector<CrackOf<D>> &cracks,
             const std::vector<Release<D>> &releasing = {}, double releaseTime = 0);

  /// Each field's mass-weighted displacement along d at every cracked node, into the window
  /// array `face` (component 0 of each slot, sum over particles of m w (x - X0).d; initialised
  /// to 0 here, so ranks combine by ADD). Also starts a new step's contact set (see apply).
  void faces(const Grid<D> &g, const Stencils<D> &st, PetscInt n, const double *x, const double *X0,
             const double *m, double *face);

  /// Starts a new step's contact set without faces() (the rate classes of -gimp_multirate keep
  /// their faces from their starts and sum them).
  void newStep() { fresh_ = true; }

  /// Frictionless contact where both fields carry mass (> cut) and their faces touch: when the
  /// fields approach each other along d, both take the normal velocity of their common centre
  /// of mass (momentum is kept); fields that separate stay free. The faces touch when their
  /// opening (field 2's nodal displacement along d minus field 1's, from faces()) is closed or
  /// closes within dt at the fields' relative normal speed (round-off aside), decided at the
  /// step's first call and kept for its other calls, so that every grid velocity of the step
  /// sees the same contact set. (A gap tolerance of a fraction of a cell, as before, held the
  /// faces of a crack in a stiff body, which open by nanometres, in contact; contact lets faces
  /// part but not return, and ratcheted such a crack open: a DCB on 0.5 mm settled with K 11 %
  /// high.) Window arrays, mass in component 0; the accelerations get the same change / dt so a
  /// FLIP update sees it (acc may be null: a velocity field alone, as MUSL's re-projection).
  /// A node an increment is releasing (setup) first has both fields' velocities moved toward
  /// their common centre of mass's by the fraction b = 1 - (t - t0) / release, in full (not only
  /// along d: the new faces are still bonded, in shear too), so that the increment opens over the
  /// release time instead of at once; momentum is kept, and the relative motion taken is
  /// dissipated. Returns the number of nodes in contact.
  PetscInt apply(const Grid<D> &g, double cut, double dt, const double *mass, const double *face,
                 double *vel, double *acc, double t);

private:
  std::vector<double> dir_; // D per crack slot (slot - nWindow)
  std::vector<char> touch_; // this step's contact set, per crack slot
  // The release: per crack slot the time its bond starts to fall (-inf: none), and its length.
  std::vector<double> bondFrom_;
  double release_ = 0;
  bool fresh_ = true; // touch_ is to be decided by the next apply
};

extern template class Contact<2>;
extern template class Contact<3>;

} // namespace gimp::cracks
