// The parts of the option table (src/input only) and the checks they declare.
#pragma once

#include "gimp/input/options.hpp"

namespace gimp::input {

inline Check above(double lo) {
  return {Check::Above, lo, 0, false, false, false};
}
inline Check atLeast(double lo) {
  return {Check::AtLeast, lo, 0, false, false, false};
}
inline Check within(double lo, double hi, bool openLo = false, bool openHi = false) {
  return {Check::Within, lo, hi, openLo, openHi, false};
}
inline Check intFrom(double lo, double hi) {
  return {Check::Within, lo, hi, false, false, true};
}

/// The bodies' options (option_table_parts.cpp).
const std::vector<OptionSpec> &bodyOptions();
/// Loads, constraints and probes.
const std::vector<OptionSpec> &loadOptions();
/// Grid levels and cracks.
const std::vector<OptionSpec> &gridOptions();

} // namespace gimp::input
