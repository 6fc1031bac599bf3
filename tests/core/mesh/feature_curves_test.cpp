#include "sdcb/core/mesh/feature_curves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/icosphere.h"
#include "testing/make_mesh.h"

namespace sdcb {
namespace {

// The unit cube, two triangles a side, counter-clockwise from outside.
TriangleMesh Cube() {
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<Eigen::Vector3i> f;
  for (const auto& q : quads) {
    f.emplace_back(q[0], q[1], q[2]);
    f.emplace_back(q[0], q[2], q[3]);
  }
  return testing::MakeMesh(v, f);
}

// A closed cylinder of radius 1 and height 1: n side quads (two triangles
// each) and two fans of n triangles around the caps' centres.
TriangleMesh Cylinder(int n) {
  std::vector<Eigen::Vector3d> v;
  for (int z = 0; z < 2; ++z) {
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * kPi * i / n;
      v.emplace_back(std::cos(a), std::sin(a), z);
    }
  }
  v.emplace_back(0, 0, 0);
  v.emplace_back(0, 0, 1);
  const int bottom = 2 * n, top = 2 * n + 1;
  std::vector<Eigen::Vector3i> f;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    f.emplace_back(i, j, n + j);
    f.emplace_back(i, n + j, n + i);
    f.emplace_back(bottom, j, i);
    f.emplace_back(top, n + i, n + j);
  }
  return testing::MakeMesh(v, f);
}

TEST(FeatureCurvesTest, CubeHasTwelveEdgesBetweenEightCorners) {
  // Across a cube edge the normals turn by 90 degrees, across a face's
  // diagonal by 0: 12 feature edges; three meet at every corner, so each
  // edge is a curve of its own.
  StatusOr<MeshFeatures> f = DetectFeatures(Cube(), 30.0);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->edges.size(), 12u);
  EXPECT_EQ(f->corners, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(f->curves.size(), 12u);
  std::set<std::pair<int, int>> ends;
  for (const FeatureCurve& c : f->curves) {
    EXPECT_FALSE(c.closed);
    ASSERT_EQ(c.vertices.size(), 2u);
    // A cube edge joins corners that differ in one coordinate bit.
    const int x = c.vertices[0] ^ c.vertices[1];
    EXPECT_TRUE(x == 1 || x == 2 || x == 4);
    ends.insert({std::min(c.vertices[0], c.vertices[1]),
                 std::max(c.vertices[0], c.vertices[1])});
  }
  EXPECT_EQ(ends.size(), 12u);
  // Nothing turns by more than 90 degrees.
  StatusOr<MeshFeatures> none = DetectFeatures(Cube(), 91.0);
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->edges.empty());
}

TEST(FeatureCurvesTest, CylinderRimsAreTwoClosedCurvesWithoutCorners) {
  // 24 sides: neighbouring side faces turn by 15 degrees, the rims by 90;
  // a rim turns by 15 degrees per vertex, no corner.
  const int n = 24;
  StatusOr<MeshFeatures> f = DetectFeatures(Cylinder(n), 30.0);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->edges.size(), size_t(2 * n));
  EXPECT_TRUE(f->corners.empty());
  ASSERT_EQ(f->curves.size(), 2u);
  for (const FeatureCurve& c : f->curves) {
    EXPECT_TRUE(c.closed);
    EXPECT_EQ(c.vertices.size(), size_t(n));
    std::set<int> rim(c.vertices.begin(), c.vertices.end());
    EXPECT_EQ(rim.size(), size_t(n));
    // One rim: all below n or all in [n, 2n).
    EXPECT_TRUE(*rim.rbegin() < n || *rim.begin() >= n);
  }
  // At 10 degrees the sides are features too: every rim vertex then has
  // three feature edges.
  StatusOr<MeshFeatures> fine = DetectFeatures(Cylinder(n), 10.0);
  ASSERT_TRUE(fine.ok());
  EXPECT_EQ(fine->edges.size(), size_t(3 * n));
  EXPECT_EQ(fine->corners.size(), size_t(2 * n));
}

TEST(FeatureCurvesTest, FlatBipyramidRimTurnsAtThreeCorners) {
  // A flat triangular bipyramid (apexes at +-0.1 over a unit triangle):
  // faces of one pyramid turn by 19.6 degrees, the rim's by 157: the rim is
  // three feature edges, and it turns by 120 degrees at each of its
  // vertices, which have only two feature edges.
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * kPi * i / 3.0;
    v.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  v.emplace_back(0, 0, 0.1);
  v.emplace_back(0, 0, -0.1);
  std::vector<Eigen::Vector3i> faces;
  for (int i = 0; i < 3; ++i) {
    faces.emplace_back(3, i, (i + 1) % 3);
    faces.emplace_back(4, (i + 1) % 3, i);
  }
  StatusOr<MeshFeatures> f = DetectFeatures(testing::MakeMesh(v, faces), 30.0);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->edges.size(), 3u);
  EXPECT_EQ(f->corners, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(f->curves.size(), 3u);
  // Below the pyramids' own turn every edge is a feature.
  StatusOr<MeshFeatures> all =
      DetectFeatures(testing::MakeMesh(v, faces), 15.0);
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(all->edges.size(), 9u);
}

TEST(FeatureCurvesTest, SmoothSphereHasNoneAndBadInputIsRefused) {
  // An icosphere of level 3: neighbouring faces turn by about 9 degrees.
  StatusOr<MeshFeatures> f = DetectFeatures(MakeIcosphere(3), 30.0);
  ASSERT_TRUE(f.ok());
  EXPECT_TRUE(f->edges.empty());
  EXPECT_TRUE(f->curves.empty());
  EXPECT_TRUE(f->corners.empty());
  EXPECT_FALSE(DetectFeatures(Cube(), 0.0).ok());
  EXPECT_FALSE(DetectFeatures(Cube(), 181.0).ok());
  TriangleMesh bad = Cube();
  bad.faces(3, 1) = 8;
  StatusOr<MeshFeatures> refused = DetectFeatures(bad, 30.0);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace sdcb
