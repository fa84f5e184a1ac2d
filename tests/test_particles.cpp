// Seeding (the particles room): what seedParticles puts in the swarm, against what the scene
// describes exactly. Particles tile their bodies: their volumes sum to the body's area (2D, cut
// cells included: the moments of a square cut by a circle are exact) or volume (3D boxes), their
// masses to rho times it, and their mass-weighted centre is the body's centroid. A leaf cell of
// level k holds ppc = n^D particles of side h_k / n, so refining a level leaves those sums alone.
// Ids are unique, and id / idSlots is the body. A particle's centre lies in its body's box, and
// so does its whole domain unless an edge cuts it.
#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/seed.hpp"
#include "gimp/particles/swarm.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace {

using gimp::Grid;
using gimp::ParticleView;
using gimp::Scene;

constexpr double kPi = 3.14159265358979323846;

/// What a seeded swarm adds up to.
struct Seeded {
  PetscInt n = 0;
  double volume = 0, mass = 0, centre[3] = {0, 0, 0}; // centre: mass-weighted
  std::vector<double> sideMin, sideMax;               // per axis, over the particles
  bool idsUnique = true, idsOfBodies = true;
  bool centresInside = true; // every centre in its body's bounding box
  bool domainsInside = true; // every particle's domain too (a cut particle's may reach past it)
};

/// The scene of `options` read, its grid built and its particles seeded on one rank.
template <int D> Seeded seed(const std::string &options) {
  Seeded out;
  EXPECT_EQ(PetscOptionsClear(nullptr), 0);
  EXPECT_EQ(PetscOptionsInsertString(nullptr, options.c_str()), 0);
  Scene<D> sc;
  EXPECT_EQ(gimp::readScene<D>(PETSC_COMM_SELF, sc), 0) << options;
  Grid<D> grid;
  EXPECT_EQ(grid.create(PETSC_COMM_SELF, sc.h, sc.levelBoxes(), sc.cracks), 0);
  sc.idSlots = gimp::bodyIdSlots<D>(grid);
  DM sw = nullptr;
  EXPECT_EQ(gimp::createSwarm<D>(PETSC_COMM_SELF, gimp::optionalFieldsOf(sc), &sw), 0);
  gimp::LoadConflict conflict;
  EXPECT_EQ(gimp::seedParticles<D>(sc, grid, sw, conflict), 0);
  ParticleView<D> p;
  EXPECT_EQ(p.get(sw), 0);
  out.n = p.n;
  out.sideMin.assign(D, 1e300);
  out.sideMax.assign(D, 0);
  std::set<PetscInt64> ids;
  for (PetscInt k = 0; k < p.n; ++k) {
    out.volume += p.V[k];
    out.mass += p.m[k];
    for (int a = 0; a < D; ++a) {
      out.centre[a] += p.m[k] * p.x[D * k + a];
      out.sideMin[a] = std::min(out.sideMin[a], 2 * p.l[D * k + a]);
      out.sideMax[a] = std::max(out.sideMax[a], 2 * p.l[D * k + a]);
    }
    out.idsUnique = out.idsUnique && ids.insert(p.id[k]).second;
    const PetscInt64 body = p.id[k] / sc.idSlots;
    if (body < 0 || body >= static_cast<PetscInt64>(sc.bodies.size())) {
      out.idsOfBodies = false;
      continue;
    }
    const auto &box = sc.bodies[body].box;
    for (int a = 0; a < D; ++a) {
      const double x = p.x[D * k + a], l = p.l[D * k + a];
      out.centresInside = out.centresInside && x >= box[a] && x <= box[D + a];
      out.domainsInside =
          out.domainsInside && x - l >= box[a] - 1e-12 && x + l <= box[D + a] + 1e-12;
    }
  }
  for (int a = 0; a < D; ++a)
    out.centre[a] /= out.mass;
  EXPECT_EQ(p.restore(sw), 0);
  EXPECT_EQ(DMDestroy(&sw), 0);
  return out;
}

const std::string kMaterial = "-gimp_E 1e7 -gimp_nu 0.3 -gimp_rho 1000 ";

