// fields.h5 and its XDMF files: the particle fields and each level's nodal velocity and mass,
// one frame per output step (XY or XYZ geometry, a 2D or 3D co-rectilinear mesh per level).
#include "gimp/io/checked.hpp"
#include "gimp/io/output.hpp"
#include "gimp/particles/swarm.hpp"

#include <petscviewerhdf5.h>

#include <cerrno>
#include <cstring>
#include <new>
#include <vector>

#include <sys/mman.h>

namespace gimp {

namespace {

/// The particle fields that the HDF5 output holds for this scene.
template <int D> std::vector<const FieldSpec<D> *> writtenFields(const Scene<D> &sc) {
  std::vector<const FieldSpec<D> *> out;
  const OptionalFields optional = optionalFieldsOf(sc);
  for (const FieldSpec<D> &f : particleFields<D>())
    if (f.written && optional.has(f.need)) out.push_back(&f);
  return out;
}

/// Room for n doubles mapped for one write and unmapped after it, so that it is resident only
/// while it is used (a heap block that large can keep its pages for the rest of the run).
class MappedRoom {
public:
  explicit MappedRoom(size_t n) : bytes_(n * sizeof(double)) {
    if (!bytes_) return;
    void *p = mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    p_ = static_cast<double *>(p);
  }
  MappedRoom(const MappedRoom &) = delete;
  MappedRoom &operator=(const MappedRoom &) = delete;
  ~MappedRoom() {
    if (p_) (void)munmap(p_, bytes_);
  }
  double *data() { return p_; }

private:
  size_t bytes_;
  double *p_ = nullptr;
};

/// XDMF's attribute type of a particle field of c components.
template <int D> const char *attributeType(PetscInt c) {
  if (c == 1) return "Scalar";
  if (D == 2) return "Matrix";
  return c == 3 ? "Vector" : "Tensor";
}

} // namespace

template <int D>
PetscErrorCode Output<D>::writeFields(PetscInt step, double t, DM sw, Vec velocity, Vec mass) {
  // Room for the frame first (a full disk stops the run with one line and the frames written
  // before intact); a write that still fails returns an error instead of printing PETSc's and
  // HDF5's stacks, and every rank learns of it.
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(sw, &nloc));
  PetscInt64 n = nloc, total = 0;
  PetscCallMPI(MPI_Allreduce(&n, &total, 1, MPI_INT64_T, MPI_SUM, comm_));
  PetscCall(reserveFrame(step, frameBytes(total)));
  PetscErrorCode ierr;
  int err;
  {
    const QuietErrors quiet(true);
    errno = 0;
    ierr = writeFrame(step, t, sw, velocity, mass);
    err = errno;
  }
  std::string error;
  if (ierr)
    error = "option -gimp_output_dir " + dir_ + ": cannot write fields.h5 at step " +
            std::to_string(static_cast<long long>(step)) + " (" +
            (err ? std::strerror(err) : "the HDF5 write failed") + ")";
  PetscCall(agree(comm_, error));
  releaseFrame();
  frames_.push_back({step, t, static_cast<long long>(total)});
  PetscCall(writeXdmf());
  return PETSC_SUCCESS;
}

template <int D> long double Output<D>::frameBytes(PetscInt64 particles) const {
  // The data of one frame, twice over for HDF5's chunks and headers, and 1 MB of metadata.
  long double components = 0, nodes = 0;
  for (const FieldSpec<D> *fs : writtenFields(sc_))
    components += fs->writtenComponents();
  for (const Level<D> &L : grid_.levels) {
    long double m = 1;
    for (int a = 0; a < D; ++a)
      m *= L.n[a];
    nodes += m;
  }
  return 2 * 8 * (particles * components + (D + 1) * nodes) + (1 << 20);
}

