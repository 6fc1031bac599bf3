// The tessellator's pattern along feature arcs (core/tessellate/
// feature_pattern.h), against the cube: its 8 corners and 12 edges as arcs,
// and the cube fitted with corner knot clusters, tessellated from the arcs
// its knots hold, against the closed-form cube.
#include "sdcb/core/tessellate/feature_pattern.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/knots/feature_knots.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"
#include "testing/kept_cube.h"

namespace sdcb {
namespace {

// The cube's corners (unit vectors, corner c at signs of its bits) and
// edges (corners differing in one bit).
void CubeArcs(Eigen::MatrixX3d* corners,
              std::vector<std::array<int, 2>>* arcs) {
  corners->resize(8, 3);
  for (int c = 0; c < 8; ++c) {
    corners->row(c) << (c & 1 ? 1 : -1), (c & 2 ? 1 : -1), (c & 4 ? 1 : -1);
  }
  corners->rowwise().normalize();
  arcs->clear();
  for (int a = 0; a < 8; ++a) {
    for (int bit : {1, 2, 4}) {
      if (!(a & bit)) arcs->push_back({a, a | bit});
    }
  }
}

TEST(FeatureAlignedPattern, TheCubesEdgesAreEdgesOfItsTriangulation) {
  Eigen::MatrixX3d corners;
  std::vector<std::array<int, 2>> arcs;
  CubeArcs(&corners, &arcs);
  StatusOr<SphereTriangulation> pattern = FeatureAlignedPattern(corners, arcs);
  ASSERT_TRUE(pattern.ok()) << pattern.status().message();
  EXPECT_EQ(pattern->num_vertices(), 8);
  EXPECT_EQ(pattern->num_faces(), 12);  // two per face
  for (const auto& [a, b] : arcs) {
    EXPECT_GE(pattern->HalfEdge(a, b), 0);
    EXPECT_TRUE(pattern->IsFeatureEdge(a, b));
  }
  for (int f = 0; f < pattern->num_face_slots(); ++f) {
    EXPECT_TRUE(pattern->IsPositive(pattern->face(f)));
  }
  // An arc's edge does not flip; a corner does not collapse.
  const int h = pattern->HalfEdge(arcs[0][0], arcs[0][1]);
  std::array<SphereTriangulation::Face, 2> flipped;
  EXPECT_FALSE(pattern->PreviewFlip(h, &flipped));
  std::vector<SphereTriangulation::Face> faces;
  EXPECT_FALSE(
      pattern->PreviewCollapse(arcs[0][0], arcs[0][1], &faces, nullptr));
  // A split of an arc's edge stays on the arc, and so do its halves.
  const int m = pattern->SplitEdge(
      h,
      (pattern->vertex(arcs[0][0]) + pattern->vertex(arcs[0][1])).normalized());
  EXPECT_EQ(pattern->vertex_arc(m), 0);
  EXPECT_TRUE(pattern->IsFeatureEdge(arcs[0][0], m));
  EXPECT_TRUE(pattern->IsFeatureEdge(m, arcs[0][1]));
}

// The spherical area of the quad (a, b, c, d) as two triangles' excesses.
double QuadArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  const auto excess = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                         const Eigen::Vector3d& z) {
    return 2.0 *
           std::atan2(x.dot(y.cross(z)), 1.0 + x.dot(y) + y.dot(z) + z.dot(x));
  };
  return excess(a, b, c) + excess(a, c, d);
}

// FeatureQuads: the cube's faces as they are; the same cut (split), and the
// octahedron's triangles cut, into quads that tile the sphere (areas by the
// closed-form excess add up to 4 pi, each positive), with every crease on
// an arc and every arc covered by its two halves.
TEST(FeatureQuads, FacesAsQuadsOrCutIntoQuadsTileTheSphere) {
  Eigen::MatrixX3d cube;
  std::vector<std::array<int, 2>> cube_arcs;
  CubeArcs(&cube, &cube_arcs);
  Eigen::MatrixX3d octahedron(6, 3);
  octahedron << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  std::vector<std::array<int, 2>> octahedron_arcs;
  for (int a = 0; a < 6; ++a) {
    for (int b = a + 1; b < 6; ++b) {
      if (a / 2 != b / 2) octahedron_arcs.push_back({a, b});
    }
  }
  struct Case {
    const Eigen::MatrixX3d* corners;
    const std::vector<std::array<int, 2>>* arcs;
    bool split;
    int points, quads;
    bool split_result;
  };
  for (const Case& c :
       {Case{&cube, &cube_arcs, false, 8, 6, false},
        Case{&cube, &cube_arcs, true, 8 + 12 + 6, 24, true},
        Case{&octahedron, &octahedron_arcs, false, 6 + 12 + 8, 24, true}}) {
    StatusOr<FeatureQuadMesh> q = FeatureQuads(*c.corners, *c.arcs, c.split);
    ASSERT_TRUE(q.ok()) << q.status().message();
    EXPECT_EQ(q->split, c.split_result);
    ASSERT_EQ(q->points.rows(), c.points);
    ASSERT_EQ(static_cast<int>(q->quads.size()), c.quads);
    EXPECT_TRUE(q->points.topRows(c.corners->rows()).isApprox(*c.corners));
    double area = 0.0;
    for (const auto& quad : q->quads) {
      EXPECT_LT(quad[0], c.corners->rows());  // starts at a corner
      const double a = QuadArea(q->points.row(quad[0]), q->points.row(quad[1]),
                                q->points.row(quad[2]), q->points.row(quad[3]));
      EXPECT_GT(a, 0.0);
      area += a;
    }
    EXPECT_NEAR(area, 4.0 * kPi, 1e-12);
    ASSERT_EQ(q->creases.size(), c.arcs->size() * (c.split_result ? 2 : 1));
    for (const auto& [a, b] : q->creases) {
      // On an arc: both ends on one arc's great circle, between its ends.
      bool on_arc = false;
      for (const auto& arc : *c.arcs) {
        const Eigen::Vector3d x = c.corners->row(arc[0]);
        const Eigen::Vector3d y = c.corners->row(arc[1]);
        const Eigen::Vector3d n = x.cross(y).normalized();
        bool both = true;
        for (const int p : {a, b}) {
          const Eigen::Vector3d v = q->points.row(p);
          both &= std::abs(n.dot(v)) < 1e-15 && v.dot(x) >= x.dot(y) - 1e-15 &&
                  v.dot(y) >= x.dot(y) - 1e-15;
        }
        on_arc |= both;
      }
      EXPECT_TRUE(on_arc) << a << " " << b;
    }
  }
}

