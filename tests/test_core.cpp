// The core room: the one-line user error and how ranks agree on it, numbers as error lines
// write them, the determinant's fixed order, and the SSE2 pairs being the scalar code lane by
// lane (bit for bit, NaN included). Run on 1 and on 2 ranks (Agree.* needs 2 to mean anything).
#include "gimp/core/errors.hpp"
#include "gimp/core/pair.hpp"
#include "gimp/core/tensor.hpp"

#include <Eigen/LU>
#include <gtest/gtest.h>
#include <petscsys.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace {

int rankOf(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}
int sizeOf(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

/// The InputError agree() throws on this rank ("" when it returns).
std::string agreed(const std::string &mine) {
  try {
    EXPECT_EQ(gimp::agree(PETSC_COMM_WORLD, mine), 0);
  } catch (const gimp::InputError &e) {
    return e.what();
  }
  return "";
}

TEST(Agree, NoErrorOnAnyRankThrowsNothing) {
  EXPECT_EQ(agreed(""), "");
}

TEST(Agree, ErrorOnTheLastRankOnlyEndsEveryRank) {
  const int last = sizeOf(PETSC_COMM_WORLD) - 1;
  const std::string mine = rankOf(PETSC_COMM_WORLD) == last ? "option -gimp_x 1: bad" : "";
  EXPECT_EQ(agreed(mine), "option -gimp_x 1: bad");
}

TEST(Agree, TheLowestRankWithAnErrorSpeaksForAll) {
  const int r = rankOf(PETSC_COMM_WORLD);
  EXPECT_EQ(agreed("error of rank " + std::to_string(r)), "error of rank 0");
  // A long message (longer than any fixed buffer) arrives whole.
  const std::string longText(100000, r == 0 ? 'a' : 'b');
  EXPECT_EQ(agreed(longText), std::string(100000, 'a'));
}

TEST(FormatNumber, TwelveSignificantDigits) {
  EXPECT_EQ(gimp::formatNumber(0.1), "0.1");
  EXPECT_EQ(gimp::formatNumber(-2.5e-7), "-2.5e-07");
  EXPECT_EQ(gimp::formatNumber(1.0 / 3.0), "0.333333333333");
  EXPECT_EQ(gimp::formatNumber(120e9), "120000000000");
  EXPECT_EQ(gimp::formatNumber(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(gimp::formatNumber(std::nan("")), "nan");
}

TEST(Determinant, AgreesWithEigenInBothDimensions) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int t = 0; t < 200; ++t) {
    gimp::Tensor<2> a;
    gimp::Tensor<3> b;
    for (int i = 0; i < 4; ++i)
      a.data()[i] = u(rng);
    for (int i = 0; i < 9; ++i)
      b.data()[i] = u(rng);
    EXPECT_NEAR(gimp::determinant<2>(a), a.determinant(), 1e-14);
    EXPECT_NEAR(gimp::determinant<3>(b), b.determinant(), 1e-13);
  }
  // Exact for a permutation and a shear (det 1) of integers.
  gimp::Tensor<3> p;
  p << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  EXPECT_EQ(gimp::determinant<3>(p), 1.0);
  gimp::Tensor<2> s;
  s << 1, 3, 0, 1;
  EXPECT_EQ(gimp::determinant<2>(s), 1.0);
}

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(Pair, EveryOperationIsTheScalarOneLaneByLane) {
  namespace simd = gimp::simd;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  for (int t = 0; t < 1000; ++t) {
    double a[2] = {u(rng), u(rng)}, b[2] = {u(rng), u(rng)};
    if (t % 10 == 1) a[t % 20 == 1] = nan;
    if (t % 10 == 2) b[0] = a[0]; // equal lanes
    if (t % 10 == 3) b[1] = -inf;
    const simd::Pair A = simd::load(a), B = simd::load(b);
    double out[2];
    simd::store(out, A * B + A / B - B);
    for (int i = 0; i < 2; ++i)
      EXPECT_TRUE(sameBits(out[i], a[i] * b[i] + a[i] / b[i] - b[i]) || std::isnan(out[i]));
    simd::store(out, simd::minOf(A, B));
    for (int i = 0; i < 2; ++i)
      EXPECT_TRUE(sameBits(out[i], simd::minOf(a[i], b[i]))) << a[i] << " " << b[i];
    simd::store(out, simd::maxOf(A, B));
    for (int i = 0; i < 2; ++i)
      EXPECT_TRUE(sameBits(out[i], simd::maxOf(a[i], b[i]))) << a[i] << " " << b[i];
    double acc[2] = {b[0], b[1]};
    simd::addTo(acc, A);
    for (int i = 0; i < 2; ++i)
      EXPECT_TRUE(sameBits(acc[i], b[i] + a[i]) || std::isnan(acc[i]));
  }
}

} // namespace