TEST(Seeding, RectangleTiledByPpcSquaresPerCell) {
  // A 1 x 0.4 box on h = 0.1: 40 cells of ppc = n^2 squares of side h / n.
  for (int ppc : {1, 2, 3, 5}) {
    const Seeded s = seed<2>(kMaterial + "-gimp_h 0.1 -gimp_body0_box 0,0,1,0.4 -gimp_body0_ppc " +
                             std::to_string(ppc * ppc));
    EXPECT_EQ(s.n, 40 * ppc * ppc) << ppc;
    EXPECT_NEAR(s.volume, 0.4, 1e-14) << ppc;
    EXPECT_NEAR(s.mass, 400.0, 1e-11) << ppc;
    EXPECT_NEAR(s.centre[0], 0.5, 1e-14) << ppc;
    EXPECT_NEAR(s.centre[1], 0.2, 1e-14) << ppc;
    for (int a = 0; a < 2; ++a) {
      EXPECT_NEAR(s.sideMin[a], 0.1 / ppc, 1e-15) << ppc;
      EXPECT_NEAR(s.sideMax[a], 0.1 / ppc, 1e-15) << ppc;
    }
    EXPECT_TRUE(s.idsUnique && s.idsOfBodies && s.centresInside && s.domainsInside) << ppc;
  }
}

TEST(Seeding, RefinedLevelsKeepTheSums) {
  // Two refined levels (ratios 2 and 3) over part of the body: leaf cells of h / 2 and h / 6
  // hold ppc particles each, and the totals are those of one level.
  const std::string levels = "-gimp_levels 3 -gimp_level1_box 0.2,0,0.8,0.4 -gimp_level1_ratio 2 "
                             "-gimp_level2_box 0.3,0.1,0.5,0.3 -gimp_level2_ratio 3 ";
  const Seeded s =
      seed<2>(kMaterial + levels + "-gimp_h 0.1 -gimp_body0_box 0,0,1,0.4 -gimp_body0_ppc 4");
  // Cells: level 0 outside level 1: 40 - 24 = 16; level 1 outside level 2: 96 - 16 = 80;
  // level 2: (0.2 / (0.1 / 6))^2 = 144.
  EXPECT_EQ(s.n, 4 * (16 + 80 + 144));
  EXPECT_NEAR(s.volume, 0.4, 1e-14);
  EXPECT_NEAR(s.mass, 400.0, 1e-11);
  EXPECT_NEAR(s.centre[0], 0.5, 1e-13);
  EXPECT_NEAR(s.centre[1], 0.2, 1e-13);
  EXPECT_NEAR(s.sideMin[0], 0.1 / 12, 1e-15);
  EXPECT_NEAR(s.sideMax[0], 0.1 / 2, 1e-15);
  EXPECT_TRUE(s.idsUnique && s.idsOfBodies && s.centresInside && s.domainsInside);
}

TEST(Seeding, CutCellsGiveTheExactArea) {
  // A quarter hole of radius 0.002 at the corner of a 0.03 square (the plate scene) and a
  // circle body: the cut squares' areas sum to the exact area, their centroids to the exact
  // first moments.
  const double r = 0.002, a = 0.03;
  const Seeded plate = seed<2>(kMaterial + "-gimp_h 1e-3 -gimp_body0_box 0,0,0.03,0.03 "
                                           "-gimp_body0_holes 0,0,0.002 -gimp_body0_ppc 1 "
                                           "-gimp_body0_hole_ppc 4");
  const double area = a * a - kPi * r * r / 4;
  EXPECT_NEAR(plate.volume, area, 1e-13 * area);
  // First moment of the plate less the quarter disk (its centroid at 4r / 3 pi from the corner).
  const double mx = a * a * a / 2 - (kPi * r * r / 4) * (4 * r / (3 * kPi));
  EXPECT_NEAR(plate.centre[0], mx / area, 1e-12 * a);
  EXPECT_NEAR(plate.centre[1], mx / area, 1e-12 * a);
  EXPECT_TRUE(plate.idsUnique && plate.idsOfBodies && plate.centresInside);

  const Seeded disk = seed<2>(kMaterial + "-gimp_h 0.1 -gimp_body0_shape circle "
                                          "-gimp_body0_circle 0.55,0.45,0.37 -gimp_body0_ppc 9");
  EXPECT_NEAR(disk.volume, kPi * 0.37 * 0.37, 1e-13);
  EXPECT_NEAR(disk.centre[0], 0.55, 1e-13);
  EXPECT_NEAR(disk.centre[1], 0.45, 1e-13);
  EXPECT_TRUE(disk.idsUnique && disk.idsOfBodies && disk.centresInside);
}

