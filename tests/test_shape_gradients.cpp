// Unit tests of the gradient of the GIMP particle weight in include/gimp/grid/shape.hpp,
// (S(d + l) - S(d - l)) / (2 l) with S the integral of the nodal tent with influence zone
// [L-, L+] (Eqs. 14 and 15). (The values and identities of the weights: test_shape_values.cpp.)
//
//   1. The gradient is the derivative of the weight: central finite differences.
//   2. C1 continuity: no jump of the gradient where a particle edge crosses a tent kink, and
//      continuous interpolated gradients on uniform and refined meshes.
//
// All random sampling uses a fixed-seed std::mt19937_64, so every run checks the same points.
// Random checks keep the largest error and report where it occurred.
#include "gimp/grid/shape.hpp"

#include "shape_nodes.hpp"
#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

using gimp::test::at;
using gimp::test::Worst;

using gimp::test::kZones;
using gimp::test::Nodes;
using gimp::test::refinedNodes;
using gimp::test::uniformNodes;

using gimp::shape::tent;
using gimp::shape::weight;
using gimp::shape::weightGradient;

// ---------------------------------------------------------------------------------------------
// 1. The gradient is the derivative of the weight: central finite differences.

TEST(ShapeWeight, GradientMatchesFiniteDifference) {
  const double h = 0.37, e = 1e-7 * h;
  std::mt19937_64 rng(0x5eed0003);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<std::pair<double, double>> zones = kZones;
  for (int k = 0; k < 200; ++k) // random zones, ratios up to 16
    zones.emplace_back(0.25 + 3.75 * U(rng), 0.25 + 3.75 * U(rng));
  Worst fd;
  long skipped = 0, nonzero = 0;
  for (size_t z = 0; z < zones.size(); ++z) {
    const double Lm = zones[z].first * h, Lp = zones[z].second * h;
    const int ns = z < kZones.size() ? 20000 : 1000;
    for (int s = 0; s < ns; ++s) {
      // l in [0.01 h, h]: for smaller l the round-off of w / (2 e) alone approaches the
      // tolerance. d covers the whole support and a margin outside it.
      const double l = h * (0.01 + 0.99 * U(rng));
      const double dlo = -Lm - l - 0.2 * h, dhi = Lp + l + 0.2 * h;
      const double d = dlo + U(rng) * (dhi - dlo);
      // The weight is a quadratic between the points where d +- l crosses a tent kink; a
      // central difference straddling one of them is not exact, so skip those few samples
      // (continuity there is test 2).
      bool nearKink = false;
      for (double k : {-Lm - l, -Lm + l, -l, l, Lp - l, Lp + l})
        nearKink = nearKink || std::abs(d - k) < 10.0 * e;
      if (nearKink) {
        ++skipped;
        continue;
      }
      const double g = weightGradient(d, l, Lm, Lp);
      const double num = (weight(d + e, l, Lm, Lp) - weight(d - e, l, Lm, Lp)) / (2.0 * e);
      if (g != 0.0) ++nonzero;
      fd.update(std::abs(num - g) / std::max(std::abs(g), 1.0 / h), [&] {
        return at({{"d", d}, {"l", l}, {"Lm", Lm}, {"Lp", Lp}, {"grad", g}, {"fd", num}});
      });
    }
  }
  EXPECT_WORST_LE(fd, 1e-6);
  EXPECT_LT(skipped, fd.count / 1000);
  EXPECT_GT(nonzero, fd.count / 2);
}

// ---------------------------------------------------------------------------------------------
// 2. C1 continuity: the weight gradient has no jump where d +- l crosses a tent kink.

