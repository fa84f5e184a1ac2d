// Material points in a PETSc DMSwarm (structure of arrays).
//
// One table per dimension, particleFields<D>(), lists every field once: its name, components,
// type, whether the HDF5 output writes it and which scenes need it (FieldNeed: every scene,
// corner tracking, strain or corner tracking, APIC, loads on faces, multi-rate steps); a field no
// scene option needs is not stored. Registration, ParticleView::get/restore, checkpoints and the
// output all walk that table. A ParticleView borrows every
// field's array for one phase of a step; restore() hands them back to the swarm.
#pragma once

#include "gimp/core/petsc_compat.hpp"
#include "gimp/core/tensor.hpp"
#include "gimp/input/scene.hpp"

#include <petscdmswarm.h>

#include <vector>

namespace gimp {

/// Which scenes need a particle field.
enum class FieldNeed { Always, Never, Corners, Strain, Affine, Boundary, Multirate, Cracks };

/// The optional fields a swarm carries: corners (corner and cpdi2 tracking), eps (strain and
/// corner tracking), B (APIC), trac and dbc (tractions or penalty conditions), rate (multi-rate
/// steps), us (2D cracks).
struct OptionalFields {
  bool corners = false, strain = false, affine = false, boundary = false, multirate = false,
       cracks = false;
  bool has(FieldNeed need) const {
    return need == FieldNeed::Always || (need == FieldNeed::Corners && corners) ||
           (need == FieldNeed::Strain && strain) || (need == FieldNeed::Affine && affine) ||
           (need == FieldNeed::Boundary && boundary) ||
           (need == FieldNeed::Multirate && multirate) || (need == FieldNeed::Cracks && cracks);
  }
};

/// A particle view's real fields of position, motion, mass, volume and domain (null where the
/// swarm does not carry them).
struct ParticleKinematics {
  double *x = nullptr;  // position [D]
  double *X0 = nullptr; // initial position [D]
  double *v = nullptr;  // velocity [D]
  double *m = nullptr;  // mass
  double *V0 = nullptr; // initial volume (area x thickness)
  double *V = nullptr;  // current volume
  double *l = nullptr;  // current half-sizes [D]
  double *l0 = nullptr; // initial half-sizes [D]
  double *B = nullptr;  // APIC affine moment sum_i S_ip v_i (x_i - x_p)^T, row-major D x D, if APIC
  double *corners = nullptr; // tracked corners (-,-), (+,-), (+,+), (-,+) [2^D x D], if any
  // 2D cracks: the displacement integrated from the velocity field that updates the stress (the
  // one F integrates; with MUSL not the one that moves x) [D]
  double *us = nullptr;
};

/// A particle view's fields of deformation, stress and strain.
struct ParticleDeformation {
  double *F = nullptr;   // deformation gradient, row-major D x D
  double *s = nullptr;   // Cauchy stress, its kStress<D> entries in Voigt order (stressAt)
  double *szz = nullptr; // 2D: out-of-plane stress (plane strain; zero in plane stress)
  double *eps = nullptr; // accumulated small-strain increments (xx, yy) [D], if strain or corners
};

/// A particle view's integer fields: identity, loads, rate class and owner.
struct ParticleTags {
  PetscInt64 *id = nullptr; // identity, independent of the rank count
  PetscInt *trac = nullptr; // traction index on its x side and y side, -1 if none [D] (null
                            // in a scene without tractions and penalty conditions)
  PetscInt *dbc = nullptr;  // penalty displacement condition index, likewise [D]
  PetscInt *rate = nullptr; // -gimp_multirate: the rate class (level) of the last coarse step,
                            // -1 before the first
  PetscInt *rank = nullptr; // owner rank (DMSwarm's migration field)
};

/// Every field of a swarm's particles, borrowed (get) and handed back (restore); the fields by
/// concept in its bases.
template <int D> struct ParticleView : ParticleKinematics, ParticleDeformation, ParticleTags {
  static constexpr int dim = D;
  PetscInt n = 0;
  bool hasCorners = false; // the swarm carries the corners field (found by get())
  OptionalFields fields;   // the optional fields it carries (found by get())

  PetscErrorCode get(DM sw);
  PetscErrorCode restore(DM sw);
  /// Particles [k0, k1) as a view of their own: every array offset to k0, n = k1 - k0. It
  /// borrows this view's arrays (never restore() it).
  ParticleView<D> slice(PetscInt k0, PetscInt k1) const;
};

template <int D> struct FieldSpec {
  const char *name;
  PetscInt components;
  PetscDataType type;
  bool written;   // in the HDF5 particle output
  FieldNeed need; // the scenes that store it
  void **(*slot)(ParticleView<D> &);
  bool symmetric = false; // a symmetric tensor held as kStress<D> entries (the stress), written
                          // to the HDF5 output as the full D x D (D * D components)
  /// Components per particle in the HDF5 output.
  PetscInt writtenComponents() const { return symmetric ? D * D : components; }
};

/// Every particle field of a D-dimensional swarm, in registration order (szz is 2D only: the
/// out-of-plane stress of plane strain).
template <int D> const std::vector<FieldSpec<D>> &particleFields();

/// Create the swarm with gimp's fields (collective).
template <int D> PetscErrorCode createSwarm(MPI_Comm comm, OptionalFields optional, DM *sw);

/// The optional fields a swarm carries.
PetscErrorCode swarmOptionalFields(DM sw, OptionalFields &optional);

/// Reorder this rank's particles: particle k becomes the former particle order[k], in every
/// field (gimp's and DMSwarm's own). Not collective.
template <int D> PetscErrorCode permuteSwarm(DM sw, const std::vector<PetscInt> &order);
/// Move a few of this rank's particles: particle at[j] becomes the former particle from[j], in
/// every field; `from` is a rearrangement of `at`, and every other particle stays. Not collective.
template <int D>
PetscErrorCode permuteSwarmAt(DM sw, const std::vector<PetscInt> &at,
                              const std::vector<PetscInt> &from);
/// Append copies of this rank's particles: new particle n0 + j (n0 the local size before) a copy
/// of particle from[j] in every field (gimp's and DMSwarm's own). Not collective.
template <int D> PetscErrorCode appendCopies(DM sw, const std::vector<PetscInt> &from);
/// The moves (permuteSwarmAt's at and from) that make the classes cls (0, 1, ..., one per
/// particle) contiguous and in increasing order: only the particles outside their class's range
/// move, each into a place of its class's range held by another class, both taken in index
/// order. Not collective.
void classMoves(const std::vector<int> &cls, std::vector<PetscInt> &at,
                std::vector<PetscInt> &from);

template <int D> struct Scene;
/// The optional fields a scene needs (its tracking and transfer).
template <int D> OptionalFields optionalFieldsOf(const Scene<D> &sc);

} // namespace gimp
