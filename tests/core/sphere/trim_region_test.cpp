// Tests core/sphere/trim_region.* against brute force on an icosphere whose
// faces are split into kept ones and holes: a random point is kept exactly
// when the spherical triangle that holds it is kept (point location by
// three orientation signs, face by face), and its distance to the trims is
// the least closed-form point-to-arc angle over all hole sides.
#include "sdcb/core/sphere/trim_region.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/icosphere.h"
#include "testing/icosphere_patches.h"
#include "testing/random_sphere_points.h"

namespace sdcb {
namespace {

// The angle from unit p to the shorter great arc a -> b, by angles in the
// arc's own frame: the foot of p on the great circle is on the arc when its
// angle from a (towards b) lies in [0, angle(a, b)].
double BruteArcAngle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                     const Eigen::Vector3d& b) {
  const Eigen::Vector3d e = (b - a.dot(b) * a).normalized();
  const Eigen::Vector3d n = a.cross(e);
  const double end = std::atan2(b.dot(e), b.dot(a));
  const double foot = std::atan2(p.dot(e), p.dot(a));
  auto angle = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
    return std::atan2(x.cross(y).norm(), x.dot(y));
  };
  if (foot >= 0 && foot <= end) {
    return std::abs(std::asin(std::clamp(p.dot(n), -1.0, 1.0)));
  }
  return std::min(angle(p, a), angle(p, b));
}

struct Case {
  TriangleMesh sphere;
  std::vector<bool> kept;
  std::vector<TrimLoop> loops;
};

Case MakeCase(int subdivisions,
              const std::function<bool(const Eigen::Vector3d&)>& keep,
              int expected_loops) {
  Case c;
  c.sphere = MakeIcosphere(subdivisions);
  c.kept = testing::FacesWhere(c.sphere, keep);
  bool simple = false;
  const std::vector<std::vector<int>> loops =
      testing::BruteForceLoops(c.sphere, c.kept, &simple);
  EXPECT_TRUE(simple);
  EXPECT_EQ(static_cast<int>(loops.size()), expected_loops);
  for (const std::vector<int>& loop : loops) {
    TrimLoop t;
    t.points.resize(loop.size(), 3);
    for (size_t i = 0; i < loop.size(); ++i) {
      t.points.row(i) = c.sphere.vertices.row(loop[i]);
    }
    c.loops.push_back(t);
  }
  return c;
}

void ExpectAgreesWithBruteForce(const Case& c, int points,
                                int distance_points) {
  const StatusOr<TrimRegion> region = TrimRegion::Create(c.loops);
  ASSERT_TRUE(region.ok()) << region.status().message();
  const Eigen::MatrixX3d queries = testing::RandomUnitVectors(points, 54);
  int compared = 0, kept = 0;
  for (int i = 0; i < points; ++i) {
    const Eigen::Vector3d p = queries.row(i);
    // Point location: the face with p on the left of (or on) all its sides.
    int face = -1;
    for (int f = 0; f < c.sphere.num_faces() && face < 0; ++f) {
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        const Eigen::Vector3d a = c.sphere.vertices.row(c.sphere.faces(f, k));
        const Eigen::Vector3d b =
            c.sphere.vertices.row(c.sphere.faces(f, (k + 1) % 3));
        inside = p.dot(a.cross(b)) >= 0;
      }
      if (inside) face = f;
    }
    ASSERT_GE(face, 0);
    double nearest = std::numeric_limits<double>::infinity();
    for (const TrimLoop& loop : c.loops) {
      for (Eigen::Index j = 0; j < loop.points.rows(); ++j) {
        nearest = std::min(
            nearest,
            BruteArcAngle(p, loop.points.row(j),
                          loop.points.row((j + 1) % loop.points.rows())));
      }
    }
    if (i < distance_points) {
      EXPECT_NEAR(region->DistanceToTrim(p), nearest, 1e-12) << "point " << i;
      EXPECT_NEAR(region->DistanceToTrim(p, 0.05), std::min(nearest, 0.05),
                  1e-12)
          << "point " << i;
    }
    if (nearest < 1e-12) continue;
    ++compared;
    kept += c.kept[face];
    EXPECT_EQ(region->Contains(p), c.kept[face]) << "point " << i;
  }
  EXPECT_GT(compared, points * 99 / 100);
  // Both answers occur.
  EXPECT_GT(kept, 0);
  EXPECT_LT(kept, compared);
}

TEST(TrimRegionTest, ThreeHolesAgreeWithPointLocation) {
  const Case c = MakeCase(
      3,
      [](const Eigen::Vector3d& x) {
        return x.x() < 0.9 && x.y() < 0.8 && x.z() < 0.7;
      },
      3);
  ExpectAgreesWithBruteForce(c, 20000, 2000);
}

TEST(TrimRegionTest, HoleLargerThanAHemisphere) {
  const Case c = MakeCase(
      3, [](const Eigen::Vector3d& x) { return x.z() > 0.6; }, 1);
  ExpectAgreesWithBruteForce(c, 20000, 2000);
}

