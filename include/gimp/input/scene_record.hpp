// The scene a checkpoint belongs to: the options that define the state (every option of the
// table but those a restart may change, keptAcrossRestart), as canonical text. A checkpoint
// stores it; a restart compares its own option by option and is refused at the first
// difference (docs/output.md, "Checkpoint and restart").
#pragma once

#include <string>

namespace gimp::input {

/// Whether option `name` (without the dash) may differ between a run and its restart: the
/// step limits, outputs and resources, not the scene.
bool keptAcrossRestart(const std::string &name);

/// This run's state-defining options given in the PETSc options database, one line each,
/// `name<TAB>canonical value<TAB>value as given`, in the order of the option table (numbers in
/// their shortest exact form, logical values as true/false, a particle file as its content's
/// hash). Not collective (rank 0 calls it: it reads the particle files).
std::string sceneRecord();

/// The first difference between the record `stored` in checkpoint `file` and `current`, as the
/// text of a one-line error ("" when they agree).
std::string sceneDifference(const std::string &stored, const std::string &current,
                            const std::string &file);

} // namespace gimp::input
