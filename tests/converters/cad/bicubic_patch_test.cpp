// Tests of converters/cad/bicubic_patch: points against de Casteljau, and the
// volume and area of closed patch sets whose values are known (a box made
// of flat patches, poles moved within their faces; a translated copy).
#include "sdcb/converters/cad/bicubic_patch.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace sdcb {
namespace {

// De Casteljau on the 4 x 4 poles: u first, then v.
Eigen::Vector3d DeCasteljau(const BicubicPatch& patch, double u, double v) {
  std::array<Eigen::Vector3d, 4> rows;
  for (int j = 0; j < 4; ++j) {
    std::array<Eigen::Vector3d, 4> p;
    for (int i = 0; i < 4; ++i) p[i] = patch.poles[4 * j + i];
    for (int level = 3; level > 0; --level) {
      for (int i = 0; i < level; ++i) p[i] = (1 - u) * p[i] + u * p[i + 1];
    }
    rows[j] = p[0];
  }
  for (int level = 3; level > 0; --level) {
    for (int j = 0; j < level; ++j) {
      rows[j] = (1 - v) * rows[j] + v * rows[j + 1];
    }
  }
  return rows[0];
}

// A flat patch over the parallelogram origin + s a + t b, (s, t) in [0,1]^2,
// its inner and edge poles moved within the plane by up to `jitter` (the
// boundary curves stay on the parallelogram's sides).
BicubicPatch FlatPatch(const Eigen::Vector3d& origin, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b, double jitter,
                       std::mt19937* rng) {
  std::uniform_real_distribution<double> d(-jitter, jitter);
  BicubicPatch patch;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      double s = i / 3.0, t = j / 3.0;
      const bool inner_s = i == 1 || i == 2, inner_t = j == 1 || j == 2;
      if (inner_s) s += d(*rng);
      if (inner_t) t += d(*rng);
      patch.poles[4 * j + i] = origin + s * a + t * b;
    }
  }
  return patch;
}

// The six faces of the box [0, x] x [0, y] x [0, z] + corner, outward.
std::vector<BicubicPatch> Box(const Eigen::Vector3d& corner, double x, double y,
                              double z, double jitter) {
  std::mt19937 rng(7);
  const Eigen::Vector3d ex(x, 0, 0), ey(0, y, 0), ez(0, 0, z);
  return {FlatPatch(corner, ey, ex, jitter, &rng),        // z = 0
          FlatPatch(corner + ez, ex, ey, jitter, &rng),   // z = z
          FlatPatch(corner, ex, ez, jitter, &rng),        // y = 0
          FlatPatch(corner + ey, ez, ex, jitter, &rng),   // y = y
          FlatPatch(corner, ez, ey, jitter, &rng),        // x = 0
          FlatPatch(corner + ex, ey, ez, jitter, &rng)};  // x = x
}

TEST(BicubicPatchTest, EvaluateMatchesDeCasteljauAndDifferences) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1, 1);
  BicubicPatch patch;
  for (auto& p : patch.poles) p = Eigen::Vector3d(d(rng), d(rng), d(rng));
  for (double u : {0.0, 0.3, 0.71, 1.0}) {
    for (double v : {0.0, 0.45, 1.0}) {
      Eigen::Vector3d du, dv;
      const Eigen::Vector3d p = patch.Evaluate(u, v, &du, &dv);
      EXPECT_LT((p - DeCasteljau(patch, u, v)).norm(), 1e-14);
      const double h = 1e-6;
      const Eigen::Vector3d fu =
          (DeCasteljau(patch, u + h, v) - DeCasteljau(patch, u - h, v)) /
          (2 * h);
      const Eigen::Vector3d fv =
          (DeCasteljau(patch, u, v + h) - DeCasteljau(patch, u, v - h)) /
          (2 * h);
      EXPECT_LT((du - fu).norm(), 1e-8);
      EXPECT_LT((dv - fv).norm(), 1e-8);
    }
  }
}

TEST(BicubicPatchTest, VolumeAndAreaOfABoxAreExact) {
  for (double jitter : {0.0, 0.1}) {
    SCOPED_TRACE(jitter);
    const PatchSetMeasures m =
        MeasurePatchSet(Box(Eigen::Vector3d::Zero(), 2, 3, 5, jitter));
    EXPECT_NEAR(m.volume, 30.0, 1e-12);
    EXPECT_NEAR(m.area, 2 * (6 + 10 + 15), 1e-12);
    // The flux form does not depend on where the box is.
    const PatchSetMeasures moved =
        MeasurePatchSet(Box(Eigen::Vector3d(100, -40, 7), 2, 3, 5, jitter));
    EXPECT_NEAR(moved.volume, 30.0, 1e-9);
    EXPECT_NEAR(moved.area, m.area, 1e-9);
  }
  // Facing inward: the volume is negative.
  std::vector<BicubicPatch> inward = Box(Eigen::Vector3d::Zero(), 1, 1, 1, 0);
  for (BicubicPatch& p : inward) {
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < j; ++i)
        std::swap(p.poles[4 * j + i], p.poles[4 * i + j]);
    }
  }
  EXPECT_NEAR(MeasurePatchSet(inward).volume, -1.0, 1e-12);
}

TEST(BicubicPatchTest, QuadEdgeParametersRunAroundTheSquare) {
  EXPECT_EQ(QuadEdgeParameter(0, 0.25), Eigen::Vector2d(0.25, 0.0));
  EXPECT_EQ(QuadEdgeParameter(1, 0.25), Eigen::Vector2d(1.0, 0.25));
  EXPECT_EQ(QuadEdgeParameter(2, 0.25), Eigen::Vector2d(0.75, 1.0));
  EXPECT_EQ(QuadEdgeParameter(3, 0.25), Eigen::Vector2d(0.0, 0.75));
}

}  // namespace
}  // namespace sdcb
