// Levels that follow a point, below the solver: where a box moves (followBox, the grid room) and
// how particles a finer box newly holds are split (splitParticles, the particles room).
//  - followBox keeps the box's size, its corners on the parent's grid lines and the box inside
//    its parent; it moves only along an axis where the point is within the margin of a face, and
//    then puts the point within half a parent cell of the centre (unless the parent stops it).
//  - splitParticles turns a seeded swarm into the swarm that seeding would give for the moved box
//    (the same initial positions and volumes inside it), keeps mass, momentum and the angular
//    momentum sum m (x × v) + m ε:Bᵀ to round-off, gives unique ids of the right body, and, under
//    an affine motion x = F X + c, places each part (and its tracked corners) at F X0 + c.
#include "gimp/grid/cpdi_cells.hpp"
#include "gimp/grid/follow.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/seed.hpp"
#include "gimp/particles/split.hpp"
#include "gimp/particles/swarm.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace {

using gimp::LatticeBox;

TEST(FollowBox, StaysWhenThePointIsInsideTheMargin) {
  const LatticeBox<2> parent{{0, 0}, {64, 64}}, box{{16, 16}, {32, 32}};
  const double x[2] = {24.5, 21.0};
  EXPECT_EQ(gimp::followBox<2>(box, parent, 4, x, 4.0), box);
}

TEST(FollowBox, MovesByWholeParentCellsToCentreThePoint) {
  const LatticeBox<2> parent{{0, 0}, {64, 64}}, box{{16, 16}, {32, 32}};
  for (double px = 28.5; px < 60; px += 1.75) {
    const double x[2] = {px, 24.0};
    const LatticeBox<2> b = gimp::followBox<2>(box, parent, 4, x, 4.0);
    EXPECT_EQ(b.hi[0] - b.lo[0], 16);
    EXPECT_EQ(b.lo[0] % 4, 0);
    EXPECT_EQ(b.lo[1], 16) << "no move along y, where the point is inside the margin";
    EXPECT_GE(b.lo[0], 0);
    EXPECT_LE(b.hi[0], 64);
    if (b.hi[0] < 64) {
      EXPECT_LE(std::fabs(px - 0.5 * (b.lo[0] + b.hi[0])), 2.0) << px;
    }
  }
}

TEST(FollowBox, KeptInsideItsParent3D) {
  const LatticeBox<3> parent{{8, 8, 8}, {40, 40, 40}}, box{{16, 16, 16}, {32, 32, 32}};
  const double x[3] = {39.0, 9.0, 24.0};
  const LatticeBox<3> b = gimp::followBox<3>(box, parent, 8, x, 4.0);
  EXPECT_EQ(b.lo, (std::array<std::int64_t, 3>{24, 8, 16}));
  EXPECT_EQ(b.hi, (std::array<std::int64_t, 3>{40, 24, 32}));
}

/// A swarm seeded for the scene `options` on one rank, its grid and scene kept.
template <int D> struct Seeded {
  gimp::Scene<D> sc;
  gimp::Grid<D> grid;
  DM sw = nullptr;
  explicit Seeded(const std::string &options) {
    EXPECT_EQ(PetscOptionsClear(nullptr), 0);
    EXPECT_EQ(PetscOptionsInsertString(nullptr, options.c_str()), 0);
    EXPECT_EQ(gimp::readScene<D>(PETSC_COMM_SELF, sc), 0) << options;
    EXPECT_EQ(grid.create(PETSC_COMM_SELF, sc.h, sc.levelBoxes(), sc.cracks), 0);
    sc.idSlots = gimp::bodyIdSlots<D>(grid);
    EXPECT_EQ(gimp::createSwarm<D>(PETSC_COMM_SELF, gimp::optionalFieldsOf(sc), &sw), 0);
    gimp::LoadConflict conflict;
    EXPECT_EQ(gimp::seedParticles<D>(sc, grid, sw, conflict), 0);
  }
  ~Seeded() { (void)DMDestroy(&sw); }
};

