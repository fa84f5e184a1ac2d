// The run state a checkpoint keeps beyond particles and scalars, as arrays of doubles: 2D crack
// growth (the grown cracks, the increments) and levels that follow a point (the split ids, the
// moves). Internal to solver/checkpoint.cpp.
#pragma once

#include "gimp/solver/state.hpp"

#include <vector>

namespace gimp {

/// 2D crack growth's state: each crack's point count, grown points at each end and points, then
/// each tip's stopped flag (cracks); every increment, 9 values each (growth).
template <int D>
void growthState(const RunState<D> &s, std::vector<double> &cracks, std::vector<double> &growth);
/// The grown cracks and the increments back into the run (the arrays of growthState, the same
/// scene: its crack and tip counts; std::out_of_range when they are short).
template <int D>
void restoreGrowth(RunState<D> &s, const std::vector<double> &cracks,
                   const std::vector<double> &growth);

/// Levels that follow a point: the particles seeded, the bodies, each body's seeded top and used
/// split ids, then the moves (32 values each: t, step, level, box (6), previous box (6), particles
/// added, the conserved sums before and after (8 each)).
template <int D> std::vector<double> followState(const RunState<D> &s);
/// The split ids and moves of followState back into the run; false (nothing restored) when no
/// particle had been split or the checkpoint seeded another count than this run.
template <int D> bool restoreFollow(RunState<D> &s, const std::vector<double> &follow);

} // namespace gimp
