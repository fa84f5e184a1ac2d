// The layout of checkpoint.h5 shared by its writer and reader (solver/checkpoint.cpp) and its
// inspection before a restart (checkpoint_verify.cpp).
#pragma once

#include "gimp/particles/swarm.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace gimp::ckpt {

inline constexpr double kFormat = 7; // layout version of checkpoint.h5

/// The scalar attributes of /state, in this order.
inline constexpr const char *kScalars[] = {"format",
                                           "step",
                                           "time",
                                           "dt",
                                           "ranks",
                                           "particles",
                                           "mean_particle_mass",
                                           "work_external",
                                           "work_damping",
                                           "migrated",
                                           "separation_strain",
                                           "max_strain",
                                           "max_separation",
                                           "mms_linf",
                                           "mms_rms",
                                           "rest_rows",
                                           "rest_strain",
                                           "at_rest",
                                           "dt_critical",
                                           "strain_before"};
inline constexpr size_t kNScalars = sizeof(kScalars) / sizeof(kScalars[0]);

/// Text as doubles: its byte count, then the bytes 8 to a value.
std::vector<double> packText(const std::string &text);
/// The text of packText's values (their count checked before: checkpointRefusal).
std::string unpackText(const std::vector<double> &packed);

/// Rank 0, before a restart: why checkpoint `file` cannot continue this scene, as the text of a
/// one-line error ("" when it can): not an HDF5 checkpoint, another layout, another scene (the
/// first option that differs), or a damaged field (missing, of another type or size than its
/// recorded counts, a value that is not finite or out of its range).
template <int D> std::string checkpointRefusal(const std::string &file, const OptionalFields &need);

} // namespace gimp::ckpt