/// Mass, momentum and angular momentum (z in 2D) of a swarm.
template <int D> std::array<double, 7> sums(DM sw) {
  gimp::ParticleView<D> p;
  EXPECT_EQ(p.get(sw), 0);
  std::array<double, 7> s{};
  for (PetscInt k = 0; k < p.n; ++k) {
    const double m = p.m[k], *x = p.x + D * k, *v = p.v + D * k;
    s[0] += m;
    for (int a = 0; a < D; ++a)
      s[1 + a] += m * v[a];
    double L[3] = {0, 0, x[0] * v[1] - x[1] * v[0]};
    if (D == 3) {
      L[0] = x[1] * v[D - 1] - x[D - 1] * v[1];
      L[1] = x[D - 1] * v[0] - x[0] * v[D - 1];
    }
    if (p.B) {
      const double *B = p.B + D * D * k;
      if (D == 3) {
        L[0] += B[7] - B[5];
        L[1] += B[2] - B[6];
        L[2] += B[3] - B[1];
      } else {
        L[2] += B[2] - B[1];
      }
    }
    for (int a = 0; a < 3; ++a)
      s[4 + a] += m * L[a];
  }
  EXPECT_EQ(p.restore(sw), 0);
  return s;
}

/// The particles of a swarm whose centre lies in `box`: (X0, V0), sorted.
template <int D> std::vector<std::array<double, D + 1>> inBox(DM sw, const gimp::BoxOf<D> &box) {
  gimp::ParticleView<D> p;
  EXPECT_EQ(p.get(sw), 0);
  std::vector<std::array<double, D + 1>> out;
  for (PetscInt k = 0; k < p.n; ++k) {
    bool in = true;
    for (int a = 0; a < D; ++a)
      in = in && p.X0[D * k + a] > box[a] && p.X0[D * k + a] < box[D + a];
    if (!in) continue;
    std::array<double, D + 1> r;
    std::copy(p.X0 + D * k, p.X0 + D * (k + 1), r.begin());
    r[D] = p.V0[k];
    out.push_back(r);
  }
  EXPECT_EQ(p.restore(sw), 0);
  std::sort(out.begin(), out.end());
  return out;
}

