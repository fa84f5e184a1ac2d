// The paths a run writes, checked at setup before anything is computed: the output directory
// (history.csv, summary.json, fields.h5 and its XDMF files, checkpoint.h5, hoop.csv), the
// particle dump and the grid dump. See docs/output.md, *The output directory*.
#pragma once

#include <petscsys.h>

#include <string>
#include <utility>
#include <vector>

namespace gimp {

/// What a run writes and the files it reads (which it must not overwrite), each with the option
/// that names it (without the dash).
struct RunPaths {
  std::string outputDir;
  std::vector<std::pair<std::string, std::string>> dumps;  // (option, file), given ones only
  std::vector<std::pair<std::string, std::string>> inputs; // (option, file) the run reads
};

/// Why a run could not write where it is asked to, as the one error line "option -X PATH:
/// reason", or "": the output directory must be a directory or creatable (its nearest existing
/// ancestor a directory that can be written), and each dump a regular file or a new one (not a
/// directory, device or pipe) in a directory that exists and can be written, not another dump,
/// not a file the run reads, not one of the output directory's own files. Reads the file system
/// only (rank 0 calls it; see checkRunPaths).
std::string runPathProblem(const RunPaths &paths);

/// runPathProblem on rank 0, agreed by every rank (collective): InputError on all ranks alike.
PetscErrorCode checkRunPaths(MPI_Comm comm, const RunPaths &paths);

} // namespace gimp
