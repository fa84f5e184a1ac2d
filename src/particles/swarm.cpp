#include "gimp/particles/swarm.hpp"
#include "gimp/input/scene.hpp"

#include <algorithm>
#include <cstring>

namespace gimp {

namespace {

template <typename T> void **slotOf(T *&p) {
  return reinterpret_cast<void **>(&p);
}

} // namespace

template <int D> const std::vector<FieldSpec<D>> &particleFields() {
  using ParticleView = gimp::ParticleView<D>;
  static const std::vector<FieldSpec<D>> fields = {
      {"x", D, PETSC_REAL, true, FieldNeed::Always, [](ParticleView &p) { return slotOf(p.x); }},
      {"X0", D, PETSC_REAL, true, FieldNeed::Always, [](ParticleView &p) { return slotOf(p.X0); }},
      {"v", D, PETSC_REAL, true, FieldNeed::Always, [](ParticleView &p) { return slotOf(p.v); }},
      {"m", 1, PETSC_REAL, true, FieldNeed::Always, [](ParticleView &p) { return slotOf(p.m); }},
      {"V0", 1, PETSC_REAL, false, FieldNeed::Always, [](ParticleView &p) { return slotOf(p.V0); }},
      {"V", 1, PETSC_REAL, true, FieldNeed::Always, [](ParticleView &p) { return slotOf(p.V); }},
      {"l", D, PETSC_REAL, true, FieldNeed::Always, [](ParticleView &p) { return slotOf(p.l); }},
      {"l0", D, PETSC_REAL, false, FieldNeed::Always, [](ParticleView &p) { return slotOf(p.l0); }},
      {"F", D * D, PETSC_REAL, false, FieldNeed::Always,
       [](ParticleView &p) { return slotOf(p.F); }},
      {"stress", kStress<D>, PETSC_REAL, true, FieldNeed::Always,
       [](ParticleView &p) { return slotOf(p.s); }, true},
      {"szz", 1, PETSC_REAL, true, D == 2 ? FieldNeed::Always : FieldNeed::Never,
       [](ParticleView &p) { return slotOf(p.szz); }},
      {"eps", D, PETSC_REAL, false, FieldNeed::Strain,
       [](ParticleView &p) { return slotOf(p.eps); }},
      {"id", 1, PETSC_INT64, false, FieldNeed::Always,
       [](ParticleView &p) { return slotOf(p.id); }},
      {"trac", D, PETSC_INT, false, FieldNeed::Boundary,
       [](ParticleView &p) { return slotOf(p.trac); }},
      {"dbc", D, PETSC_INT, false, FieldNeed::Boundary,
       [](ParticleView &p) { return slotOf(p.dbc); }},
      {"rate", 1, PETSC_INT, false, FieldNeed::Multirate,
       [](ParticleView &p) { return slotOf(p.rate); }},
      {"B", D * D, PETSC_REAL, true, FieldNeed::Affine,
       [](ParticleView &p) { return slotOf(p.B); }},
      {"corners", (1 << D) * D, PETSC_REAL, true, FieldNeed::Corners,
       [](ParticleView &p) { return slotOf(p.corners); }},
      {"us", D, PETSC_REAL, false, FieldNeed::Cracks, [](ParticleView &p) { return slotOf(p.us); }},
  };
  return fields;
}

namespace {
constexpr int kOptional = 6;
const char *const kMarks[kOptional] = {"gimp_corners",  "gimp_strain",    "gimp_affine",
                                       "gimp_boundary", "gimp_multirate", "gimp_cracks"};
} // namespace

template <int D> OptionalFields optionalFieldsOf(const Scene<D> &sc) {
  OptionalFields o;
  o.corners = tracksCorners(sc.tracking);
  o.strain = sc.tracking == Tracking::Strain || sc.tracking == Tracking::Corners;
  o.affine = sc.transfer == Transfer::Apic;
  o.boundary = !sc.tractions.empty() || !sc.dbcs.empty();
  o.multirate = sc.multirate;
  o.cracks = D == 2 && !sc.cracks.empty();
  return o;
}

PetscErrorCode swarmOptionalFields(DM sw, OptionalFields &optional) {
  bool *flag[kOptional] = {&optional.corners,  &optional.strain,    &optional.affine,
                           &optional.boundary, &optional.multirate, &optional.cracks};
  for (int i = 0; i < kOptional; ++i) {
    PetscObject mark = nullptr;
    PetscCall(PetscObjectQuery(reinterpret_cast<PetscObject>(sw), kMarks[i], &mark));
    *flag[i] = mark != nullptr;
  }
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode ParticleView<D>::get(DM sw) {
  PetscCall(swarmOptionalFields(sw, fields));
  hasCorners = fields.corners;
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  for (const FieldSpec<D> &f : particleFields<D>())
    if (fields.has(f.need)) PetscCall(DMSwarmGetField(sw, f.name, nullptr, nullptr, f.slot(*this)));
  PetscCall(DMSwarmGetField(sw, DMSwarmField_rank, nullptr, nullptr, slotOf(rank)));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode ParticleView<D>::restore(DM sw) {
  for (const FieldSpec<D> &f : particleFields<D>())
    if (fields.has(f.need))
      PetscCall(DMSwarmRestoreField(sw, f.name, nullptr, nullptr, f.slot(*this)));
  PetscCall(DMSwarmRestoreField(sw, DMSwarmField_rank, nullptr, nullptr, slotOf(rank)));
  return PETSC_SUCCESS;
}

template <int D> ParticleView<D> ParticleView<D>::slice(PetscInt k0, PetscInt k1) const {
  ParticleView q = *this;
  q.n = k1 - k0;
  for (const FieldSpec<D> &f : particleFields<D>()) {
    char **a = reinterpret_cast<char **>(f.slot(q));
    const size_t size = f.type == PETSC_INT     ? sizeof(PetscInt)
                        : f.type == PETSC_INT64 ? sizeof(PetscInt64)
                                                : sizeof(PetscReal);
    if (*a) *a += static_cast<size_t>(k0) * size * static_cast<size_t>(f.components);
  }
  if (q.rank) q.rank += k0;
  return q;
}

template <int D> PetscErrorCode createSwarm(MPI_Comm comm, OptionalFields optional, DM *sw) {
  PetscCall(DMCreate(comm, sw));
  PetscCall(DMSetType(*sw, DMSWARM));
  PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(*sw), "particles"));
  PetscCall(DMSetDimension(*sw, D));
  PetscCall(DMSwarmSetType(*sw, DMSWARM_BASIC));
  PetscCall(DMSwarmInitializeFieldRegister(*sw));
  for (const FieldSpec<D> &f : particleFields<D>())
    if (optional.has(f.need))
      PetscCall(DMSwarmRegisterPetscDatatypeField(*sw, f.name, f.components, f.type));
  PetscCall(DMSwarmFinalizeFieldRegister(*sw));
  // Mark the swarm with its optional fields, so that ParticleView::get knows which are there.
  const bool flag[kOptional] = {optional.corners,  optional.strain,    optional.affine,
                                optional.boundary, optional.multirate, optional.cracks};
  for (int i = 0; i < kOptional; ++i) {
    if (!flag[i]) continue;
    PetscContainer mark;
    PetscCall(PetscContainerCreate(comm, &mark));
    PetscCall(PetscObjectCompose(reinterpret_cast<PetscObject>(*sw), kMarks[i],
                                 reinterpret_cast<PetscObject>(mark)));
    PetscCall(PetscContainerDestroy(&mark));
  }
  return PETSC_SUCCESS;
}

namespace {

/// Every field of the swarm (gimp's and DMSwarm's pid and rank) as rows of bytes: f(rows, row
/// size) for each, between DMSwarmGetField and DMSwarmRestoreField.
template <int D, class F> PetscErrorCode forEachFieldRows(DM sw, F &&f) {
  OptionalFields optional;
  PetscCall(swarmOptionalFields(sw, optional));
  std::vector<const char *> names;
  for (const FieldSpec<D> &fs : particleFields<D>())
    if (optional.has(fs.need)) names.push_back(fs.name);
  names.push_back(DMSwarmField_pid);
  names.push_back(DMSwarmField_rank);
  for (const char *name : names) {
    PetscInt bs = 0;
    PetscDataType type;
    void *data = nullptr;
    PetscCall(DMSwarmGetField(sw, name, &bs, &type, &data));
    size_t size = 0;
    PetscCall(PetscDataTypeGetSize(type, &size));
    f(static_cast<char *>(data), size * static_cast<size_t>(bs));
    PetscCall(DMSwarmRestoreField(sw, name, &bs, &type, &data));
  }
  return PETSC_SUCCESS;
}

/// Every field's rows from[j] gathered, then written back to rows at[j], or with `at` null to
/// rows 0, 1, ... (a whole permutation).
template <int D>
PetscErrorCode moveRows(DM sw, const std::vector<PetscInt> &from, const std::vector<PetscInt> *at) {
  std::vector<char> scratch;
  const size_t n = from.size();
  return forEachFieldRows<D>(sw, [&](char *rows, size_t row) {
    scratch.resize(row * n);
    for (size_t j = 0; j < n; ++j)
      std::memcpy(&scratch[j * row], rows + static_cast<size_t>(from[j]) * row, row);
    if (!at)
      std::memcpy(rows, scratch.data(), row * n);
    else
      for (size_t j = 0; j < n; ++j)
        std::memcpy(rows + static_cast<size_t>((*at)[j]) * row, &scratch[j * row], row);
  });
}

} // namespace

template <int D> PetscErrorCode permuteSwarm(DM sw, const std::vector<PetscInt> &order) {
  return moveRows<D>(sw, order, nullptr);
}

template <int D>
PetscErrorCode permuteSwarmAt(DM sw, const std::vector<PetscInt> &at,
                              const std::vector<PetscInt> &from) {
  return moveRows<D>(sw, from, &at);
}

void classMoves(const std::vector<int> &cls, std::vector<PetscInt> &at,
                std::vector<PetscInt> &from) {
  // Class c's range is [begin_c, begin_c+1) (classes in order, by their counts). The particles
  // of class c outside its range fill the places in it held by other classes, both in index
  // order: a class change moves a few particles, where a stable partition would move every
  // particle behind the first one that changed.
  at.clear();
  from.clear();
  if (cls.empty()) return;
  const int nc = 1 + *std::max_element(cls.begin(), cls.end());
  std::vector<PetscInt> begin(static_cast<size_t>(nc) + 1, 0);
  for (int c : cls)
    ++begin[static_cast<size_t>(c) + 1];
  for (int c = 0; c < nc; ++c)
    begin[c + 1] += begin[c];
  std::vector<std::vector<PetscInt>> strays(static_cast<size_t>(nc));
  for (PetscInt k = 0; k < static_cast<PetscInt>(cls.size()); ++k)
    if (k < begin[cls[k]] || k >= begin[cls[k] + 1]) strays[cls[k]].push_back(k);
  for (int c = 0; c < nc; ++c) {
    for (PetscInt k = begin[c]; k < begin[c + 1]; ++k)
      if (cls[k] != c) at.push_back(k);
    from.insert(from.end(), strays[c].begin(), strays[c].end());
  }
}

template <int D> PetscErrorCode appendCopies(DM sw, const std::vector<PetscInt> &from) {
  PetscInt n0 = 0;
  PetscCall(DMSwarmGetLocalSize(sw, &n0));
  PetscCall(DMSwarmAddNPoints(sw, static_cast<PetscInt>(from.size())));
  return forEachFieldRows<D>(sw, [&](char *rows, size_t row) {
    for (size_t j = 0; j < from.size(); ++j)
      std::memcpy(rows + (static_cast<size_t>(n0) + j) * row,
                  rows + static_cast<size_t>(from[j]) * row, row);
  });
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode appendCopies<D>(DM, const std::vector<PetscInt> &);                      \
  template const std::vector<FieldSpec<D>> &particleFields<D>();                                   \
  template OptionalFields optionalFieldsOf<D>(const Scene<D> &);                                   \
  template struct ParticleView<D>;                                                                 \
  template PetscErrorCode createSwarm<D>(MPI_Comm, OptionalFields, DM *);                          \
  template PetscErrorCode permuteSwarm<D>(DM, const std::vector<PetscInt> &);                      \
  template PetscErrorCode permuteSwarmAt<D>(DM, const std::vector<PetscInt> &,                     \
                                            const std::vector<PetscInt> &);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