/// Seed with the box at `from`, move every particle by x = F X + c (v: a rigid spin plus a
/// shear rate; B some moment), move the box to `to` and split; check against seeding at `to`.
template <int D>
void checkSplit(const std::string &scene, const std::string &from, const std::string &to,
                const std::string &box, bool moved) {
  Seeded<D> a(scene + " -gimp_level1_box " + from);
  const double F[9] = {1.02, 0.05, -0.03, -0.04, 0.97, 0.02, 0.01, -0.02, 1.01};
  const double c[3] = {0.003, -0.002, 0.001};
  const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, zero[3] = {0, 0, 0};
  const double *M = moved ? F : I, *m0 = moved ? c : zero;
  auto Fx = [&](const double *X, double *x) {
    for (int i = 0; i < D; ++i) {
      x[i] = m0[i];
      for (int j = 0; j < D; ++j)
        x[i] += M[3 * i + j] * X[j];
    }
  };
  {
    gimp::ParticleView<D> p;
    ASSERT_EQ(p.get(a.sw), 0);
    for (PetscInt k = 0; k < p.n; ++k) {
      Fx(p.X0 + D * k, p.x + D * k);
      for (int i = 0; i < D; ++i) {
        for (int j = 0; j < D; ++j)
          p.F[D * D * k + D * i + j] = M[3 * i + j];
        p.v[D * k + i] = 0.3 * p.x[D * k + (i + 1) % D] - 0.1 * i + 0.05 * p.X0[D * k];
      }
      if (p.B)
        for (int q = 0; q < D * D; ++q)
          p.B[D * D * k + q] = 1e-3 * (q + 1) * (1 + 0.1 * k);
      if (p.corners)
        for (int q = 0; q < (1 << D); ++q) {
          double X[3];
          for (int i = 0; i < D; ++i)
            X[i] = p.X0[D * k + i] + gimp::cpdi::cornerSign<D>(q, i) * p.l0[D * k + i];
          Fx(X, p.corners + D * ((1 << D) * k + q));
        }
    }
    ASSERT_EQ(p.restore(a.sw), 0);
  }
  const std::array<double, 7> before = sums<D>(a.sw);
  std::vector<double> to6;
  for (size_t i = 0, j = 0; j <= to.size(); ++j)
    if (j == to.size() || to[j] == ',') {
      to6.push_back(std::stod(to.substr(i, j - i)));
      i = j + 1;
    }
  std::copy(to6.begin(), to6.end(), a.sc.levels[1].box.begin());
  gimp::SplitIds ids;
  PetscInt64 added = 0;
  ASSERT_EQ(gimp::splitParticles<D>(PETSC_COMM_SELF, a.sc, a.sw, ids, added), 0);
  EXPECT_GT(added, 0);
  const std::array<double, 7> after = sums<D>(a.sw);
  for (int q = 0; q < 7; ++q)
    EXPECT_NEAR(after[q], before[q], 1e-13 * (std::fabs(before[q]) + before[0])) << q;

  // At rest, the swarm inside the moved box is the one seeding gives there (moved, the particles'
  // current places decide which are split, and seeding knows only initial ones).
  Seeded<D> b(scene + " -gimp_level1_box " + to);
  gimp::BoxOf<D> inner;
  std::vector<double> bx;
  for (size_t i = 0, j = 0; j <= box.size(); ++j)
    if (j == box.size() || box[j] == ',') {
      bx.push_back(std::stod(box.substr(i, j - i)));
      i = j + 1;
    }
  std::copy(bx.begin(), bx.end(), inner.begin());
  const auto got = inBox<D>(a.sw, inner), want = inBox<D>(b.sw, inner);
  if (!moved) {
    ASSERT_EQ(got.size(), want.size());
    for (size_t k = 0; k < got.size(); ++k)
      for (int i = 0; i <= D; ++i)
        EXPECT_NEAR(got[k][i], want[k][i], 1e-12) << k;
  }

  gimp::ParticleView<D> p;
  ASSERT_EQ(p.get(a.sw), 0);
  std::set<PetscInt64> unique(p.id, p.id + p.n);
  EXPECT_EQ(static_cast<PetscInt>(unique.size()), p.n);
  double worst = 0;
  for (PetscInt k = 0; k < p.n; ++k) {
    EXPECT_EQ(p.id[k] / a.sc.idSlots, 0);
    double x[3];
    Fx(p.X0 + D * k, x);
    for (int i = 0; i < D; ++i)
      worst = std::max(worst, std::fabs(x[i] - p.x[D * k + i]));
    if (p.corners)
      for (int q = 0; q < (1 << D); ++q) {
        double X[3];
        for (int i = 0; i < D; ++i)
          X[i] = p.X0[D * k + i] + gimp::cpdi::cornerSign<D>(q, i) * p.l0[D * k + i];
        Fx(X, x);
        for (int i = 0; i < D; ++i)
          worst = std::max(worst, std::fabs(x[i] - p.corners[D * ((1 << D) * k + q) + i]));
      }
  }
  EXPECT_LT(worst, 1e-15) << "parts and corners at F X0 + c";
  ASSERT_EQ(p.restore(a.sw), 0);
}

