#include "gimp/io/output.hpp"

#include "gimp/io/checked.hpp"

#include "gimp/particles/swarm.hpp"

#include <hdf5.h>
#include <petscviewerhdf5.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace gimp {

namespace {

/// The particle fields that the HDF5 output holds for this scene.
std::vector<const FieldSpec<2> *> writtenFields(const Scene<2> &sc) {
  std::vector<const FieldSpec<2> *> out;
  const OptionalFields optional = optionalFieldsOf(sc);
  for (const FieldSpec<2> &f : particleFields<2>())
    if (f.written && optional.has(f.need)) out.push_back(&f);
  return out;
}

/// Before a frame: room for `bytes` more in `file` (within the process's file size limit, and
/// reserved on the disk where the file system can), or the reason there is none. HDF5 must
/// never meet a failed write: it keeps the file open and unreadable, and its own clean-up at
/// MPI_Finalize then crashes writing to it again.
std::string reserveSpace(const std::string &file, long double bytes) {
  struct stat st {};
  const long double size = ::stat(file.c_str(), &st) == 0 ? st.st_size : 0;
  rlimit lim{};
  if (getrlimit(RLIMIT_FSIZE, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY &&
      size + bytes > static_cast<long double>(lim.rlim_cur))
    return std::strerror(EFBIG);
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT, 0644);
  if (fd < 0) return std::strerror(errno);
  int err =
      fallocate(fd, FALLOC_FL_KEEP_SIZE, static_cast<off_t>(size), static_cast<off_t>(bytes)) == 0
          ? 0
          : errno;
  ::close(fd);
  if (err == EOPNOTSUPP || err == ENOSYS) err = 0; // the file system cannot tell in advance
  return err ? std::strerror(err) : "";
}

/// After a frame (the file closed by every rank): give back what reserveSpace kept beyond the
/// end of the file (truncating to its own size frees blocks allocated past it).
void releaseSpace(const std::string &file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return;
  if (truncate(file.c_str(), st.st_size) != 0) return; // the blocks only stay allocated
}

} // namespace

Output::~Output() {
  if (history_) std::fclose(history_);
}