TEST(Seeding, TwoBodiesHaveTheirOwnIds) {
  const Seeded s =
      seed<2>(kMaterial + "-gimp_h 0.1 -gimp_bodies 2 -gimp_body0_box 0,0,0.4,0.4 "
                          "-gimp_body0_ppc 4 -gimp_body1_box 0.6,0,1,0.2 -gimp_body1_ppc 9");
  EXPECT_EQ(s.n, 16 * 4 + 8 * 9);
  EXPECT_NEAR(s.volume, 0.16 + 0.08, 1e-14);
  EXPECT_TRUE(s.idsUnique && s.idsOfBodies && s.centresInside && s.domainsInside);
}

TEST(Seeding, BoxIn3DTiledByPpcCubesPerCell) {
  // A 0.4 x 0.3 x 0.2 box on h = 0.1: 24 cells of ppc = n^3 cubes of side h / n.
  for (int ppc : {1, 2, 3}) {
    const Seeded s = seed<3>(kMaterial +
                             "-gimp_dim 3 -gimp_h 0.1 -gimp_body0_box "
                             "0,0,0,0.4,0.3,0.2 -gimp_body0_ppc " +
                             std::to_string(ppc * ppc * ppc));
    EXPECT_EQ(s.n, 24 * ppc * ppc * ppc) << ppc;
    EXPECT_NEAR(s.volume, 0.024, 1e-15) << ppc;
    EXPECT_NEAR(s.mass, 24.0, 1e-12) << ppc;
    EXPECT_NEAR(s.centre[0], 0.2, 1e-14) << ppc;
    EXPECT_NEAR(s.centre[1], 0.15, 1e-14) << ppc;
    EXPECT_NEAR(s.centre[2], 0.1, 1e-14) << ppc;
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(s.sideMax[a], 0.1 / ppc, 1e-15) << ppc;
    EXPECT_TRUE(s.idsUnique && s.idsOfBodies && s.centresInside && s.domainsInside) << ppc;
  }
}

TEST(Seeding, CutCellsIn3DGiveTheExactVolume) {
  // A sphere, a cylinder along x and a box with a spherical hole, none on the particle lattice:
  // the cut cubes' volumes sum to the exact volumes, their centroids to the exact centres.
  const std::string dim = kMaterial + "-gimp_dim 3 -gimp_h 0.1 -gimp_body0_ppc 8 ";
  const double r = 0.37, V = 4 * kPi * r * r * r / 3;
  const Seeded ball =
      seed<3>(dim + "-gimp_body0_shape sphere -gimp_body0_sphere 0.55,0.45,0.52,0.37");
  EXPECT_NEAR(ball.volume, V, 1e-10 * V);
  const double c[3] = {0.55, 0.45, 0.52};
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(ball.centre[a], c[a], 1e-12);
  EXPECT_TRUE(ball.idsUnique && ball.idsOfBodies && ball.centresInside);

  const Seeded rod = seed<3>(dim + "-gimp_body0_shape cylinder -gimp_body0_cylinder_axis x "
                                   "-gimp_body0_cylinder 0.43,0.41,0.23,0.07,0.88");
  const double Vc = kPi * 0.23 * 0.23 * 0.81;
  EXPECT_NEAR(rod.volume, Vc, 1e-10 * Vc);
  EXPECT_NEAR(rod.centre[0], 0.475, 1e-12);
  EXPECT_NEAR(rod.centre[1], 0.43, 1e-12);
  EXPECT_NEAR(rod.centre[2], 0.41, 1e-12);

  const Seeded holed = seed<3>(dim + "-gimp_body0_box 0,0,0,0.6,0.5,0.4 "
                                     "-gimp_body0_hole_spheres 0.31,0.26,0.18,0.13");
  const double Vh = 0.6 * 0.5 * 0.4 - 4 * kPi * std::pow(0.13, 3) / 3;
  EXPECT_NEAR(holed.volume, Vh, 1e-10 * Vh);
  EXPECT_TRUE(holed.idsUnique && holed.idsOfBodies && holed.centresInside);

  // A sphere with a cylindrical hole through its centre: cubes that both surfaces cut.
  const Seeded bead =
      seed<3>(dim + "-gimp_body0_shape sphere -gimp_body0_sphere "
                    "0.55,0.45,0.52,0.37 -gimp_body0_hole_cylinders 0.55,0.45,0.13");
  const double Vb = 4 * kPi / 3 * std::pow(0.37 * 0.37 - 0.13 * 0.13, 1.5);
  EXPECT_NEAR(bead.volume, Vb, 1e-10 * Vb);
}

