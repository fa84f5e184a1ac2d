// Checkpoint and restart (solver/checkpoint.hpp).
#include "gimp/solver/checkpoint.hpp"

#include "checkpoint_file.hpp"
#include "checkpoint_state.hpp"
#include "gimp/input/scene_record.hpp"

#include "gimp/io/checked.hpp"

#include <hdf5.h>
#include <petscviewerhdf5.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>

namespace gimp {

using ckpt::kFormat;
using ckpt::kNScalars;
using ckpt::kScalars;

namespace {

/// An array known on rank 0, written as [n, values...] (never an empty dataset).
PetscErrorCode writeArray(MPI_Comm comm, PetscViewer v, const char *name,
                          const std::vector<double> &a) {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  Vec x;
  PetscCall(
      VecCreateMPI(comm, rank == 0 ? static_cast<PetscInt>(a.size()) + 1 : 0, PETSC_DETERMINE, &x));
  PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(x), name));
  if (rank == 0) {
    PetscScalar *p = nullptr;
    PetscCall(VecGetArray(x, &p));
    p[0] = static_cast<double>(a.size());
    std::copy(a.begin(), a.end(), p + 1);
    PetscCall(VecRestoreArray(x, &p));
  }
  PetscCall(VecView(x, v));
  PetscCall(VecDestroy(&x));
  return PETSC_SUCCESS;
}

/// Such an array, read onto every rank.
PetscErrorCode readArray(MPI_Comm comm, PetscViewer v, const char *name, std::vector<double> &a) {
  Vec x, all;
  VecScatter toAll;
  PetscCall(VecCreate(comm, &x));
  PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(x), name));
  PetscCall(VecLoad(x, v));
  PetscCall(VecScatterCreateToAll(x, &toAll, &all));
  PetscCall(VecScatterBegin(toAll, x, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(toAll, x, all, INSERT_VALUES, SCATTER_FORWARD));
  const PetscScalar *p = nullptr;
  PetscCall(VecGetArrayRead(all, &p));
  a.assign(p + 1, p + 1 + static_cast<size_t>(p[0]));
  PetscCall(VecRestoreArrayRead(all, &p));
  PetscCall(VecScatterDestroy(&toAll));
  PetscCall(VecDestroy(&all));
  PetscCall(VecDestroy(&x));
  return PETSC_SUCCESS;
}

/// A Vec of this rank's n particles' values of field fs (integers as doubles: exact).
template <int D>
PetscErrorCode fieldVec(MPI_Comm comm, const FieldSpec<D> &fs, PetscInt n, Vec *x) {
  PetscCall(VecCreate(comm, x));
  PetscCall(VecSetSizes(*x, fs.components * n, PETSC_DETERMINE));
  PetscCall(VecSetBlockSize(*x, fs.components));
  PetscCall(VecSetType(*x, VECSTANDARD));
  PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(*x), fs.name));
  return PETSC_SUCCESS;
}

template <typename T> void copyAs(T *d, PetscScalar *a, PetscInt count, bool toSwarm) {
  for (PetscInt i = 0; i < count; ++i) {
    if (toSwarm)
      d[i] = static_cast<T>(a[i]);
    else
      a[i] = static_cast<PetscScalar>(d[i]);
  }
}

/// Copy field fs between the swarm and the array a (toSwarm: a -> swarm).
template <int D>
PetscErrorCode copyField(DM sw, const FieldSpec<D> &fs, PetscScalar *a, PetscInt count,
                         bool toSwarm) {
  void *data = nullptr;
  PetscCall(DMSwarmGetField(sw, fs.name, nullptr, nullptr, &data));
  if (fs.type == PETSC_INT64)
    copyAs(static_cast<PetscInt64 *>(data), a, count, toSwarm);
  else if (fs.type == PETSC_INT)
    copyAs(static_cast<PetscInt *>(data), a, count, toSwarm);
  else
    copyAs(static_cast<PetscReal *>(data), a, count, toSwarm);
  PetscCall(DMSwarmRestoreField(sw, fs.name, nullptr, nullptr, &data));
  return PETSC_SUCCESS;
}

