// Tests core/sphere/unit_vector_grid.*: every grid point of small grids
// against the octahedral map's definition (|x| + |y| + |z| = 1, the lower
// half folded out), exact re-encoding of every decoded vector, and the
// angle a random direction moves when snapped, for every bit count.
#include "sdcb/core/sphere/unit_vector_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace sdcb {
namespace {

bool SameBits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0;
}

TEST(UnitVectorGridTest, EveryGridPointFollowsTheOctahedralMap) {
  for (int bits = kMinUnitVectorGridBits; bits <= 8; ++bits) {
    const uint32_t top = (1u << bits) - 1;
    for (uint32_t a = 0; a <= top; ++a) {
      for (uint32_t b = 0; b <= top; ++b) {
        const Eigen::Vector3d v = DecodeUnitVector({a, b}, bits);
        ASSERT_NEAR(v.norm(), 1.0, 1e-15);
        for (int c = 0; c < 3; ++c)
          ASSERT_FALSE(v[c] == 0 && std::signbit(v[c]));
        // The definition: v / |v|_1 = (u, v', 1 - |u| - |v'|) on the upper
        // half; on the lower half (u, v') = ((1 - |y|) sgn x, (1 - |x|) sgn y).
        const double u = (2.0 * a - top) / top, w = (2.0 * b - top) / top;
        const Eigen::Vector3d p = v / v.cwiseAbs().sum();
        if (1 - std::abs(u) - std::abs(w) >= 0) {
          EXPECT_NEAR(p.x(), u, 1e-15);
          EXPECT_NEAR(p.y(), w, 1e-15);
        } else {
          EXPECT_NEAR(std::abs(p.x()), 1 - std::abs(w), 1e-15);
          EXPECT_NEAR(std::abs(p.y()), 1 - std::abs(u), 1e-15);
          EXPECT_LT(p.z(), 0);
        }
        // Re-encoding names a grid point with exactly these bits.
        UnitVectorCode code;
        ASSERT_TRUE(IsOnUnitVectorGrid(v, bits, &code)) << a << " " << b;
        ASSERT_TRUE(SameBits(DecodeUnitVector(code, bits), v));
      }
    }
  }
}

TEST(UnitVectorGridTest, SnappingMovesADirectionByLessThanTheStatedAngle) {
  std::mt19937 rng(4);
  std::normal_distribution<double> gauss;
  for (int bits = 4; bits <= kMaxUnitVectorGridBits; ++bits) {
    const double limit = 2.5 * std::ldexp(1.0, 1 - bits);
    double largest = 0;
    for (int i = 0; i < 20000; ++i) {
      const Eigen::Vector3d d(gauss(rng), gauss(rng), gauss(rng));
      const Eigen::Vector3d s =
          DecodeUnitVector(EncodeUnitVector(d, bits), bits);
      largest =
          std::max(largest, std::acos(std::min(1.0, s.dot(d.normalized()))));
      ASSERT_TRUE(IsOnUnitVectorGrid(s, bits, nullptr));
    }
    EXPECT_LT(largest, limit) << bits;
    // Not vacuous: the worst sample moves by a good part of it.
    if (bits <= 20) EXPECT_GT(largest, 0.6 * limit) << bits;
  }
}

TEST(UnitVectorGridTest, OffGridVectorsAreNotOnTheGrid) {
  const Eigen::Vector3d v = Eigen::Vector3d(0.3, -0.4, 0.5).normalized();
  EXPECT_FALSE(IsOnUnitVectorGrid(v, 16, nullptr));
  EXPECT_FALSE(IsOnUnitVectorGrid(Eigen::Vector3d::Zero(), 16, nullptr));
  EXPECT_FALSE(IsOnUnitVectorGrid(Eigen::Vector3d(NAN, 0, 1), 16, nullptr));
  // Grid points of one grid are not (in general) points of another.
  const Eigen::Vector3d g = DecodeUnitVector({1234, 777}, 16);
  EXPECT_TRUE(IsOnUnitVectorGrid(g, 16, nullptr));
  EXPECT_FALSE(IsOnUnitVectorGrid(g, 15, nullptr));
}

}  // namespace
}  // namespace sdcb