TEST(Seeding, HoleBandsIn3DTakeTheirOwnPpc) {
  // A box with a spherical and a cylindrical hole, one particle per cell and 8 in the cells next
  // to the holes: the cut cubes still sum to the exact volume, ids stay unique, and a band that
  // covers the whole box gives the particles of 8 per cell everywhere.
  const std::string box = kMaterial + "-gimp_dim 3 -gimp_h 0.1 -gimp_body0_box 0,0,0,0.6,0.5,0.4 "
                                      "-gimp_body0_hole_spheres 0.31,0.26,0.18,0.13 "
                                      "-gimp_body0_hole_cylinders 0.48,0.12,0.06 ";
  const double V = 0.6 * 0.5 * 0.4 - 4 * kPi * std::pow(0.13, 3) / 3 - kPi * 0.06 * 0.06 * 0.4;
  const Seeded one = seed<3>(box + "-gimp_body0_ppc 1");
  const Seeded eight = seed<3>(box + "-gimp_body0_ppc 8");
  const Seeded band = seed<3>(box + "-gimp_body0_ppc 1 -gimp_body0_hole_ppc 8");
  const Seeded all = seed<3>(box + "-gimp_body0_ppc 1 -gimp_body0_hole_ppc 8 "
                                   "-gimp_body0_hole_band 1");
  for (const Seeded *s : {&one, &eight, &band, &all}) {
    EXPECT_NEAR(s->volume, V, 1e-10 * V);
    EXPECT_TRUE(s->idsUnique && s->idsOfBodies && s->centresInside);
  }
  EXPECT_GT(band.n, one.n);
  EXPECT_LT(band.n, eight.n);
  for (int a = 0; a < 3; ++a) { // whole cells away from the holes, the cut sub-cubes at them
    EXPECT_NEAR(band.sideMax[a], 0.1, 1e-15);
    EXPECT_EQ(band.sideMin[a], eight.sideMin[a]);
  }
  EXPECT_EQ(all.n, eight.n);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(all.centre[a], eight.centre[a], 1e-14);
}

TEST(Seeding, SphereCutsThatAreNotExactAreNamed) {
  // Two spherical surfaces that cross (a hole through a sphere body's surface, two holes that
  // meet) are where 3D cut cells are approximate; apart or nested inside the body they are exact.
  auto named = [](const std::string &shape) {
    EXPECT_EQ(PetscOptionsClear(nullptr), 0);
    EXPECT_EQ(
        PetscOptionsInsertString(nullptr, (kMaterial + "-gimp_dim 3 -gimp_h 0.1 " + shape).c_str()),
        0);
    Scene<3> sc;
    EXPECT_EQ(gimp::readScene<3>(PETSC_COMM_SELF, sc), 0) << shape;
    return gimp::approximateCuts(sc.bodies.at(0), "gimp_body0_");
  };
  const std::string ball = "-gimp_body0_shape sphere -gimp_body0_sphere 0,0,0,0.5 ";
  EXPECT_NE(named(ball + "-gimp_body0_hole_spheres 0.5,0,0,0.2").find("crosses the surface"),
            std::string::npos);
  EXPECT_NE(named(ball + "-gimp_body0_hole_spheres 0.15,0,0,0.2,-0.15,0,0,0.2").find("meet"),
            std::string::npos);
  EXPECT_EQ(named(ball + "-gimp_body0_hole_spheres 0.25,0,0,0.1,-0.25,0,0,0.1"), "");
  EXPECT_EQ(named("-gimp_body0_box 0,0,0,1,1,1 -gimp_body0_hole_spheres 0.5,0.5,0.5,0.2"), "");
}