/// The swarm's fields (those registered) into the viewer's current group, or back from it.
template <int D> PetscErrorCode transferFields(MPI_Comm comm, PetscViewer v, DM sw, bool load) {
  OptionalFields optional;
  PetscCall(swarmOptionalFields(sw, optional));
  PetscInt n = 0;
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  for (const FieldSpec<D> &fs : particleFields<D>()) {
    if (!optional.has(fs.need)) continue;
    Vec x;
    PetscScalar *a = nullptr;
    PetscCall(fieldVec(comm, fs, n, &x));
    if (load) PetscCall(VecLoad(x, v));
    PetscCall(VecGetArray(x, &a));
    PetscCall(copyField(sw, fs, a, fs.components * n, load));
    PetscCall(VecRestoreArray(x, &a));
    if (!load) PetscCall(VecView(x, v));
    PetscCall(VecDestroy(&x));
  }
  return PETSC_SUCCESS;
}

/// The levels as h, box and node counts: a checkpoint belongs to the grid that wrote it.
template <int D> std::vector<double> gridDescription(const Grid<D> &g) {
  std::vector<double> d;
  for (const Level<D> &L : g.levels) {
    d.push_back(L.h);
    d.insert(d.end(), L.box.begin(), L.box.end());
    for (int a = 0; a < D; ++a)
      d.push_back(static_cast<double>(L.n[a]));
  }
  return d;
}

} // namespace

