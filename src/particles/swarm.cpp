#include "gimp/particles/swarm.hpp"

namespace gimp {

namespace {

constexpr int D = kDim;

template <typename T> void **slotOf(T *&p) {
  return reinterpret_cast<void **>(&p);
}

} // namespace

const std::vector<FieldSpec> &particleFields() {
  static const std::vector<FieldSpec> fields = {
      {"x", D, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.x); }},
      {"X0", D, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.X0); }},
      {"v", D, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.v); }},
      {"m", 1, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.m); }},
      {"V0", 1, PETSC_REAL, false, false, [](ParticleView &p) { return slotOf(p.V0); }},
      {"V", 1, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.V); }},
      {"l", D, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.l); }},
      {"l0", D, PETSC_REAL, false, false, [](ParticleView &p) { return slotOf(p.l0); }},
      {"F", D * D, PETSC_REAL, false, false, [](ParticleView &p) { return slotOf(p.F); }},
      {"stress", D * D, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.s); }},
      {"szz", 1, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.szz); }},
      {"eps", D, PETSC_REAL, false, false, [](ParticleView &p) { return slotOf(p.eps); }},
      {"id", 1, PETSC_INT64, false, false, [](ParticleView &p) { return slotOf(p.id); }},
      {"trac", D, PETSC_INT, false, false, [](ParticleView &p) { return slotOf(p.trac); }},
      {"dbc", D, PETSC_INT, false, false, [](ParticleView &p) { return slotOf(p.dbc); }},
      {"B", D * D, PETSC_REAL, true, false, [](ParticleView &p) { return slotOf(p.B); }},
      {"corners", (1 << D) * D, PETSC_REAL, true, true,
       [](ParticleView &p) { return slotOf(p.corners); }},
  };
  return fields;
}

PetscErrorCode swarmHasCorners(DM sw, bool &has) {
  PetscObject mark = nullptr;
  PetscCall(PetscObjectQuery(reinterpret_cast<PetscObject>(sw), "gimp_corners", &mark));
  has = mark != nullptr;
  return PETSC_SUCCESS;
}

PetscErrorCode ParticleView::get(DM sw) {
  PetscCall(swarmHasCorners(sw, hasCorners));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  for (const FieldSpec &f : particleFields())
    if (hasCorners || !f.cornersOnly)
      PetscCall(DMSwarmGetField(sw, f.name, nullptr, nullptr, f.slot(*this)));
  PetscCall(DMSwarmGetField(sw, DMSwarmField_rank, nullptr, nullptr, slotOf(rank)));
  return PETSC_SUCCESS;
}

PetscErrorCode ParticleView::restore(DM sw) {
  for (const FieldSpec &f : particleFields())
    if (hasCorners || !f.cornersOnly)
      PetscCall(DMSwarmRestoreField(sw, f.name, nullptr, nullptr, f.slot(*this)));
  PetscCall(DMSwarmRestoreField(sw, DMSwarmField_rank, nullptr, nullptr, slotOf(rank)));
  return PETSC_SUCCESS;
}

PetscErrorCode createSwarm(MPI_Comm comm, bool corners, DM *sw) {
  PetscCall(DMCreate(comm, sw));
  PetscCall(DMSetType(*sw, DMSWARM));
  PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(*sw), "particles"));
  PetscCall(DMSetDimension(*sw, D));
  PetscCall(DMSwarmSetType(*sw, DMSWARM_BASIC));
  PetscCall(DMSwarmInitializeFieldRegister(*sw));
  for (const FieldSpec &f : particleFields())
    if (corners || !f.cornersOnly)
      PetscCall(DMSwarmRegisterPetscDatatypeField(*sw, f.name, f.components, f.type));
  PetscCall(DMSwarmFinalizeFieldRegister(*sw));
  if (corners) { // mark the swarm, so that ParticleView::get knows the field is there
    PetscContainer mark;
    PetscCall(PetscContainerCreate(comm, &mark));
    PetscCall(PetscObjectCompose(reinterpret_cast<PetscObject>(*sw), "gimp_corners",
                                 reinterpret_cast<PetscObject>(mark)));
    PetscCall(PetscContainerDestroy(&mark));
  }
  return PETSC_SUCCESS;
}

} // namespace gimp
