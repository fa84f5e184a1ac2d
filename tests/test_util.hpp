// Shared helpers of the property tests: the worst error over many samples, with where it
// occurred, checked and printed with its sample count.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <sstream>
#include <string>
#include <utility>

namespace gimp::test {

/// "name=value ..." with full precision, to report a failing case.
std::string at(std::initializer_list<std::pair<const char *, double>> values) {
  std::ostringstream s;
  s.precision(17);
  for (const auto &[name, v] : values)
    s << name << '=' << v << ' ';
  return s.str();
}

/// The largest error seen so far (NaN sticks) and a description of where it occurred.
struct Worst {
  double err = 0.0;
  std::string where = "(no sample)";
  long count = 0;
  template <class F> void update(double e, F &&describe) {
    ++count;
    if (std::isnan(err)) return;
    if (!(e <= err)) {
      err = e;
      where = describe();
    }
  }
};

// Checks the largest error and prints it with the sample count (kept in the ctest log).
#define EXPECT_WORST_LE(worst, tol)                                                                \
  do {                                                                                             \
    std::printf("  %-11s max %9.3g  tol %7.1g  samples %ld\n", #worst, (worst).err, (tol),         \
                (worst).count);                                                                    \
    EXPECT_GT((worst).count, 0);                                                                   \
    EXPECT_LE((worst).err, (tol)) << #worst << " over " << (worst).count << " samples, worst at "  \
                                  << (worst).where;                                                \
  } while (0)

} // namespace gimp::test
