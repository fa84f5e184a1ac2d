// The paths a run writes, checked at setup (see include/gimp/io/paths.hpp).
#include "gimp/io/paths.hpp"

#include "gimp/core/errors.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace gimp {

namespace {

namespace fs = std::filesystem;

/// The files gimp writes in its output directory (each also as NAME.tmp while written whole).
const char *const kOwnFiles[] = {"history.csv", "summary.json",  "fields.h5", "particles.xmf",
                                 "grid.xmf",    "checkpoint.h5", "hoop.csv",  "hoop_fit.csv"};

/// The path made absolute and free of `.`, `..` and symbolic links as far as it exists.
fs::path canonical(const std::string &p) {
  std::error_code ec;
  const fs::path a = fs::absolute(p, ec);
  const fs::path c = fs::weakly_canonical(a, ec);
  return ec ? a.lexically_normal() : c;
}

/// Why a directory that exists cannot take new files, or "".
std::string unwritableDirectory(const fs::path &dir) {
  if (::access(dir.c_str(), W_OK | X_OK) == 0) return "";
  return dir.string() + " is not writable (" + std::strerror(errno) + ")";
}

/// The output directory: a directory, or one that can be created.
std::string outputDirProblem(const std::string &dir) {
  std::error_code ec;
  const std::string head = "option -gimp_output_dir " + dir + ": ";
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) return head + "is not a directory";
    const std::string why = unwritableDirectory(fs::path(dir));
    return why.empty() ? "" : head + why;
  }
  fs::path up = fs::absolute(dir, ec).parent_path();
  while (!up.empty() && !fs::exists(up, ec) && up != up.root_path())
    up = up.parent_path();
  if (!fs::is_directory(up, ec))
    return head + "cannot create it (" + up.string() + " is not a directory)";
  const std::string why = unwritableDirectory(up);
  return why.empty() ? "" : head + "cannot create it (" + why + ")";
}

/// One dump: a regular file or a new one, in a writable directory that exists (or in the output
/// directory `dir`, created before it is written).
std::string dumpFileProblem(const std::string &file, const fs::path &dir) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) return "is a directory, not a file";
  if (fs::exists(file, ec) && !fs::is_regular_file(file, ec))
    return "is not a regular file (a device, pipe or socket): give the path of a file";
  const fs::path parent = fs::absolute(file, ec).parent_path();
  if (canonical(parent.string()) == dir) return "";
  const std::string shown = fs::path(file).parent_path().string();
  if (!fs::is_directory(parent, ec))
    return (shown.empty() ? parent.string() : shown) + " is not a directory that exists";
  return unwritableDirectory(parent);
}

} // namespace

std::string runPathProblem(const RunPaths &paths) {
  const std::string dirProblem = outputDirProblem(paths.outputDir);
  if (!dirProblem.empty()) return dirProblem;
  const fs::path dir = canonical(paths.outputDir);
  for (size_t i = 0; i < paths.dumps.size(); ++i) {
    const auto &[option, file] = paths.dumps[i];
    const std::string head = "option -" + option + " " + file + ": ";
    const std::string why = dumpFileProblem(file, dir);
    if (!why.empty()) return head + why;
    const fs::path at = canonical(file);
    for (size_t j = 0; j < i; ++j)
      if (canonical(paths.dumps[j].second) == at)
        return head + "is the -" + paths.dumps[j].first + " file too: give two files";
    for (const auto &[input, read] : paths.inputs)
      if (!read.empty() && canonical(read) == at)
        return head + "is the file -" + input + " reads: the run would overwrite it";
    for (const char *own : kOwnFiles)
      for (const char *tail : {"", ".tmp"})
        if (at == dir / (std::string(own) + tail))
          return head + "is the output directory's " + own + tail + ": give another file";
  }
  return "";
}

PetscErrorCode checkRunPaths(MPI_Comm comm, const RunPaths &paths) {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  return agree(comm, rank == 0 ? runPathProblem(paths) : std::string());
}

} // namespace gimp
