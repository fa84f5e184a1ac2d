// What every writer shares: the output directory, history.csv, files written whole or not at
// all, and room on the disk for a field frame before it is written.
#include "gimp/io/checked.hpp"
#include "gimp/io/output.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace gimp {

namespace {

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

/// Rank 0: the dump paths can be written (not a directory, in a directory that exists, the
/// particle dump can be created), and the particle dump of an earlier run is gone.
std::string checkDumpPaths(const std::string &particleDump, const std::string &gridDump) {
  namespace fs = std::filesystem;
  for (const auto &[option, file] :
       {std::pair<std::string, std::string>{"gimp_particle_dump", particleDump},
        {"gimp_grid_dump", gridDump}}) {
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
  std::error_code ec;
  if (particleDump.empty()) return "";
  if (fs::is_regular_file(particleDump, ec)) fs::remove(particleDump, ec);
  FILE *f = std::fopen(particleDump.c_str(), "w");
  if (!f)
    return "option -gimp_particle_dump " + particleDump + ": cannot open the file (" +
           std::strerror(errno) + ")";
  std::fclose(f);
  if (fs::is_regular_file(particleDump, ec)) fs::remove(particleDump, ec);
  return "";
}

/// Rank 0: the directory, emptied of every file an earlier run wrote there (and the temporary
/// files of one that was killed while writing), so a run that fails later leaves none of them
/// behind. A restart keeps the frames its checkpoint lists and the checkpoint; a fresh run also
/// removes an earlier checkpoint, which no longer matches.
std::string emptyDirectory(const std::string &dir, bool resume) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return "option -gimp_output_dir " + dir + ": cannot create it (" + ec.message() + ")";
  if (!std::filesystem::is_directory(dir, ec))
    return "option -gimp_output_dir " + dir + ": is not a directory";
  std::vector<std::string> stale{"summary.json", "hoop.csv", "hoop_fit.csv", "history.csv"};
  if (resume) stale.push_back("checkpoint.h5.tmp"); // left by a crash while writing
  if (!resume)
    stale.insert(stale.end(), {"fields.h5", "particles.xmf", "grid.xmf", "checkpoint.h5"});
  for (const std::string &name : stale)
    for (const char *tail : {"", ".tmp"})
      if (!std::filesystem::remove(dir + "/" + name + tail, ec) && ec)
        return "option -gimp_output_dir " + dir + ": cannot remove the earlier run's " + name +
               tail + " (" + ec.message() + ")";
  return "";
}

} // namespace

OutputFiles::~OutputFiles() {
  if (history_) std::fclose(history_);
}

PetscErrorCode OutputFiles::prepare(const OutputResume *resume, const std::string &particleDump,
                                    const std::string &gridDump) {
  PetscCallMPI(MPI_Comm_rank(comm_, &rank_));
  std::string error;
  if (rank_ == 0) {
    error = emptyDirectory(dir_, resume != nullptr);
    if (error.empty()) error = checkDumpPaths(particleDump, gridDump);
  }
  PetscCall(agree(comm_, error));
  PetscCall(openOnRoot("history.csv", &history_, false));
  if (!resume) return PETSC_SUCCESS;
  // A restart: the history up to the checkpoint, the frames it had written.
  if (rank_ == 0) std::fwrite(resume->history.data(), 1, resume->history.size(), history_);
  PetscCall(flushHistory(0));
  return keepFrames(resume->frames);
}

PetscErrorCode OutputFiles::openOnRoot(const std::string &name, FILE **f, bool whole) const {
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

PetscErrorCode OutputFiles::closeOnRoot(const std::string &name, FILE *f, bool whole) const {
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

PetscErrorCode OutputFiles::flushHistory(long rowStart) {
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

PetscErrorCode OutputFiles::reserveFrame(PetscInt step, long double bytes) const {
  std::string error;
  if (rank_ == 0) {
    const std::string reason = reserveSpace(dir_ + "/fields.h5", bytes);
    if (!reason.empty())
      error = "option -gimp_output_dir " + dir_ + ": cannot write fields.h5 at step " +
              std::to_string(static_cast<long long>(step)) + " (" + reason + ")";
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

void OutputFiles::releaseFrame() const {
  // Give back what reserveSpace kept beyond the end of the file (truncating to its own size
  // frees blocks allocated past it).
  if (rank_ != 0) return;
  const std::string file = dir_ + "/fields.h5";
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return;
  if (truncate(file.c_str(), st.st_size) != 0) return; // the blocks only stay allocated
}

} // namespace gimp
