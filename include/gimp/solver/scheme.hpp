// The update scheme (USF, USL, MUSL) as a table: which velocity field the stress update reads
// and when it runs. The step (solver/step.cpp) asks the scheme, never the scene's enum.
#pragma once

#include "gimp/input/scene.hpp"

namespace gimp {

struct Scheme {
  const char *name;
  /// USF: the stress is updated from the P2G velocity, before the grid update.
  bool stressBeforeGridUpdate;
  /// MUSL: after G2P the updated particle momenta are projected to the grid again, and that
  /// velocity field updates the stress (and is the end velocity of the step's work).
  bool stressFromReprojection;
};

inline Scheme schemeFor(Update u) {
  switch (u) {
  case Update::USF:
    return {"usf", true, false};
  case Update::USL:
    return {"usl", false, false};
  case Update::MUSL:
    break;
  }
  return {"musl", false, true};
}

} // namespace gimp