/// Split where the box moved to `to`, then move it back to `from` and merge: the swarm of the
/// start comes back (every field of every particle, to round-off: the particles translate, so the
/// parts' velocities are their parent's), the sums kept throughout.
template <int D>
void checkRoundTrip(const std::string &scene, const std::string &from, const std::string &to) {
  Seeded<D> a(scene + " -gimp_level1_box " + from);
  const auto boxOf = [](const std::string &t) {
    gimp::BoxOf<D> b;
    size_t i = 0, q = 0;
    for (size_t j = 0; j <= t.size(); ++j)
      if (j == t.size() || t[j] == ',') {
        b[q++] = std::stod(t.substr(i, j - i));
        i = j + 1;
      }
    return b;
  };
  {
    gimp::ParticleView<D> p;
    ASSERT_EQ(p.get(a.sw), 0);
    for (PetscInt k = 0; k < p.n; ++k) { // a translation and some B: the parts of a split keep
      for (int i = 0; i < D; ++i)        // them, so the merge gives them back exactly
        p.v[D * k + i] = 0.3 - 0.1 * i;
      if (p.B)
        for (int q = 0; q < D * D; ++q)
          p.B[D * D * k + q] = 1e-3 * (q + 1);
    }
    ASSERT_EQ(p.restore(a.sw), 0);
  }
  const auto snapshot = [&] {
    gimp::ParticleView<D> p;
    EXPECT_EQ(p.get(a.sw), 0);
    std::vector<std::vector<double>> rows;
    for (PetscInt k = 0; k < p.n; ++k) {
      std::vector<double> r(p.X0 + D * k, p.X0 + D * (k + 1));
      r.insert(r.end(), p.x + D * k, p.x + D * (k + 1));
      r.insert(r.end(), p.v + D * k, p.v + D * (k + 1));
      r.insert(r.end(), p.l0 + D * k, p.l0 + D * (k + 1));
      r.insert(r.end(), {p.m[k], p.V[k], p.V0[k], static_cast<double>(p.id[k])});
      if (p.B) r.insert(r.end(), p.B + D * D * k, p.B + D * D * (k + 1));
      if (p.corners)
        r.insert(r.end(), p.corners + D * (1 << D) * k, p.corners + D * (1 << D) * (k + 1));
      rows.push_back(r);
    }
    EXPECT_EQ(p.restore(a.sw), 0);
    // By initial position, rounded: a merged particle's is a mean, equal to round-off only.
    std::sort(rows.begin(), rows.end(), [](const auto &a, const auto &b) {
      for (int i = 0; i < D; ++i) {
        const double x = std::round(a[i] * 1e9), y = std::round(b[i] * 1e9);
        if (x != y) return x < y;
      }
      return false;
    });
    return rows;
  };
  const auto start = snapshot();
  const std::array<double, 7> s0 = sums<D>(a.sw);
  a.sc.levels[1].box = boxOf(to);
  gimp::SplitIds ids;
  PetscInt64 added = 0, removed = 0;
  ASSERT_EQ(gimp::splitParticles<D>(PETSC_COMM_SELF, a.sc, a.sw, ids, added), 0);
  ASSERT_EQ(gimp::mergeParticles<D>(PETSC_COMM_SELF, a.sc, a.sw, {}, removed), 0);
  EXPECT_GT(added, 0);
  EXPECT_GT(removed, 0) << "the parts the box left at `from` merge";
  const std::array<double, 7> s1 = sums<D>(a.sw);
  a.sc.levels[1].box = boxOf(from);
  PetscInt64 added2 = 0, removed2 = 0;
  ASSERT_EQ(gimp::splitParticles<D>(PETSC_COMM_SELF, a.sc, a.sw, ids, added2), 0);
  ASSERT_EQ(gimp::mergeParticles<D>(PETSC_COMM_SELF, a.sc, a.sw, {}, removed2), 0);
  EXPECT_EQ(added2, removed) << "the box back: what merged splits again";
  EXPECT_EQ(removed2, added) << "and what split merges again";
  const std::array<double, 7> s2 = sums<D>(a.sw);
  for (int q = 0; q < 7; ++q) {
    EXPECT_NEAR(s1[q], s0[q], 1e-13 * (std::fabs(s0[q]) + s0[0])) << q;
    EXPECT_NEAR(s2[q], s0[q], 1e-13 * (std::fabs(s0[q]) + s0[0])) << q;
  }
  const auto end = snapshot();
  ASSERT_EQ(end.size(), start.size());
  double worst = 0;
  size_t idsDiffer = 0;
  for (size_t k = 0; k < end.size(); ++k) {
    ASSERT_EQ(end[k].size(), start[k].size());
    for (size_t i = 0; i < end[k].size(); ++i)
      if (i == 4 * D + 3) // the id: a part that merges keeps the smallest id, not its own
        idsDiffer += end[k][i] != start[k][i];
      else {
        const double d = std::fabs(end[k][i] - start[k][i]) / std::max(1.0, std::fabs(start[k][i]));
        if (d > 1e-14 && worst <= 1e-14)
          ADD_FAILURE() << "particle " << k << " field " << i << ": " << end[k][i] << " against "
                        << start[k][i];
        worst = std::max(worst, d);
      }
  }
  EXPECT_LT(worst, 1e-14) << "every field of every particle back";
  (void)idsDiffer;
}

TEST(Merge, RoundTrip2D) {
  checkRoundTrip<2>("-gimp_E 1e6 -gimp_nu 0.3 -gimp_rho 1000 -gimp_h 0.1 -gimp_body0_box "
                    "0,0,1,0.6 -gimp_body0_ppc 4 -gimp_levels 2 -gimp_transfer apic",
                    "0.2,0.2,0.4,0.4", "0.5,0.1,0.7,0.3");
}

TEST(Merge, RoundTripCorners2D) {
  checkRoundTrip<2>("-gimp_E 1e6 -gimp_nu 0.3 -gimp_rho 1000 -gimp_h 0.1 -gimp_body0_box "
                    "0,0,1,0.6 -gimp_body0_ppc 4 -gimp_levels 2 -gimp_transfer apic "
                    "-gimp_tracking cpdi2 -gimp_level1_ratio 3",
                    "0.2,0.2,0.4,0.4", "0.3,0.2,0.5,0.4");
}

