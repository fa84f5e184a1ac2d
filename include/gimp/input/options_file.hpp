// Options files, read by gimp before PETSc starts. A scene is a PETSc options file; a scene
// may include another with a line `-options_file NAME`. PETSc would open NAME relative to the
// working directory; here NAME is relative to the directory of the file that names it, so a
// scene that includes another runs from any working directory.
//
// main() passes the command line through expandOptionsFiles(): every `-options_file FILE` is
// replaced, in place, by FILE's options, so that an option given later on the command line
// still overrides the file (the last one wins). A scene can be long (hundreds of kB of
// polygons and probes), longer than MPI lets a command line be, so splitForPetsc() keeps the
// scene's own options (-gimp_*) out of what PetscInitialize gets; main() inserts them, in
// their order, right after it (PETSc reads none of them while it starts).
//
// In an options file, a relative path given to an option that names a file the run reads
// (-gimp_bodyK_file, -gimp_restart) is resolved as a nested -options_file is: beside the file.
//
// Files are read as PETSc 3.18 reads them (PetscOptionsInsertFile), so a scene gives PETSc the
// same options as before: one option per line, optionally followed by its value; `#` starts a
// comment (even inside quotes); blanks, tabs and CR separate tokens; a value in double quotes
// may hold blanks; a line that starts with anything but an option, a second option or a third
// token on a line are errors. Differences: `alias` lines are refused (gimp does not use them),
// a UTF-8 byte-order mark at the start of a file is skipped, a file that holds a NUL byte is
// refused. YAML files (named *.yaml, *.yml, *.json, NAME:yaml, or starting with "%YAML " or
// "---") and names holding "${" (PETSc substitutes those) are left to PETSc: the pair
// `-options_file NAME` is kept, NAME resolved against the including file's directory if it
// is nested.
#pragma once

#include "gimp/core/errors.hpp" // InputError

#include <string>
#include <vector>

namespace gimp {

/// Deepest nesting of options files; the file named on the command line is level 1.
constexpr int kMaxOptionsFileDepth = 16;

/// The command line `args` (without the program name) as PETSc would read it, with every
/// `-options_file FILE` replaced by FILE's options, nested files expanded where they are
/// included. A FILE on the command line is relative to the working directory; a nested one
/// to the directory of the file that includes it (absolute names stay as they are). The
/// result is a list of options, each followed by its value if it has one; words PETSc skips
/// (a non-option where an option is expected) are dropped. Throws InputError with one line
/// "option -options_file NAME: ..." for a missing, unreadable or binary file, a directory, a
/// syntax error, a file that includes itself (directly or through a cycle), nesting deeper
/// than kMaxOptionsFileDepth, or `-options_file` without a name.
std::vector<std::string> expandOptionsFiles(const std::vector<std::string> &args);

/// One option of the scene, inserted after PetscInitialize.
struct LateOption {
  std::string key, value;
  bool hasValue = false;
};

/// The expanded command line split in two: `early`, what PetscInitialize gets (every option
/// PETSc may read while it starts, in order), and `late`, the -gimp_* options with their
/// values, in order (none inside a -prefix_push: those stay early with their prefix).
struct SplitArgs {
  std::vector<std::string> early;
  std::vector<LateOption> late;
};
SplitArgs splitForPetsc(const std::vector<std::string> &expanded);

/// This process's rank as its MPI launcher set it in the environment (OMPI_COMM_WORLD_RANK,
/// PMIX_RANK or PMI_RANK), or -1 when none is set: lets main() report an error found before
/// MPI starts once, from rank 0.
int launcherRank();

} // namespace gimp