TEST(TrimRegionTest, TubeKeepsTheBandBetweenTwoHoles) {
  const Case c = MakeCase(
      3, [](const Eigen::Vector3d& x) { return std::abs(x.z()) < 0.5; }, 2);
  ExpectAgreesWithBruteForce(c, 20000, 2000);
}

TEST(TrimRegionTest, WindingLoopOnAFineSphere) {
  // A hole shaped like a wavy band's complement on a finer mesh: the kept
  // region is where z is near a sine of the longitude (one long loop pair).
  const Case c = MakeCase(
      4,
      [](const Eigen::Vector3d& x) {
        return std::abs(x.z() - 0.4 * std::sin(5 * std::atan2(x.y(), x.x()))) <
               0.25;
      },
      2);
  ExpectAgreesWithBruteForce(c, 20000, 2000);
}

TEST(TrimRegionTest, LongSidesOctantKeptOrOctantHole) {
  // Sides of 90 degrees: the kept region is the positive octant (its
  // corners counter-clockwise seen from outside), or, reversed, the octant
  // is the hole. Brute force: the octant is where all coordinates are >= 0.
  TrimLoop octant;
  octant.points = Eigen::Matrix3d::Identity();
  TrimLoop reversed;
  reversed.points = octant.points.colwise().reverse();
  const StatusOr<TrimRegion> kept = TrimRegion::Create({octant});
  const StatusOr<TrimRegion> hole = TrimRegion::Create({reversed});
  ASSERT_TRUE(kept.ok() && hole.ok());
  const Eigen::MatrixX3d queries = testing::RandomUnitVectors(20000, 8);
  int inside = 0;
  for (int i = 0; i < queries.rows(); ++i) {
    const Eigen::Vector3d p = queries.row(i);
    if (p.minCoeff() > -1e-12 && p.minCoeff() < 1e-12) continue;
    const bool in_octant = p.minCoeff() >= 0;
    inside += in_octant;
    EXPECT_EQ(kept->Contains(p), in_octant) << i;
    EXPECT_EQ(hole->Contains(p), !in_octant) << i;
    // The distance to the octant's sides: in the octant, its smallest
    // coordinate's arcsine (the nearest side's plane is a coordinate plane).
    if (in_octant) {
      EXPECT_NEAR(kept->DistanceToTrim(p), std::asin(p.minCoeff()), 1e-12);
    }
  }
  EXPECT_NEAR(inside, 20000 / 8, 200);
}

TEST(TrimRegionTest, PointsNearASideAndOnTheLeftAreKept) {
  // A triangle around the north pole, clockwise from above (the cap is the
  // hole): points 1e-9 inside and outside the middle of a side.
  TrimLoop loop;
  loop.points.resize(3, 3);
  for (int i = 0; i < 3; ++i) {
    const double phi = -2 * kPi * i / 3;
    loop.points.row(i) << 0.5 * std::cos(phi), 0.5 * std::sin(phi),
        std::sqrt(0.75);
  }
  const StatusOr<TrimRegion> region = TrimRegion::Create({loop});
  ASSERT_TRUE(region.ok());
  const Eigen::Vector3d a = loop.points.row(0), b = loop.points.row(1);
  const Eigen::Vector3d n = a.cross(b).normalized();
  const Eigen::Vector3d mid = (a + b).normalized();
  EXPECT_TRUE(region->Contains((mid + 1e-9 * n).normalized()));
  EXPECT_FALSE(region->Contains((mid - 1e-9 * n).normalized()));
  EXPECT_FALSE(region->Contains(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(region->Contains(-Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(region->DistanceToTrim((mid + 1e-9 * n).normalized()), 1e-9,
              1e-15);
}

TEST(TrimRegionTest, NoLoopsKeepsEverything) {
  const TrimRegion region;
  EXPECT_TRUE(region.empty());
  EXPECT_TRUE(region.Contains(Eigen::Vector3d::UnitX()));
  EXPECT_EQ(region.DistanceToTrim(Eigen::Vector3d::UnitX()),
            std::numeric_limits<double>::infinity());
}

TEST(TrimRegionTest, ValidateTrimLoopNamesTheProblem) {
  TrimLoop loop;
  loop.points.resize(2, 3);
  loop.points << 1, 0, 0, 0, 1, 0;
  EXPECT_EQ(ValidateTrimLoop(loop).code(), StatusCode::kInvalidArgument);
  loop.points.resize(3, 3);
  loop.points << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  EXPECT_TRUE(ValidateTrimLoop(loop).ok());
  loop.points(1, 1) = 1.001;  // not unit
  EXPECT_EQ(ValidateTrimLoop(loop).code(), StatusCode::kInvalidArgument);
  loop.points << 1, 0, 0, 1, 0, 0, 0, 0, 1;  // equal neighbours
  EXPECT_EQ(ValidateTrimLoop(loop).code(), StatusCode::kInvalidArgument);
  loop.points << 1, 0, 0, 0, 1, 0, -1, 0, 0;  // last and first antipodal
  EXPECT_EQ(ValidateTrimLoop(loop).code(), StatusCode::kInvalidArgument);
  loop.points(1, 0) = std::nan("");
  EXPECT_EQ(ValidateTrimLoop(loop).code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(TrimRegion::Create({loop}).ok());
}

}  // namespace
}  // namespace sdcb