PetscErrorCode Output::openOnRoot(const std::string &name, FILE **f, bool whole) const {
  *f = nullptr;
  std::string error;
  if (rank_ == 0) {
    *f = std::fopen((dir_ + "/" + name + (whole ? ".tmp" : "")).c_str(), "w");
    if (!*f)
      error = "option -gimp_output_dir " + dir_ + ": cannot write " + name + " there (" +
              std::strerror(errno) + ")";
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

PetscErrorCode Output::closeOnRoot(const std::string &name, FILE *f, bool whole) const {
  std::string error;
  if (rank_ == 0) {
    const std::string path = dir_ + "/" + name;
    error = closeChecked(f);
    if (error.empty() && whole && std::rename((path + ".tmp").c_str(), path.c_str()) != 0)
      error = std::strerror(errno);
    if (!error.empty()) {
      if (whole) std::remove((path + ".tmp").c_str());
      error = "option -gimp_output_dir " + dir_ + ": cannot write " + name + " (" + error + ")";
    }
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

/// Rank 0: the dump paths can be written (not a directory, in a directory that exists, the
/// particle dump can be created), and the particle dump of an earlier run is gone.
std::string Output::checkDumpPaths() const {
  namespace fs = std::filesystem;
  for (const auto &[option, file] :
       {std::pair<std::string, std::string>{"gimp_particle_dump", sc_.particleDump},
        {"gimp_grid_dump", sc_.gridDump}}) {
    if (file.empty()) continue;
    std::error_code ec;
    const fs::path parent = fs::path(file).parent_path();
    if (fs::is_directory(file, ec))
      return "option -" + option + " " + file + ": is a directory, not a file";
    if (!parent.empty() && !fs::is_directory(parent, ec))
      return "option -" + option + " " + file + ": " + parent.string() +
             " is not a directory that exists";
  }
  // The particle dump is written at the end: try now that it can be created, then leave no
  // file (neither this probe nor an earlier run's dump).
  const std::string &dump = sc_.particleDump;
  std::error_code ec;
  if (dump.empty()) return "";
  if (fs::is_regular_file(dump, ec)) fs::remove(dump, ec);
  FILE *f = std::fopen(dump.c_str(), "w");
  if (!f)
    return "option -gimp_particle_dump " + dump + ": cannot open the file (" +
           std::strerror(errno) + ")";
  std::fclose(f);
  if (fs::is_regular_file(dump, ec)) fs::remove(dump, ec);
  return "";
}

PetscErrorCode Output::open(const Resume *resume) {
  PetscCallMPI(MPI_Comm_rank(comm_, &rank_));
  dir_ = sc_.outputDir;
  std::string error;
  if (rank_ == 0) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec)
      error = "option -gimp_output_dir " + dir_ + ": cannot create it (" + ec.message() + ")";
    else if (!std::filesystem::is_directory(dir_, ec))
      error = "option -gimp_output_dir " + dir_ + ": is not a directory";
    // Remove every file an earlier run in the same directory wrote (and the temporary files of
    // one that was killed while writing): a run that fails later leaves none of them behind.
    // A restart keeps the frames its checkpoint lists (resumeFrames) and the checkpoint; a fresh
    // run also removes an earlier checkpoint, which no longer matches.
    std::vector<std::string> stale{"summary.json", "hoop.csv", "hoop_fit.csv", "history.csv"};
    if (resume) stale.push_back("checkpoint.h5.tmp"); // left by a crash while writing
    if (!resume)
      stale.insert(stale.end(), {"fields.h5", "particles.xmf", "grid.xmf", "checkpoint.h5"});
    for (const std::string &name : stale)
      for (const char *tail : {"", ".tmp"})
        if (error.empty() && !std::filesystem::remove(dir_ + "/" + name + tail, ec) && ec)
          error = "option -gimp_output_dir " + dir_ + ": cannot remove the earlier run's " + name +
                  tail + " (" + ec.message() + ")";
    if (error.empty()) error = checkDumpPaths();
  }
  PetscCall(agree(comm_, error));
  PetscCall(openOnRoot("history.csv", &history_, false));
  if (resume) { // a restart: the history up to the checkpoint, the frames it had written
    if (rank_ == 0) std::fwrite(resume->history.data(), 1, resume->history.size(), history_);
    PetscCall(flushHistory(0));
    return resumeFrames(resume->frames);
  }
  if (rank_ == 0) {
    std::fprintf(history_,
                 "step,time,kinetic,strain,external_work,damping,total,momentum_x,momentum_y,"
                 "separation,strain_x");
    for (const Probe<2> &p : sc_.probes)
      for (const char *c : {"ux", "uy", "sxx", "syy", "sxy", "szz"})
        std::fprintf(history_, ",%s_%s", p.name.c_str(), c);
    for (size_t q = 0; q < sc_.dbcs.size(); ++q)
      std::fprintf(history_, ",dbc%zu_fx,dbc%zu_fy,dbc%zu_gap", q, q, q);
    if (sc_.mms != Mms::None) std::fprintf(history_, ",mms_linf,mms_rms");
    for (const cracks::TipMeasure &m : cracks::tipsOf(sc_))
      for (const char *c : {"G_vcct", "GII_vcct", "G_J", "KI_vcct", "KII_vcct", "KI_J", "KII_J",
                            "opening_n", "opening_t"})
        std::fprintf(history_, ",crack%d_tip%d_%s", m.crack, m.end, c);
    std::fprintf(history_, "\n");
  }
  return flushHistory(0);
}

PetscErrorCode Output::flushHistory(long rowStart) {
  std::string error;
  if (rank_ == 0) {
    errno = 0;
    if (std::fflush(history_) != 0 || std::ferror(history_)) {
      error = "option -gimp_output_dir " + dir_ + ": cannot write history.csv (" +
              std::strerror(errno ? errno : EIO) + ")";
      // No half row: the rows before stay a valid CSV file.
      if (ftruncate(fileno(history_), rowStart) != 0) error += ", its last row may be partial";
    }
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeHistory(const HistoryRow &r) {
  if (rank_ != 0) return flushHistory(0);
  const long rowStart = std::ftell(history_);
  const Energies &e = r.energy;
  std::fprintf(history_, "%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e",
               static_cast<long long>(r.step), r.t, e.kinetic, e.strain, e.externalWork, e.damping,
               e.total(), e.momentum[0], e.momentum[1]);
  std::fprintf(history_, ",%.12e,%.12e", r.separation, r.strainX);
  for (const ProbeState &p : r.probes)
    std::fprintf(history_, ",%.12e,%.12e,%.12e,%.12e,%.12e,%.12e", p.u[0], p.u[1], p.stress[0],
                 p.stress[1], p.stress[2], p.stress[3]);
  for (size_t q = 0; q < r.gaps.size(); ++q)
    std::fprintf(history_, ",%.12e,%.12e,%.12e", r.reactions[2 * q], r.reactions[2 * q + 1],
                 r.gaps[q]);
  if (sc_.mms != Mms::None) std::fprintf(history_, ",%.12e,%.12e", r.mmsLinf, r.mmsRms);
  for (const cracks::TipMeasure &m : r.tips)
    std::fprintf(history_, ",%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e", m.G_vcct,
                 m.GII_vcct, m.G_J, m.KI_vcct, m.KII_vcct, m.KI_J, m.KII_J, m.opening[0],
                 m.opening[1]);
  std::fprintf(history_, "\n");
  return flushHistory(rowStart);
}

PetscErrorCode Output::writeFields(PetscInt step, double t, DM sw, Vec velocity, Vec mass) {
  // Room for the frame first (a full disk stops the run with one line and the frames written
  // before intact); a write that still fails returns an error instead of printing PETSc's and
  // HDF5's stacks, and every rank learns of it.
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(sw, &nloc));
  PetscInt64 n = nloc, total = 0;
  PetscCallMPI(MPI_Allreduce(&n, &total, 1, MPI_INT64_T, MPI_SUM, comm_));
  const std::string where = "option -gimp_output_dir " + dir_ +
                            ": cannot write fields.h5 at step " +
                            std::to_string(static_cast<long long>(step)) + " (";
  std::string error;
  if (rank_ == 0) {
    const std::string reason = reserveSpace(dir_ + "/fields.h5", frameBytes(total));
    if (!reason.empty()) error = where + reason + ")";
  }
  PetscCall(agree(comm_, error));
  PetscErrorCode ierr;
  int err;
  {
    const QuietErrors quiet(true);
    errno = 0;
    ierr = writeFrame(step, t, sw, velocity, mass);
    err = errno;
  }
  if (ierr) error = where + (err ? std::strerror(err) : "the HDF5 write failed") + ")";
  PetscCall(agree(comm_, error));
  if (rank_ == 0) releaseSpace(dir_ + "/fields.h5");
  frames_.push_back({step, t, static_cast<long long>(total)});
  PetscCall(writeXdmf());
  return PETSC_SUCCESS;
}

long double Output::frameBytes(PetscInt64 particles) const {
  // The data of one frame, twice over for HDF5's chunks and headers, and 1 MB of metadata.
  long double components = 0, nodes = 0;
  for (const FieldSpec<2> *fs : writtenFields(sc_))
    components += fs->components;
  for (const Level<2> &L : grid_.levels)
    nodes += static_cast<long double>(L.n[0]) * L.n[1];
  return 2 * 8 * (particles * components + 3 * nodes) + (1 << 20);
}

PetscErrorCode Output::writeFrame(PetscInt step, double t, DM sw, Vec velocity, Vec mass) {
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

PetscErrorCode Output::writeParticleFrame(PetscViewer v, const std::string &g, double t,
                                          DM sw) const {
  PetscCall(PetscViewerHDF5PushGroup(v, ("/particles/" + g).c_str()));
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(sw, &nloc));
  for (const FieldSpec<2> *fs : writtenFields(sc_)) {
    // A plain MPI Vec over the field array: written as an (N, components) dataset.
    PetscScalar *data = nullptr;
    Vec f;
    const PetscInt bs = fs->components;
    PetscCall(DMSwarmGetField(sw, fs->name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
    PetscCall(VecCreateMPIWithArray(comm_, bs, bs * nloc, PETSC_DECIDE, data, &f));
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

PetscErrorCode Output::writeGridFrame(PetscViewer v, const std::string &g, Vec velocity,
                                      Vec mass) const {
  // Each level's velocity and mass as (N, M[, 2]) datasets.
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

PetscErrorCode Output::writeXdmf() const {
  // Written whole to a temporary file and renamed: a failure leaves the previous version.
  FILE *fp = nullptr, *fg = nullptr;
  PetscCall(openOnRoot("particles.xmf", &fp, true));
  PetscCall(openOnRoot("grid.xmf", &fg, true));
  if (rank_ == 0) {
    const char *head =
        "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
        "<Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    const char *tail = "</Grid>\n</Domain>\n</Xdmf>\n";
    std::fprintf(fp, head, "particles");
    std::fprintf(fg, head, "grid");
    PetscCall(writeParticleXdmf(fp));
    PetscCall(writeGridXdmf(fg));
    std::fputs(tail, fp);
    std::fputs(tail, fg);
  }
  PetscCall(closeOnRoot("particles.xmf", fp, true));
  PetscCall(closeOnRoot("grid.xmf", fg, true));
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeParticleXdmf(FILE *fp) const {
  for (const Frame &fr : frames_) {
    const std::string g = frameGroup(fr.step);
    std::fprintf(fp,
                 " <Grid Name=\"%s\" GridType=\"Uniform\">\n  <Time Value=\"%.12e\"/>\n"
                 "  <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%lld\"/>\n"
                 "  <Geometry GeometryType=\"XY\"><DataItem Dimensions=\"%lld 2\" "
                 "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/particles/%s/x"
                 "</DataItem></Geometry>\n",
                 g.c_str(), fr.t, fr.particles, fr.particles, g.c_str());
    for (const FieldSpec<2> *fs : writtenFields(sc_)) {
      if (std::string(fs->name) == "x") continue;
      const std::string dims =
          fs->components == 1 ? "" : " " + std::to_string(static_cast<int>(fs->components));
      std::fprintf(fp,
                   "  <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\"><DataItem "
                   "Dimensions=\"%lld%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                   "fields.h5:/particles/%s/%s</DataItem></Attribute>\n",
                   fs->name, fs->components == 1 ? "Scalar" : "Matrix", fr.particles, dims.c_str(),
                   g.c_str(), fs->name);
    }
    std::fprintf(fp, " </Grid>\n");
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeGridXdmf(FILE *fg) const {
  for (const Frame &fr : frames_) {
    const std::string g = frameGroup(fr.step);
    std::fprintf(fg,
                 " <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
                 "  <Time Value=\"%.12e\"/>\n",
                 g.c_str(), fr.t);
    for (size_t k = 0; k < grid_.levels.size(); ++k) {
      const Level<2> &L = grid_.levels[k];
      const long long N = L.n[1], M = L.n[0];
      const std::string ref = "fields.h5:/grid/" + g + "/level_" + std::to_string(k);
      std::fprintf(fg,
                   "  <Grid Name=\"level_%zu\" GridType=\"Uniform\">\n"
                   "   <Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"%lld %lld\"/>\n"
                   "   <Geometry GeometryType=\"ORIGIN_DXDY\">\n"
                   "    <DataItem Dimensions=\"2\" NumberType=\"Float\" Format=\"XML\">%.17g %.17g"
                   "</DataItem>\n"
                   "    <DataItem Dimensions=\"2\" NumberType=\"Float\" Format=\"XML\">%.17g %.17g"
                   "</DataItem>\n   </Geometry>\n"
                   "   <Attribute Name=\"mass\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
                   "Dimensions=\"%lld %lld\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                   "%s/mass</DataItem></Attribute>\n"
                   "   <Attribute Name=\"velocity\" AttributeType=\"Matrix\" Center=\"Node\">"
                   "<DataItem Dimensions=\"%lld %lld 2\" NumberType=\"Float\" Precision=\"8\" "
                   "Format=\"HDF\">%s/velocity</DataItem></Attribute>\n  </Grid>\n",
                   k, N, M, L.box[1], L.box[0], L.h, L.h, N, M, ref.c_str(), N, M, ref.c_str());
    }
    std::fprintf(fg, " </Grid>\n");
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeHoop(const HoleMeasure &h) {
  FILE *f = nullptr;
  PetscCall(openOnRoot("hoop.csv", &f, true));
  if (rank_ == 0) {
    std::fprintf(f, "angle_deg,r,hoop_over_p,kirsch\n");
    for (const std::vector<double> &r : h.rows)
      std::fprintf(f, "%.6f,%.9e,%.9e,%.9e\n", r[0], r[1], r[2], r[3]);
  }
  PetscCall(closeOnRoot("hoop.csv", f, true));
  PetscCall(openOnRoot("hoop_fit.csv", &f, true));
  if (rank_ == 0) {
    std::fprintf(f, "angle_deg,edge_hoop_over_p,kirsch_edge,particles\n");
    for (const auto &c : h.curve)
      std::fprintf(f, "%.3f,%.9e,%.9e,%d\n", c[0], c[1], c[2], static_cast<int>(c[3]));
  }
  return closeOnRoot("hoop_fit.csv", f, true);
}

} // namespace gimp
