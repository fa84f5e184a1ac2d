// Explicit cracks in the step (docs/architecture.md, "A second velocity field at cracked
// nodes"): each field's face at the cracked nodes once per step, and frictionless contact
// between the two fields on every grid velocity the step uses.
#include "gimp/solver/step.hpp"

namespace gimp {

template <int D>
PetscErrorCode Step<D>::crackFaces(const ParticleView<D> &p, const std::vector<Vec> *classFaces) {
  // Each field's mass-weighted displacement along its contact normal at every cracked node:
  // summed over the ranks that hold the node, back to every window. With them the summed mass
  // and the mask on the window, which the step's contact passes read. With -gimp_multirate the
  // sum runs over the rate classes (classFaces), each with its stencils from its last start.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  PetscCall(s.grid.toWindow(n.mass, n.massW));
  PetscCall(s.grid.toWindow(n.mask, n.maskW));
  if (!classFaces) {
    PetscScalar *f = nullptr;
    PetscCall(VecGetArray(n.faceW, &f));
    contact_.faces(s.grid, s.st, p.n, p.x, p.X0, p.m, f);
    PetscCall(VecRestoreArray(n.faceW, &f));
  } else { // the classes' faces from their starts (MultiRate::startClasses)
    contact_.newStep();
    PetscCall(VecZeroEntries(n.faceW));
    for (Vec f : *classFaces)
      PetscCall(VecAXPY(n.faceW, 1.0, f));
  }
  PetscCall(VecSet(n.face, 0.0));
  PetscCall(s.grid.fromWindow(n.faceW, n.face, ADD_VALUES));
  PetscCall(s.grid.toWindow(n.face, n.faceW));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Step<D>::contactOnMomentum(const StepClock &c) {
  // Contact on the projected momentum (before the forces): the fields' velocities and P, so the
  // step starts from fields that do not approach each other.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  PetscCall(s.grid.toWindow(n.vel, n.velW));
  PetscCall(VecCopy(n.velW, n.accW));
  PetscCall(crackContact(c, n.velW, n.vel, nullptr, nullptr));
  PetscCall(s.grid.toWindow(n.P, n.sumW));
  const PetscScalar *v = nullptr, *m = nullptr;
  PetscScalar *old = nullptr, *P = nullptr;
  PetscCall(VecGetArrayRead(n.velW, &v));
  PetscCall(VecGetArrayRead(n.massW, &m));
  PetscCall(VecGetArray(n.accW, &old));
  PetscCall(VecGetArray(n.sumW, &P));
  for (PetscInt i = 0; i < s.grid.nSlots; ++i)
    for (int d = 0; d < D; ++d)
      P[D * i + d] += m[D * i] * (v[D * i + d] - old[D * i + d]);
  PetscCall(VecRestoreArray(n.sumW, &P));
  PetscCall(VecRestoreArray(n.accW, &old));
  PetscCall(VecRestoreArrayRead(n.massW, &m));
  PetscCall(VecRestoreArrayRead(n.velW, &v));
  PetscCall(s.grid.fromWindow(n.sumW, n.P, INSERT_VALUES));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Step<D>::crackContact(const StepClock &c, Vec velW, Vec vel, Vec accW, Vec acc) {
  // Frictionless contact of the two fields at cracked nodes, on the window (every rank that
  // holds a node computes the same result), then back to the global vectors.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  PetscCall(PetscLogStagePush(s.stages.grid));
  const PetscScalar *m = nullptr, *mask = nullptr, *face = nullptr;
  PetscScalar *v = nullptr, *a = nullptr;
  PetscCall(VecGetArrayRead(n.massW, &m));
  PetscCall(VecGetArrayRead(n.maskW, &mask));
  PetscCall(VecGetArrayRead(n.faceW, &face));
  PetscCall(VecGetArray(velW, &v));
  if (accW) PetscCall(VecGetArray(accW, &a));
  const PetscInt touching =
      contact_.apply(s.grid, s.sc.massCutoff * s.meanParticleMass, c.dt, m, face, v, a, c.t);
  for (PetscInt i = 0; i < D * s.grid.nSlots; ++i) { // constrained dofs stay fixed
    v[i] *= mask[i];
    if (a) a[i] *= mask[i];
  }
  if (accW) PetscCall(VecRestoreArray(accW, &a));
  PetscCall(VecRestoreArray(velW, &v));
  PetscCall(VecRestoreArrayRead(n.faceW, &face));
  PetscCall(VecRestoreArrayRead(n.maskW, &mask));
  PetscCall(VecRestoreArrayRead(n.massW, &m));
  PetscCall(PetscInfo(nullptr,
                      "step %" PetscInt_FMT ": %" PetscInt_FMT " cracked nodes in contact\n",
                      c.step, touching));
  PetscCall(s.grid.fromWindow(velW, vel, INSERT_VALUES));
  if (accW) PetscCall(s.grid.fromWindow(accW, acc, INSERT_VALUES));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode Step<D>::crackFaces(const ParticleView<D> &, const std::vector<Vec> *);  \
  template PetscErrorCode Step<D>::contactOnMomentum(const StepClock &);                           \
  template PetscErrorCode Step<D>::crackContact(const StepClock &, Vec, Vec, Vec, Vec);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