TEST(ShapeWeight, GradientIsContinuousAtKinks) {
  const double h = 0.37, delta = 1e-9 * h;
  std::mt19937_64 rng(0x5eed0004);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<std::pair<double, double>> zones = kZones;
  for (int k = 0; k < 200; ++k)
    zones.emplace_back(0.25 + 3.75 * U(rng), 0.25 + 3.75 * U(rng));
  Worst jump;
  for (const auto &[zm, zp] : zones) {
    const double Lm = zm * h, Lp = zp * h;
    std::vector<double> ls = {0.25 * h, 0.5 * h, h,
                              0.5 * std::min(zm > 0 ? Lm : h, zp > 0 ? Lp : h)};
    for (int k = 0; k < 200; ++k)
      ls.push_back(h * (0.05 + 0.95 * U(rng)));
    for (double l : ls) {
      // Kinks of the weight: a particle edge d +- l on -L-, 0 or L+. With a zero zone the tent
      // itself jumps at 0 (the domain edge), so d = +-l is where the particle leaves the grid
      // and the gradient does jump there (checked in ShapeExact.DomainEdgeNode,
      // test_shape_values.cpp).
      std::vector<double> kinks;
      if (Lm > 0 && Lp > 0) kinks = {-l, l};
      if (Lm > 0) kinks.insert(kinks.end(), {-Lm - l, -Lm + l});
      if (Lp > 0) kinks.insert(kinks.end(), {Lp - l, Lp + l});
      if (Lm == 0 || Lp == 0) // drop kinks that coincide with the jump at the domain edge
        kinks.erase(std::remove_if(kinks.begin(), kinks.end(),
                                   [&](double k) { return std::abs(std::abs(k) - l) < 1e-12 * h; }),
                    kinks.end());
      for (double k : kinks) {
        const double gl = weightGradient(k - delta, l, Lm, Lp);
        const double gr = weightGradient(k + delta, l, Lm, Lp);
        jump.update(std::abs(gr - gl) / std::max({std::abs(gl), std::abs(gr), 1.0 / h}), [&] {
          return at({{"d", k}, {"l", l}, {"Lm", Lm}, {"Lp", Lp}, {"left", gl}, {"right", gr}});
        });
      }
    }
  }
  EXPECT_WORST_LE(jump, 1e-6);

  // The same sampling does see a C0 kink: the point tent's slope jumps by 2/h at the node.
  const double slopeL = (tent(0.0, h, h) - tent(-delta, h, h)) / delta;
  const double slopeR = (tent(delta, h, h) - tent(0.0, h, h)) / delta;
  EXPECT_NEAR(slopeL - slopeR, 2.0 / h, 1e-5 / h);
}

// The gradient of an interpolated field sum_i v_i g_i(x_p) is continuous as the particle
// crosses cell borders (x_p = x_k) and as its edges cross grid lines (x_p = x_k +- l), on a
// uniform grid and on refined meshes with transition nodes.
TEST(ShapeWeight, InterpolatedGradientIsContinuous) {
  std::mt19937_64 rng(0x5eed0005);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<std::pair<Nodes, double>> meshes = {{uniformNodes(12, 0.37), 0.37}};
  for (int r : {2, 3, 4})
    meshes.emplace_back(refinedNodes(r, true), 1.0);
  Worst jump, sumJump;
  for (const auto &[g, h] : meshes) {
    const double delta = 1e-9 * h;
    std::vector<double> v(g.size());
    for (double &vi : v)
      vi = 2.0 * U(rng) - 1.0;
    auto field = [&](double xp, double l, double &G, double &sumG) {
      G = sumG = 0.0;
      for (int i = 0; i < g.size(); ++i) {
        const double gi = weightGradient(xp - g.x[i], l, g.Lm[i], g.Lp[i]);
        G += v[i] * gi;
        sumG += gi;
      }
    };
    for (int s = 0; s < 300; ++s) {
      const double l = h * (0.05 + 0.95 * U(rng));
      for (int k = 0; k < g.size(); ++k)
        for (double xp : {g.x[k], g.x[k] - l, g.x[k] + l}) {
          if (!(xp - l - delta >= g.lo() && xp + l + delta < g.hi())) continue;
          double Gl, Gr, sl, sr;
          field(xp - delta, l, Gl, sl);
          field(xp + delta, l, Gr, sr);
          auto where = [&] { return at({{"xp", xp}, {"l", l}, {"left", Gl}, {"right", Gr}}); };
          jump.update(std::abs(Gr - Gl) * h, where);
          sumJump.update(std::max(std::abs(sl), std::abs(sr)) * h, where);
        }
    }
  }
  EXPECT_WORST_LE(jump, 1e-6);
  EXPECT_WORST_LE(sumJump, 1e-10);
}

} // namespace