template <int D>
PetscErrorCode Output<D>::writeFrame(PetscInt step, double t, DM sw, Vec velocity, Vec mass) {
  // Every object borrowed here is given back before an error returns, so that a failed write
  // leaves the swarm and the grid usable and the run can stop cleanly.
  PetscViewer v = nullptr;
  const std::string file = dir_ + "/fields.h5";
  PetscCall(PetscViewerHDF5Open(comm_, file.c_str(),
                                frames_.empty() ? FILE_MODE_WRITE : FILE_MODE_APPEND, &v));
  PetscErrorCode ierr = writeParticleFrame(v, frameGroup(step), t, sw);
  if (!ierr) ierr = writeGridFrame(v, frameGroup(step), velocity, mass);
  const PetscErrorCode closed = PetscViewerDestroy(&v);
  PetscCall(ierr);
  PetscCall(closed);
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Output<D>::writeParticleFrame(PetscViewer v, const std::string &g, double t,
                                             DM sw) const {
  PetscCall(PetscViewerHDF5PushGroup(v, ("/particles/" + g).c_str()));
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(sw, &nloc));
  for (const FieldSpec<D> *fs : writtenFields(sc_)) {
    // A plain MPI Vec over the field array: written as an (N, components) dataset.
    PetscScalar *data = nullptr;
    Vec f;
    const PetscInt bs = fs->writtenComponents();
    PetscCall(DMSwarmGetField(sw, fs->name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
    const PetscScalar *from = data;
    MappedRoom full(fs->symmetric ? static_cast<size_t>(D * D) * static_cast<size_t>(nloc) : 0);
    if (fs->symmetric) { // (the stress as full D x D tensors)
      for (PetscInt k = 0; k < nloc; ++k)
        tensorAt<D>(full.data(), k) = stressAt<D>(data, k);
      from = full.data();
    }
    PetscCall(VecCreateMPIWithArray(comm_, bs, bs * nloc, PETSC_DECIDE, from, &f));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(f), fs->name));
    const PetscErrorCode ierr = VecView(f, v);
    PetscCall(VecDestroy(&f));
    PetscCall(
        DMSwarmRestoreField(sw, fs->name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
    PetscCall(ierr);
  }
  PetscCall(PetscViewerHDF5WriteAttribute(v, nullptr, "time", PETSC_DOUBLE, &t));
  PetscCall(PetscViewerHDF5PopGroup(v));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Output<D>::writeGridFrame(PetscViewer v, const std::string &g, Vec velocity,
                                         Vec mass) const {
  // Each level's velocity and mass as ([P,] N, M[, D]) datasets.
  const int K = static_cast<int>(grid_.levels.size());
  std::vector<Vec> vel(K), ms(K);
  PetscCall(DMCompositeGetAccessArray(grid_.dm, velocity, K, nullptr, vel.data()));
  PetscCall(DMCompositeGetAccessArray(grid_.dm, mass, K, nullptr, ms.data()));
  PetscErrorCode ierr = PETSC_SUCCESS;
  for (int k = 0; k < K && !ierr; ++k) {
    Vec m1;
    PetscCall(PetscViewerHDF5PushGroup(v, ("/grid/" + g + "/level_" + std::to_string(k)).c_str()));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(vel[k]), "velocity"));
    ierr = VecView(vel[k], v);
    PetscCall(DMGetGlobalVector(grid_.da1[k], &m1));
    PetscCall(VecStrideGather(ms[k], 0, m1, INSERT_VALUES));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(m1), "mass"));
    if (!ierr) ierr = VecView(m1, v);
    PetscCall(DMRestoreGlobalVector(grid_.da1[k], &m1));
    PetscCall(PetscViewerHDF5PopGroup(v));
  }
  PetscCall(DMCompositeRestoreAccessArray(grid_.dm, mass, K, nullptr, ms.data()));
  PetscCall(DMCompositeRestoreAccessArray(grid_.dm, velocity, K, nullptr, vel.data()));
  PetscCall(ierr);
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Output<D>::writeXdmf() const {
  // Written whole to a temporary file and renamed: a failure leaves the previous version.
  FILE *fp = nullptr, *fg = nullptr;
  PetscCall(openOnRoot("particles.xmf", &fp, true));
  PetscCall(openOnRoot("grid.xmf", &fg, true));
  if (rank_ == 0) {
    const char *head = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
                       "<Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    const char *tail = "</Grid>\n</Domain>\n</Xdmf>\n";
    std::fprintf(fp, head, "particles");
    std::fprintf(fg, head, "grid");
    writeParticleXdmf(fp);
    writeGridXdmf(fg);
    std::fputs(tail, fp);
    std::fputs(tail, fg);
  }
  PetscCall(closeOnRoot("particles.xmf", fp, true));
  PetscCall(closeOnRoot("grid.xmf", fg, true));
  return PETSC_SUCCESS;
}