TEST(Swarm, ClassMovesMakeClassesContiguousMovingOnlyTheStrays) {
  // Rate classes made contiguous (a per-level step's coarse start): after classMoves and
  // permuteSwarmAt the classes run 0, 1, 2 in order, every particle keeps all its fields (its id
  // with its position, mass and volume), and a particle already in its class's range stays.
  EXPECT_EQ(PetscOptionsClear(nullptr), 0);
  EXPECT_EQ(PetscOptionsInsertString(nullptr, (kMaterial + "-gimp_h 0.1 -gimp_body0_box 0,0,1,0.5 "
                                                           "-gimp_body0_ppc 4")
                                                  .c_str()),
            0);
  Scene<2> sc;
  ASSERT_EQ(gimp::readScene<2>(PETSC_COMM_SELF, sc), 0);
  Grid<2> grid;
  ASSERT_EQ(grid.create(PETSC_COMM_SELF, sc.h, sc.levelBoxes(), sc.cracks), 0);
  sc.idSlots = gimp::bodyIdSlots<2>(grid);
  DM sw = nullptr;
  ASSERT_EQ(gimp::createSwarm<2>(PETSC_COMM_SELF, gimp::optionalFieldsOf(sc), &sw), 0);
  gimp::LoadConflict conflict;
  ASSERT_EQ(gimp::seedParticles<2>(sc, grid, sw, conflict), 0);
  ParticleView<2> p;
  ASSERT_EQ(p.get(sw), 0);
  const PetscInt n = p.n;
  ASSERT_EQ(n, 200);
  // Classes as a per-level step leaves them (0 ... 0 1 ... 1 2 ... 2), then a few particles
  // changed class, in both directions and by two classes.
  std::vector<int> cls(static_cast<size_t>(n));
  for (PetscInt k = 0; k < n; ++k)
    cls[k] = k < 120 ? 0 : k < 170 ? 1 : 2;
  for (PetscInt k : {3, 57, 119})
    cls[k] = 1;
  cls[60] = 2;
  for (PetscInt k : {121, 150})
    cls[k] = 0;
  cls[199] = 0;
  std::map<PetscInt64, std::array<double, 4>> was; // id -> x, y, m, V
  for (PetscInt k = 0; k < n; ++k)
    was[p.id[k]] = {p.x[2 * k], p.x[2 * k + 1], p.m[k], p.V[k]};
  std::vector<PetscInt64> idBefore(p.id, p.id + n);
  ASSERT_EQ(p.restore(sw), 0);
  std::vector<PetscInt> at, from;
  gimp::classMoves(cls, at, from);
  ASSERT_EQ(at.size(), from.size());
  EXPECT_EQ(std::set<PetscInt>(at.begin(), at.end()), std::set<PetscInt>(from.begin(), from.end()));
  ASSERT_EQ(gimp::permuteSwarmAt<2>(sw, at, from), 0);
  std::vector<int> now = cls;
  for (size_t j = 0; j < at.size(); ++j)
    now[at[j]] = cls[from[j]];
  EXPECT_TRUE(std::is_sorted(now.begin(), now.end()));
  EXPECT_EQ(std::count(now.begin(), now.end(), 0), std::count(cls.begin(), cls.end(), 0));
  EXPECT_EQ(std::count(now.begin(), now.end(), 2), std::count(cls.begin(), cls.end(), 2));
  ASSERT_EQ(p.get(sw), 0);
  const std::set<PetscInt> moved(at.begin(), at.end());
  // Ranges now [0, 119), [119, 170), [170, 200): 119 stays (its new class's range starts there);
  // 3, 57 (to class 1), 60 (to 2), 121, 150 and 199 (to 0) move, each into a place another of
  // them left.
  EXPECT_EQ(moved, (std::set<PetscInt>{3, 57, 60, 121, 150, 199}));
  for (PetscInt k = 0; k < n; ++k) {
    const std::array<double, 4> &w = was.at(p.id[k]);
    EXPECT_EQ(p.x[2 * k], w[0]);
    EXPECT_EQ(p.x[2 * k + 1], w[1]);
    EXPECT_EQ(p.m[k], w[2]);
    EXPECT_EQ(p.V[k], w[3]);
    if (!moved.count(k)) {
      EXPECT_EQ(p.id[k], idBefore[k]) << k;
    }
  }
  ASSERT_EQ(p.restore(sw), 0);
  ASSERT_EQ(DMDestroy(&sw), 0);
}

} // namespace