TEST(Merge, RoundTrip3D) {
  checkRoundTrip<3>("-gimp_dim 3 -gimp_E 1e6 -gimp_nu 0.3 -gimp_rho 1000 -gimp_h 0.1 "
                    "-gimp_body0_box 0,0,0,0.6,0.4,0.4 -gimp_body0_ppc 8 -gimp_levels 2 "
                    "-gimp_transfer apic -gimp_tracking cpdi2",
                    "0.1,0.1,0.1,0.3,0.3,0.3", "0.3,0.1,0.2,0.5,0.3,0.4");
}

const std::string kScene2 = "-gimp_E 1e6 -gimp_nu 0.3 -gimp_rho 1000 -gimp_h 0.1 "
                            "-gimp_body0_box 0,0,1,0.6 -gimp_body0_ppc 4 -gimp_levels 2 ";
const std::string kScene3 = "-gimp_dim 3 -gimp_E 1e6 -gimp_nu 0.3 -gimp_rho 1000 -gimp_h 0.1 "
                            "-gimp_body0_box 0,0,0,0.6,0.4,0.4 -gimp_body0_ppc 8 -gimp_levels 2 ";

TEST(Split, Stretch2D) {
  checkSplit<2>(kScene2 + "-gimp_tracking stretch -gimp_transfer apic", "0.2,0.2,0.4,0.4",
                "0.4,0.2,0.6,0.4", "0.4,0.2,0.6,0.4", false);
  checkSplit<2>(kScene2 + "-gimp_tracking stretch -gimp_transfer apic", "0.2,0.2,0.4,0.4",
                "0.4,0.2,0.6,0.4", "0.4,0.2,0.6,0.4", true);
}

TEST(Split, TrackedCorners2D) {
  checkSplit<2>(kScene2 + "-gimp_tracking cpdi2 -gimp_transfer apic", "0.2,0.2,0.4,0.4",
                "0.5,0.1,0.7,0.3", "0.5,0.1,0.7,0.3", false);
  checkSplit<2>(kScene2 + "-gimp_tracking cpdi2 -gimp_transfer apic", "0.2,0.2,0.4,0.4",
                "0.5,0.1,0.7,0.3", "0.5,0.1,0.7,0.3", true);
}

TEST(Split, RatioThree2D) {
  checkSplit<2>(kScene2 + "-gimp_tracking stretch -gimp_level1_ratio 3", "0.2,0.2,0.4,0.4",
                "0.6,0.2,0.8,0.4", "0.6,0.2,0.8,0.4", false);
  checkSplit<2>(kScene2 + "-gimp_tracking stretch -gimp_level1_ratio 3", "0.2,0.2,0.4,0.4",
                "0.6,0.2,0.8,0.4", "0.6,0.2,0.8,0.4", true);
}

TEST(Split, Stretch3D) {
  checkSplit<3>(kScene3 + "-gimp_tracking stretch -gimp_transfer apic", "0.1,0.1,0.1,0.3,0.3,0.3",
                "0.3,0.1,0.1,0.5,0.3,0.3", "0.3,0.1,0.1,0.5,0.3,0.3", false);
  checkSplit<3>(kScene3 + "-gimp_tracking stretch -gimp_transfer apic", "0.1,0.1,0.1,0.3,0.3,0.3",
                "0.3,0.1,0.1,0.5,0.3,0.3", "0.3,0.1,0.1,0.5,0.3,0.3", true);
}

TEST(Split, TrackedCorners3D) {
  checkSplit<3>(kScene3 + "-gimp_tracking cpdi2 -gimp_transfer apic", "0.1,0.1,0.1,0.3,0.3,0.3",
                "0.3,0.1,0.2,0.5,0.3,0.4", "0.3,0.1,0.2,0.5,0.3,0.4", false);
  checkSplit<3>(kScene3 + "-gimp_tracking cpdi2 -gimp_transfer apic", "0.1,0.1,0.1,0.3,0.3,0.3",
                "0.3,0.1,0.2,0.5,0.3,0.4", "0.3,0.1,0.2,0.5,0.3,0.4", true);
}

} // namespace