template <int D> void Output<D>::writeParticleXdmf(FILE *fp) const {
  for (const OutputFrame &fr : frames_) {
    const std::string g = frameGroup(fr.step);
    std::fprintf(fp,
                 " <Grid Name=\"%s\" GridType=\"Uniform\">\n  <Time Value=\"%.12e\"/>\n"
                 "  <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%lld\"/>\n"
                 "  <Geometry GeometryType=\"%s\"><DataItem Dimensions=\"%lld %d\" "
                 "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/particles/%s/x"
                 "</DataItem></Geometry>\n",
                 g.c_str(), fr.t, fr.particles, D == 2 ? "XY" : "XYZ", fr.particles, D, g.c_str());
    for (const FieldSpec<D> *fs : writtenFields(sc_)) {
      if (std::string(fs->name) == "x") continue;
      const PetscInt c = fs->writtenComponents();
      const std::string dims = c == 1 ? "" : " " + std::to_string(static_cast<int>(c));
      std::fprintf(fp,
                   "  <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\"><DataItem "
                   "Dimensions=\"%lld%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                   "fields.h5:/particles/%s/%s</DataItem></Attribute>\n",
                   fs->name, attributeType<D>(c), fr.particles, dims.c_str(), g.c_str(), fs->name);
    }
    std::fprintf(fp, " </Grid>\n");
  }
}

template <int D> const double *Output<D>::levelOrigin(size_t k, PetscInt step) const {
  // A frame is written after its step's report, before that step's moves: the box it shows is
  // the one the first later move of the level left (its previous box), or the current one.
  for (const RegridRecord &r : moves_)
    if (r.level == static_cast<int>(k) && r.step >= step) return r.previous.data();
  return grid_.levels[k].box.data();
}

template <int D> void Output<D>::writeGridXdmf(FILE *fg) const {
  // A co-rectilinear mesh per level: its node counts and origin slowest axis first, as the
  // DMDA's datasets are laid out.
  for (const OutputFrame &fr : frames_) {
    const std::string g = frameGroup(fr.step);
    std::fprintf(fg,
                 " <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
                 "  <Time Value=\"%.12e\"/>\n",
                 g.c_str(), fr.t);
    for (size_t k = 0; k < grid_.levels.size(); ++k) {
      const Level<D> &L = grid_.levels[k];
      std::string dims, origin, step;
      const double *lo = levelOrigin(k, fr.step);
      for (int a = D - 1; a >= 0; --a) {
        char b[64];
        dims += (dims.empty() ? "" : " ") + std::to_string(static_cast<long long>(L.n[a]));
        std::snprintf(b, sizeof(b), "%s%.17g", origin.empty() ? "" : " ", lo[a]);
        origin += b;
        std::snprintf(b, sizeof(b), "%s%.17g", step.empty() ? "" : " ", L.h);
        step += b;
      }
      const std::string ref = "fields.h5:/grid/" + g + "/level_" + std::to_string(k);
      std::fprintf(fg,
                   "  <Grid Name=\"level_%zu\" GridType=\"Uniform\">\n"
                   "   <Topology TopologyType=\"%dDCoRectMesh\" Dimensions=\"%s\"/>\n"
                   "   <Geometry GeometryType=\"%s\">\n"
                   "    <DataItem Dimensions=\"%d\" NumberType=\"Float\" Format=\"XML\">%s"
                   "</DataItem>\n"
                   "    <DataItem Dimensions=\"%d\" NumberType=\"Float\" Format=\"XML\">%s"
                   "</DataItem>\n   </Geometry>\n"
                   "   <Attribute Name=\"mass\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
                   "Dimensions=\"%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                   "%s/mass</DataItem></Attribute>\n"
                   "   <Attribute Name=\"velocity\" AttributeType=\"%s\" Center=\"Node\">"
                   "<DataItem Dimensions=\"%s %d\" NumberType=\"Float\" Precision=\"8\" "
                   "Format=\"HDF\">%s/velocity</DataItem></Attribute>\n  </Grid>\n",
                   k, D, dims.c_str(), D == 2 ? "ORIGIN_DXDY" : "ORIGIN_DXDYDZ", D, origin.c_str(),
                   D, step.c_str(), dims.c_str(), ref.c_str(), D == 2 ? "Matrix" : "Vector",
                   dims.c_str(), D, ref.c_str());
    }
    std::fprintf(fg, " </Grid>\n");
  }
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode Output<D>::writeFields(PetscInt, double, DM, Vec, Vec);                  \
  template PetscErrorCode Output<D>::writeXdmf() const;
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