namespace {

/// Rank 0: why a new file of `bytes` cannot be written in `dir` (the process's file size limit,
/// the free space), or "".
std::string roomFor(const std::string &dir, long double bytes) {
  rlimit lim{};
  if (getrlimit(RLIMIT_FSIZE, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY &&
      bytes > static_cast<long double>(lim.rlim_cur))
    return std::strerror(EFBIG);
  struct statvfs fs {};
  if (statvfs(dir.c_str(), &fs) == 0 &&
      static_cast<long double>(fs.f_bavail) * static_cast<long double>(fs.f_frsize) < bytes)
    return std::strerror(ENOSPC);
  return "";
}

} // namespace

template <int D> PetscErrorCode Checkpoint<D>::write(PetscInt step, double t) {
  RunState<D> &s = s_;
  // Room for the file first (twice its data, history.csv's bytes and 1 MB of metadata), so that
  // HDF5 does not meet a full disk; a write that still fails is one line on every rank, the
  // previous checkpoint whole and no .tmp left.
  const std::string where = "option -gimp_output_dir " + s.sc.outputDir +
                            ": cannot write checkpoint.h5 at step " +
                            std::to_string(static_cast<long long>(step)) + " (";
  std::string error;
  if (s.rank == 0 && record_.empty()) record_ = input::sceneRecord(); // once: it hashes files
  if (s.rank == 0) {
    long double components = 0;
    for (const FieldSpec<D> &fs : particleFields<D>())
      components += fs.components;
    struct stat st {};
    const long double history =
        ::stat((s.sc.outputDir + "/history.csv").c_str(), &st) == 0 ? st.st_size : 0;
    const std::string why =
        roomFor(s.sc.outputDir, 2 * (8 * components * s.nParticles + history) + (1 << 20));
    if (!why.empty()) error = where + why + ")";
  }
  PetscCall(agree(s.comm, error));
  PetscErrorCode ierr;
  int err;
  { // (a failed rename throws on every rank; the guard restores the handlers then too)
    const QuietErrors quiet(true);
    errno = 0;
    ierr = writeFile(step, t);
    err = errno;
  }
  if (ierr) {
    error = where + (err ? std::strerror(err) : "the HDF5 write failed") + ")";
    if (s.rank == 0) std::remove((s.sc.outputDir + "/checkpoint.h5.tmp").c_str());
  }
  PetscCall(agree(s.comm, error));
  return PETSC_SUCCESS;
}

namespace {

/// What moved in the run: the grown cracks (2D) and the levels that follow a point.
template <int D> PetscErrorCode writeMoves(MPI_Comm comm, PetscViewer v, const RunState<D> &s) {
  if (s.sc.follows()) PetscCall(writeArray(comm, v, "follow", followState(s)));
  if (s.sc.growth == Growth::None) return PETSC_SUCCESS;
  std::vector<double> cracks, growth;
  growthState(s, cracks, growth);
  PetscCall(writeArray(comm, v, "cracks", cracks));
  PetscCall(writeArray(comm, v, "growth", growth));
  return PETSC_SUCCESS;
}

} // namespace

template <int D> PetscErrorCode Checkpoint<D>::writeFile(PetscInt step, double t) {
  // Every rank writes into checkpoint.h5.tmp; when all have closed it, rank 0 renames it into
  // place, so a crash while writing leaves the previous checkpoint whole.
  RunState<D> &s = s_;
  const MPI_Comm comm = s.comm;
  PetscCall(PetscLogStagePush(s.stages.output));
  const std::string file = s.sc.outputDir + "/checkpoint.h5", tmp = file + ".tmp";
  PetscViewer v;
  PetscCall(PetscViewerHDF5Open(comm, tmp.c_str(), FILE_MODE_WRITE, &v));
  PetscCall(PetscViewerHDF5PushGroup(v, "/particles"));
  PetscCall(transferFields<D>(comm, v, s.sw, false));
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(s.sw, &nloc));
  PetscInt64 mine = nloc;
  std::vector<PetscInt64> sizes(static_cast<size_t>(s.size));
  PetscCallMPI(MPI_Gather(&mine, 1, MPI_INT64_T, sizes.data(), 1, MPI_INT64_T, 0, comm));
  PetscCall(writeArray(comm, v, "local_sizes", std::vector<double>(sizes.begin(), sizes.end())));
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscViewerHDF5PushGroup(v, "/state"));
  PetscCall(writeArray(comm, v, "grid", gridDescription(s.grid)));
  PetscCall(writeArray(comm, v, "max_gaps", s.boundary.maxGap()));
  std::vector<double> force, gap; // of the last step, for a restart that runs no step
  PetscCall(s.boundary.lastReactions(comm, force, gap));
  PetscCall(writeArray(comm, v, "reactions", force));
  PetscCall(writeArray(comm, v, "gaps", gap));
  std::vector<double> frames;
  for (const OutputFrame &fr : reporter_.output().frames())
    frames.insert(frames.end(),
                  {static_cast<double>(fr.step), fr.t, static_cast<double>(fr.particles)});
  PetscCall(writeArray(comm, v, "frames", frames));
  std::string text; // history.csv's bytes, 8 to a value, after their count
  PetscCall(reporter_.output().historyText(text));
  PetscCall(writeArray(comm, v, "history", ckpt::packText(text)));
  PetscCall(writeArray(comm, v, "scene", ckpt::packText(record_))); // the options, rank 0's
  PetscCall(writeMoves(comm, v, s));
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(s.ts, &dt));
  const RunMeasures &m = s.measures;
  // (so that a restart reports the energies of the straight run)
  double strainBefore = 0;
  PetscCall(strainBeforeTotal(comm, s.work, strainBefore));
  const double values[kNScalars] = {kFormat,
                                    static_cast<double>(step),
                                    t,
                                    dt,
                                    static_cast<double>(s.size),
                                    static_cast<double>(s.nParticles),
                                    s.meanParticleMass,
                                    s.work.external,
                                    s.work.damping,
                                    static_cast<double>(m.migrated),
                                    m.separationStrain,
                                    m.maxStrain,
                                    m.maxSeparation,
                                    m.mmsLinf,
                                    m.mmsRms,
                                    static_cast<double>(s.status.restRows),
                                    s.status.restStrain,
                                    s.status.atRest ? 1.0 : 0.0,
                                    m.dtCritical,
                                    strainBefore};
  for (size_t q = 0; q < kNScalars; ++q)
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/state", kScalars[q], PETSC_DOUBLE, &values[q]));
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscViewerDestroy(&v));
  PetscCallMPI(MPI_Barrier(comm));
  std::string error;
  if (s.rank == 0) {
    std::error_code ec;
    std::filesystem::rename(tmp, file, ec);
    if (ec)
      error = "option -gimp_output_dir " + s.sc.outputDir + ": cannot move " + tmp + " to " + file +
              " (" + ec.message() + ")";
  }
  PetscCall(agree(comm, error));
  PetscCall(PetscInfo(nullptr, "step %" PetscInt_FMT ": checkpoint written\n", step));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Checkpoint<D>::check(PetscViewer v, const std::vector<double> &sv) {
  // The checkpoint must come from this scene: the same grid, particles and fields, conditions
  // and time step. Every rank read the same values, so every rank finds the same mismatch.
  RunState<D> &s = s_;
  std::vector<double> grid, gaps;
  PetscCall(readArray(s.comm, v, "/state/grid", grid));
  PetscCall(readArray(s.comm, v, "/state/max_gaps", gaps));
  // The optional particle fields it holds must be the scene's (tracking and transfer).
  const OptionalFields optional = optionalFieldsOf(s.sc);
  std::string fieldWhy;
  for (const FieldSpec<D> &fs : particleFields<D>()) {
    if (fs.need == FieldNeed::Always || fs.need == FieldNeed::Never || !fieldWhy.empty()) continue;
    PetscBool has = PETSC_FALSE;
    PetscCall(PetscViewerHDF5HasDataset(v, ("/particles/" + std::string(fs.name)).c_str(), &has));
    if ((has == PETSC_TRUE) != optional.has(fs.need))
      fieldWhy = "its particles " + std::string(has ? "carry" : "lack") + " the field " + fs.name +
                 ", the scene's do" + (has ? " not" : "") +
                 " (the tracking, the transfer, the boundary conditions or -gimp_multirate differ)";
  }
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(s.ts, &dt));
  std::string why;
  if (sv[0] != kFormat)
    why = "its layout version " + formatNumber(sv[0]) + " is not " + formatNumber(kFormat);
  else if (grid != gridDescription(s.grid))
    why = "its grid differs from the scene's (levels, cell sizes, boxes)";
  else if (sv[5] != static_cast<double>(s.nParticles))
    why = "it holds " + formatNumber(sv[5]) + " particles, the scene seeds " +
          std::to_string(s.nParticles);
  else if (!fieldWhy.empty())
    why = fieldWhy;
  else if (gaps.size() != s.sc.dbcs.size())
    why = "it has " + std::to_string(gaps.size()) + " displacement conditions, the scene " +
          std::to_string(s.sc.dbcs.size());
  // (A step chosen from the eigen-solver's estimate differs in its last bits with the rank
  // count; the restart continues with the checkpoint's.)
  else if (std::fabs(sv[3] - dt) > 1e-9 * dt)
    why =
        "its time step " + formatNumber(sv[3]) + " s differs from the scene's " + formatNumber(dt);
  if (!why.empty()) {
    PetscCall(PetscViewerDestroy(&v));
    throw InputError("option -gimp_restart " + s.sc.restart + ": " + why +
                     ": give the options of the run that wrote it");
  }
  std::vector<double> force, gap;
  PetscCall(readArray(s.comm, v, "/state/reactions", force));
  PetscCall(readArray(s.comm, v, "/state/gaps", gap));
  s.boundary.restore(gaps, force, gap, s.rank == 0);
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Checkpoint<D>::loadFollow(
    PetscViewer v, const std::function<PetscErrorCode(const std::vector<LevelBox<D>> &)> &regrid) {
  RunState<D> &s = s_;
  std::vector<double> grid, follow;
  PetscCall(readArray(s.comm, v, "/state/grid", grid));
  PetscCall(readArray(s.comm, v, "/state/follow", follow));
  const std::vector<double> now = gridDescription(s.grid);
  if (grid.size() != now.size()) return PETSC_SUCCESS; // another grid: check() refuses it
  std::vector<LevelBox<D>> boxes = s.sc.levelBoxes();
  const size_t per = 1 + 3 * D; // h, box, nodes per axis
  for (size_t k = 1; k < boxes.size(); ++k)
    std::copy(grid.begin() + static_cast<std::ptrdiff_t>(k * per + 1),
              grid.begin() + static_cast<std::ptrdiff_t>(k * per + 1 + 2 * D),
              boxes[k].box.begin());
  if (grid != now) PetscCall(regrid(boxes));
  // The split ids and moves; a checkpoint whose particles were split holds more than the scene
  // seeds (check() compares the count seeding gave).
  if (restoreFollow(s, follow)) s.nParticles = -1; // the checkpoint's count, set below
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode
Checkpoint<D>::load(OutputResume &resume,
                    const std::function<PetscErrorCode(const std::vector<LevelBox<D>> &)> &regrid) {
  // Runs after setup has seeded the scene: the particles are replaced by the checkpoint's, each
  // rank's own in their order on as many ranks, split evenly and migrated on another count.
  RunState<D> &s = s_;
  const std::string &file = s.sc.restart;
  // Rank 0 inspects the whole file first (the scene it belongs to, every field's presence,
  // size and values): PETSc's reader below meets a whole checkpoint of this scene only.
  PetscCall(agree(s.comm, s.rank == 0 ? ckpt::checkpointRefusal<D>(file, optionalFieldsOf(s.sc))
                                      : std::string()));
  PetscViewer v;
  PetscCall(PetscViewerHDF5Open(s.comm, file.c_str(), FILE_MODE_READ, &v));
  std::vector<double> sv(kNScalars);
  // The layout version first: a checkpoint of another layout may lack the later attributes.
  PetscCall(PetscViewerHDF5ReadAttribute(v, "/state", kScalars[0], PETSC_DOUBLE, nullptr, &sv[0]));
  for (size_t q = 1; q < kNScalars && sv[0] == kFormat; ++q)
    PetscCall(
        PetscViewerHDF5ReadAttribute(v, "/state", kScalars[q], PETSC_DOUBLE, nullptr, &sv[q]));
  if (s.sc.follows()) PetscCall(loadFollow(v, regrid));
  if (s.nParticles < 0) s.nParticles = static_cast<PetscInt64>(sv[5]); // split before it
  PetscCall(check(v, sv));                                             // destroys v when it throws
  std::vector<double> sizes, frames, history;
  PetscCall(readArray(s.comm, v, "/particles/local_sizes", sizes));
  PetscCall(readArray(s.comm, v, "/state/frames", frames));
  PetscCall(readArray(s.comm, v, "/state/history", history));
  if (s.sc.growth != Growth::None) { // the grown cracks (their count checked: verify)
    std::vector<double> cracks, growth;
    PetscCall(readArray(s.comm, v, "/state/cracks", cracks));
    PetscCall(readArray(s.comm, v, "/state/growth", growth));
    try { // (every rank read the same arrays: every rank throws alike)
      restoreGrowth(s, cracks, growth);
    } catch (const std::out_of_range &) {
      PetscCall(PetscViewerDestroy(&v));
      throw InputError("option -gimp_restart " + file +
                       ": its field /state/cracks is shorter than the scene's cracks need (a "
                       "damaged checkpoint)");
    }
  }
  const bool same = sizes.size() == static_cast<size_t>(s.size);
  const PetscInt total = static_cast<PetscInt>(sv[5]);
  const PetscInt nloc = same ? static_cast<PetscInt>(sizes[static_cast<size_t>(s.rank)])
                             : total / s.size + (s.rank < total % s.size ? 1 : 0);
  PetscCall(DMSwarmSetLocalSizes(s.sw, nloc, 16));
  PetscCall(PetscViewerHDF5PushGroup(v, "/particles"));
  PetscCall(transferFields<D>(s.comm, v, s.sw, true));
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscViewerDestroy(&v));
  PetscInt *owner = nullptr;
  PetscCall(DMSwarmGetField(s.sw, DMSwarmField_rank, nullptr, nullptr,
                            reinterpret_cast<void **>(&owner)));
  std::fill(owner, owner + nloc, static_cast<PetscInt>(s.rank));
  PetscCall(DMSwarmRestoreField(s.sw, DMSwarmField_rank, nullptr, nullptr,
                                reinterpret_cast<void **>(&owner)));
  if (!same) PetscCall(step_.migrate());
  PetscCall(restoreState(sv));
  for (size_t q = 0; q + 2 < frames.size(); q += 3)
    resume.frames.push_back(
        {static_cast<PetscInt>(frames[q]), frames[q + 1], static_cast<long long>(frames[q + 2])});
  resume.history = ckpt::unpackText(history);
  PetscCall(PetscPrintf(s.comm, "gimp: restart from %s at step %" PetscInt_FMT " t %.9g s\n",
                        file.c_str(), static_cast<PetscInt>(sv[1]), sv[2]));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Checkpoint<D>::restoreState(const std::vector<double> &sv) {
  RunState<D> &s = s_;
  PetscCall(TSSetStepNumber(s.ts, static_cast<PetscInt>(sv[1])));
  PetscCall(TSSetTime(s.ts, sv[2]));
  PetscCall(TSSetTimeStep(s.ts, sv[3])); // the step of the run that wrote it, to the last bit
  // A run that would end before its checkpoint is refused (every rank read the same one); one
  // that ends on it runs no step and reports that step again.
  PetscInt maxSteps = 0;
  PetscReal maxTime = 0;
  PetscCall(TSGetMaxSteps(s.ts, &maxSteps));
  PetscCall(TSGetMaxTime(s.ts, &maxTime));
  if (maxSteps < static_cast<PetscInt>(sv[1]))
    throw InputError("option -ts_max_steps " + std::to_string(maxSteps) + ": the checkpoint " +
                     s.sc.restart + " is at step " + std::to_string(static_cast<PetscInt>(sv[1])) +
                     ", past the run's end; -ts_max_steps counts from step 0");
  if (maxTime < sv[2])
    throw InputError("option -ts_max_time " + formatNumber(maxTime) + ": the checkpoint " +
                     s.sc.restart + " is at t = " + formatNumber(sv[2]) + " s, past the run's end");
  RunMeasures &m = s.measures;
  s.meanParticleMass = sv[6];
  s.work.external = sv[7];
  s.work.damping = sv[8];
  m.migrated = static_cast<PetscInt64>(sv[9]);
  m.separationStrain = sv[10];
  m.maxStrain = sv[11];
  m.maxSeparation = sv[12];
  m.mmsLinf = sv[13];
  m.mmsRms = sv[14];
  s.status.restRows = static_cast<int>(sv[15]);
  s.status.restStrain = sv[16];
  s.status.atRest = sv[17] != 0;
  // The smallest critical step of the run so far (re-checks before the checkpoint included).
  m.dtCritical = std::fmin(m.dtCritical, sv[18]);
  // (rank 0 holds the sum; an empty ledger where it was not measured)
  s.work.strainBefore.clear();
  if (!std::isnan(sv[19])) s.work.strainBefore.assign(1, s.rank == 0 ? sv[19] : 0.0);
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode Checkpoint<D>::write(PetscInt, double);                                  \
  template PetscErrorCode Checkpoint<D>::load(                                                     \
      OutputResume &, const std::function<PetscErrorCode(const std::vector<LevelBox<D>> &)> &);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