TEST(FeatureAlignedPattern, ArcsThatCrossOrDangleAreRefused) {
  Eigen::MatrixX3d corners;
  std::vector<std::array<int, 2>> arcs;
  CubeArcs(&corners, &arcs);
  // Both diagonals of the face z = -1 (corners 0..3): they cross.
  std::vector<std::array<int, 2>> crossing = arcs;
  crossing.push_back({0, 3});
  crossing.push_back({1, 2});
  EXPECT_EQ(FeatureAlignedPattern(corners, crossing).status().code(),
            StatusCode::kInvalidArgument);
  // A corner at the end of a single arc.
  std::vector<std::array<int, 2>> dangling(arcs.begin(), arcs.begin() + 1);
  EXPECT_EQ(FeatureAlignedPattern(corners, dangling).status().code(),
            StatusCode::kInvalidArgument);
}

// The cube fitted with its corners' knot clusters (FitOptions::keep_features),
// tessellated from the pattern of the arcs its knots hold: 12 flat
// triangles whose corners are the cube's (the closed form, side 1 in the
// normalized frame), split along the edges with the faces' normals. The
// icosphere's pattern crosses the creases and needs ~70,000 (docs/FITTING.md).
TEST(FeatureAlignedPattern, TheKeptCubeTessellatesIntoItsTwelveTriangles) {
  auto fit = testing::FitKeptCube();
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  ASSERT_TRUE(fit->features_kept);
  auto spline = SurfaceFromModel(fit->model);
  ASSERT_TRUE(spline.ok());
  const PiecewiseSurface pieces(*spline);
  const PiecewiseSplineSampler sampler(*spline, pieces);

  const KnotFeatureArcs arcs = FeatureArcsOfKnots(fit->model.knots);
  ASSERT_EQ(arcs.corners.size(), 8u);
  ASSERT_EQ(arcs.arcs.size(), 12u);
  StatusOr<SphereTriangulation> pattern =
      FeatureAlignedPattern(arcs.corner_directions, arcs.arcs);
  ASSERT_TRUE(pattern.ok()) << pattern.status().message();
  TessellationOptions options;
  options.tolerance = 1e-3;
  options.initial_pattern = &*pattern;
  StatusOr<Tessellation> t = TessellateAdaptively(sampler, options);
  ASSERT_TRUE(t.ok()) << t.status().message();
  EXPECT_EQ(t->faces.rows(), 12);
  EXPECT_EQ(t->uncertified_faces, 0);
  // Each corner once per side (3 x 8), with that side's normal: the
  // closed-form cube's corners and face normals.
  ASSERT_EQ(t->positions.rows(), 24);
  for (Eigen::Index f = 0; f < t->faces.rows(); ++f) {
    const Eigen::Vector3d a = t->positions.row(t->faces(f, 0));
    const Eigen::Vector3d b = t->positions.row(t->faces(f, 1));
    const Eigen::Vector3d c = t->positions.row(t->faces(f, 2));
    const Eigen::Vector3d face_normal = (b - a).cross(c - a).normalized();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d x = t->positions.row(t->faces(f, k));
      EXPECT_NEAR(x.cwiseAbs().minCoeff(), 0.5, 1e-4) << x.transpose();
      const Eigen::Vector3d n = t->normals.row(t->faces(f, k));
      EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-6) << n.transpose();
      EXPECT_GT(n.dot(face_normal), 1.0 - 1e-6);
    }
  }
}

}  // namespace
}  // namespace sdcb
