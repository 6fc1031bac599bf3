// The feature corners' knot clusters (core/knots/feature_knots.h).
#include "sdcb/core/knots/feature_knots.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace sdcb {
namespace {

TEST(CornerKnotClusters, TheCornerAndOneKnotAlongEachFeatureEdge) {
  // A corner (vertex 0) with three feature edges and a fourth vertex that
  // only the edge (1, 2) reaches.
  Eigen::MatrixX3d sphere(4, 3);
  sphere << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  sphere.rowwise().normalize();
  MeshFeatures features;
  features.edges = {{0, 1}, {0, 2}, {0, 3}, {1, 2}};
  features.corners = {0};
  const double gap = 1e-3;
  const Eigen::MatrixX3d knots = CornerKnotClusters(features, sphere, gap);
  ASSERT_EQ(knots.rows(), 4);
  const Eigen::Vector3d corner = sphere.row(0);
  EXPECT_EQ((knots.row(0).transpose() - corner).norm(), 0.0);
  for (int k = 1; k <= 3; ++k) {
    const Eigen::Vector3d knot = knots.row(k);
    const Eigen::Vector3d other = sphere.row(k);
    EXPECT_NEAR(knot.norm(), 1.0, 1e-15);
    // `gap` radians from the corner, on the great circle toward the edge's
    // other end, on the corner's side.
    EXPECT_NEAR(std::atan2(knot.cross(corner).norm(), knot.dot(corner)), gap,
                1e-15);
    EXPECT_NEAR(knot.dot(corner.cross(other).normalized()), 0.0, 1e-15);
    EXPECT_LT((knot - other).norm(), (corner - other).norm());
  }
}

// The arcs come back from the knots alone: the cube's clusters give its 8
// corners and 12 edges, and knots without clusters give none.
TEST(FeatureArcsOfKnots, TheCubesEdgesFromItsClusters) {
  Eigen::MatrixX3d sphere(8, 3);
  for (int c = 0; c < 8; ++c) {
    sphere.row(c) << (c & 1 ? 1 : -1), (c & 2 ? 1 : -1), (c & 4 ? 1 : -1);
  }
  sphere.rowwise().normalize();
  MeshFeatures features;
  for (int a = 0; a < 8; ++a) {
    features.corners.push_back(a);
    for (int b = a + 1; b < 8; ++b) {
      const int differ = a ^ b;
      if (differ == 1 || differ == 2 || differ == 4) {
        features.edges.push_back({a, b});
      }
    }
  }
  const Eigen::MatrixX3d knots = CornerKnotClusters(features, sphere);
  ASSERT_EQ(knots.rows(), 32);
  const KnotFeatureArcs arcs = FeatureArcsOfKnots(knots);
  ASSERT_EQ(arcs.corners.size(), 8u);
  ASSERT_EQ(arcs.arcs.size(), 12u);
  for (const auto& arc : arcs.arcs) {
    const Eigen::Vector3d a = knots.row(arcs.corners[arc[0]]);
    const Eigen::Vector3d b = knots.row(arcs.corners[arc[1]]);
    // Adjacent cube corners: 1/3 apart in the dot product.
    EXPECT_NEAR(a.dot(b), 1.0 / 3.0, 1e-12);
  }
  EXPECT_TRUE(FeatureArcsOfKnots(sphere).arcs.empty());
}

TEST(CornerKnotClusters, NoCornersNoKnots) {
  Eigen::MatrixX3d sphere(2, 3);
  sphere << 1, 0, 0, 0, 1, 0;
  MeshFeatures features;
  features.edges = {{0, 1}};
  EXPECT_EQ(CornerKnotClusters(features, sphere).rows(), 0);
}

TEST(ClustersKeepEveryFeature, CurvesAlongOneArcBetweenCorners) {
  // Vertices 0, 1, 2 on the equator (1 between 0 and 2), 3 off it.
  Eigen::MatrixX3d sphere(4, 3);
  sphere << 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1;
  sphere.rowwise().normalize();
  MeshFeatures features;
  features.edges = {{0, 1}, {1, 2}};
  features.curves = {{{0, 1}, false}, {{1, 2}, false}};
  EXPECT_FALSE(FeatureCurvesJoinCorners(features));  // no corners
  EXPECT_FALSE(ClustersKeepEveryFeature(features, sphere));
  features.corners = {0, 1, 2};
  EXPECT_TRUE(ClustersKeepEveryFeature(features, sphere));
  features.corners = {0, 1};  // the second curve ends at a non-corner
  EXPECT_FALSE(FeatureCurvesJoinCorners(features));
  EXPECT_FALSE(ClustersKeepEveryFeature(features, sphere));
  // One curve through vertex 1, on the great circle of its ends: an arc.
  features.corners = {0, 2};
  features.curves = {{{0, 1, 2}, false}};
  EXPECT_TRUE(ClustersKeepEveryFeature(features, sphere));
  // Vertex 1 a hair (1e-6 rad) off that circle, or beyond an end: not one.
  sphere.row(1) << 1, 1, 1.4142e-6;
  sphere.row(1).normalize();
  EXPECT_TRUE(FeatureCurvesJoinCorners(features));
  EXPECT_FALSE(ClustersKeepEveryFeature(features, sphere));
  sphere.row(1) << -1, 1, 0;
  sphere.row(1).normalize();
  EXPECT_FALSE(ClustersKeepEveryFeature(features, sphere));
}

// Several knots along each feature edge: gap, 2 gap, 4 gap from the corner
// on the great circle toward the far end of the edge's curve (a chain of two
// edges here, whose middle vertex the knots do not aim at).
TEST(CornerKnotClusters, SeveralKnotsAlongTheCurve) {
  Eigen::MatrixX3d sphere(3, 3);
  sphere << 1, 0, 0, 0.6, 0.8, 0.001, 0, 1, 0;
  MeshFeatures features;
  features.edges = {{0, 1}, {1, 2}};
  features.curves = {{{0, 1, 2}, false}};
  features.corners = {0, 2};
  const double gap = 1e-3;
  const Eigen::MatrixX3d knots = CornerKnotClusters(features, sphere, gap, 3);
  ASSERT_EQ(knots.rows(), 8);  // 2 corners x (1 + 3)
  for (int c = 0; c < 2; ++c) {
    const Eigen::Vector3d corner = knots.row(4 * c);
    EXPECT_EQ(corner, sphere.row(2 * c).transpose());
    for (int k = 1; k <= 3; ++k) {
      const Eigen::Vector3d knot = knots.row(4 * c + k);
      EXPECT_NEAR(std::atan2(knot.cross(corner).norm(), knot.dot(corner)),
                  gap * std::pow(2.0, k - 1), 1e-15);
      EXPECT_NEAR(knot.z(), 0.0, 1e-15);  // on the equator, not toward 1
      EXPECT_GT(knot.dot(sphere.row(2 - 2 * c)),
                corner.dot(sphere.row(2 - 2 * c)));
    }
  }
}

// A regular tetrahedron's clusters with four knots along each edge (what
// the fit tries at degree 4): its 4 corners and 6 edges come back, the
// further knots along an edge being no corner between its two ends.
TEST(FeatureArcsOfKnots, TheTetrahedronsEdgesFromClustersOfSeveralKnots) {
  Eigen::MatrixX3d sphere(4, 3);
  sphere << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  sphere.rowwise().normalize();
  MeshFeatures features;
  features.corners = {0, 1, 2, 3};
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) {
      features.edges.push_back({a, b});
      features.curves.push_back({{a, b}, false});
    }
  }
  const Eigen::MatrixX3d knots =
      CornerKnotClusters(features, sphere, kCornerClusterGap, 4);
  ASSERT_EQ(knots.rows(), 52);  // 4 x (1 + 3 x 4)
  const KnotFeatureArcs arcs = FeatureArcsOfKnots(knots);
  ASSERT_EQ(arcs.corners.size(), 4u);
  EXPECT_EQ(arcs.arcs.size(), 6u);
  for (size_t c = 0; c < arcs.corners.size(); ++c) {
    EXPECT_NEAR((arcs.corner_directions.row(c) -
                 sphere.row(static_cast<Eigen::Index>(c)))
                    .norm(),
                0.0, 1e-15);
  }
}

}  // namespace
}  // namespace sdcb
