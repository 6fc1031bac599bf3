// core/mesh/triangle_mesh.h's per-vertex areas and normals against closed
// forms: a regular tetrahedron (every vertex a third of three faces, normal
// along its position by symmetry) and an icosphere (areas summing to the
// mesh's area, normals approaching the sphere's); the split to an edge
// length against Euler's formula, the tetrahedron's area and volume, and its
// faces; the covering radius against brute force.
#include "sdcb/core/mesh/triangle_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <utility>

#include "sdcb/core/mesh/icosphere.h"
#include "testing/fan_mesh.h"

namespace sdcb {
namespace {

using testing::RegularTetrahedron;

TEST(TriangleMeshTest, RegularTetrahedronAreasAndNormalsInClosedForm) {
  const TriangleMesh m = RegularTetrahedron();
  // Edge 2 sqrt 2: each face sqrt(3) / 4 * 8 = 2 sqrt 3.
  const Eigen::VectorXd area = VertexAreas(m);
  const Eigen::MatrixX3d normal = VertexNormals(m);
  for (int v = 0; v < 4; ++v) {
    EXPECT_NEAR(area[v], 2.0 * std::sqrt(3.0), 1e-12) << v;
    const Eigen::Vector3d expected = m.vertices.row(v).normalized();
    EXPECT_NEAR((normal.row(v).transpose() - expected).norm(), 0.0, 1e-12) << v;
  }
}

TEST(TriangleMeshTest, IcosphereAreasSumToTheMeshAndNormalsPointOutward) {
  const TriangleMesh m = MakeIcosphere(3);
  double total = 0.0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.vertices.row(m.faces(f, 0));
    const Eigen::Vector3d b = m.vertices.row(m.faces(f, 1));
    const Eigen::Vector3d c = m.vertices.row(m.faces(f, 2));
    total += 0.5 * (b - a).cross(c - a).norm();
  }
  EXPECT_NEAR(VertexAreas(m).sum(), total, 1e-12 * total);
  const Eigen::MatrixX3d normal = VertexNormals(m);
  for (int v = 0; v < m.num_vertices(); ++v) {
    EXPECT_NEAR(normal.row(v).norm(), 1.0, 1e-12);
    EXPECT_GT(normal.row(v).dot(m.vertices.row(v).normalized()), 0.999) << v;
  }
}

// A vertex whose triangles' normals cancel (two copies of one triangle,
// opposite orientations) gets a zero normal, not NaN.
TEST(TriangleMeshTest, CancellingNormalsGiveZero) {
  TriangleMesh m;
  m.vertices.resize(3, 3);
  m.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  m.faces.resize(2, 3);
  m.faces << 0, 1, 2, 0, 2, 1;
  const Eigen::MatrixX3d normal = VertexNormals(m);
  EXPECT_EQ(normal, Eigen::MatrixX3d::Zero(3, 3));
}

// Every directed edge once and its reverse once: a closed, conforming,
// consistently oriented mesh. Returns the number of undirected edges.
size_t ExpectClosedAndConforming(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> edges;
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k)
      ++edges[{m.faces(f, k), m.faces(f, (k + 1) % 3)}];
  }
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  return edges.size() / 2;
}

double SignedVolume(const TriangleMesh& m) {
  double volume = 0.0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.vertices.row(m.faces(f, 0));
    const Eigen::Vector3d b = m.vertices.row(m.faces(f, 1));
    const Eigen::Vector3d c = m.vertices.row(m.faces(f, 2));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

double LongestEdge(const TriangleMesh& m) {
  double longest = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      longest = std::max(longest, (m.vertices.row(m.faces(f, k)) -
                                   m.vertices.row(m.faces(f, (k + 1) % 3)))
                                      .norm());
    }
  }
  return longest;
}

TEST(TriangleMeshTest, SplittingToAnEdgeLengthKeepsTheSurfacePointForPoint) {
  const TriangleMesh m = RegularTetrahedron();
  auto s = SplitToEdgeLength(m, 0.3, 100000);
  ASSERT_TRUE(s.has_value());
  EXPECT_LE(LongestEdge(*s), 0.3);
  EXPECT_EQ(s->vertices.topRows(4), m.vertices);
  // Closed and conforming (the two triangles of an edge split it alike):
  // Euler's formula of a sphere.
  const size_t edges = ExpectClosedAndConforming(*s);
  EXPECT_EQ(s->num_vertices() - static_cast<int>(edges) + s->num_faces(), 2);
  // Area 4 * 2 sqrt 3 and volume (2 sqrt 2)^3 / (6 sqrt 2) = 8 / 3, signed
  // by the faces' orientation.
  EXPECT_NEAR(VertexAreas(*s).sum(), 8.0 * std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(SignedVolume(*s), 8.0 / 3.0, 1e-12);
  // Every vertex lies on one of the tetrahedron's faces.
  for (int v = 0; v < s->num_vertices(); ++v) {
    const Eigen::Vector3d x = s->vertices.row(v);
    double on_face = 1e300;
    for (int f = 0; f < 4; ++f) {
      const Eigen::Vector3d a = m.vertices.row(m.faces(f, 0));
      const Eigen::Vector3d b = m.vertices.row(m.faces(f, 1));
      const Eigen::Vector3d c = m.vertices.row(m.faces(f, 2));
      const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
      on_face = std::min(on_face, std::abs((x - a).dot(n)));
    }
    EXPECT_LT(on_face, 1e-12) << v;
  }
  // Edge 2 sqrt 2 halved 4 times is 0.177 <= 0.3 < 0.354: each face's
  // edges get 15 points inside. A piece of edges <= 0.3 has at most the
  // area of the equilateral one: 8 sqrt 3 / (0.09 sqrt 3 / 4) = 356 pieces
  // at least.
  EXPECT_GE(s->num_faces(), 356);
  int on_edges = 0;
  for (int v = 4; v < s->num_vertices(); ++v) {
    const Eigen::Vector3d x = s->vertices.row(v);
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        const Eigen::Vector3d a = m.vertices.row(i), b = m.vertices.row(j);
        on_edges += (x - a).cross(b - a).norm() < 1e-12;
      }
    }
  }
  EXPECT_EQ(on_edges, 6 * 15);
  // Too many vertices: nothing; a length not > 0: nothing split.
  EXPECT_FALSE(SplitToEdgeLength(m, 0.3, s->num_vertices() - 1).has_value());
  EXPECT_EQ(SplitToEdgeLength(m, 0.3, s->num_vertices())->faces, s->faces);
  EXPECT_EQ(SplitToEdgeLength(m, 0.0, 4)->faces, m.faces);
  EXPECT_EQ(SplitToEdgeLength(m, std::nan(""), 4)->faces, m.faces);
  EXPECT_EQ(SplitToEdgeLength(m, 3.0, 4)->faces, m.faces);
}

// Needles (a double cone of 1024 long, thin triangles, 0.006 wide at the
// rim) are split along their length, not into squares: the vertices grow
// like the needles' length over the limit, not like its square.
TEST(TriangleMeshTest, SplittingNeedlesGrowsLinearlyInTheirLength) {
  const TriangleMesh m = testing::DoubleCone(1024);
  Eigen::Index previous = 0;
  for (double h : {0.2, 0.1, 0.05}) {
    auto s = SplitToEdgeLength(m, h, 10000000);
    ASSERT_TRUE(s.has_value());
    EXPECT_LE(LongestEdge(*s), h);
    ExpectClosedAndConforming(*s);
    EXPECT_NEAR(VertexAreas(*s).sum(), VertexAreas(m).sum(), 1e-12);
    // Each of the 2048 slant edges (length sqrt 2) needs sqrt 2 / h - 1
    // points inside at least.
    EXPECT_GE(s->num_vertices(), 2048 * (std::sqrt(2.0) / h - 1));
    if (previous > 0) {
      EXPECT_LT(s->num_vertices(), 2.5 * previous) << h;
    }
    previous = s->num_vertices();
  }
}

// SplitEdgeLengthFor: a coarse mesh split to the length for n vertices has
// about n (the icosahedron's 12 vertices split for 1,000 to 40,000), and
// its edges are then about as long as an even mesh of n vertices' (area
// A = 2 n (sqrt 3 / 4) h^2 for n vertices, 2 n triangles of side h).
TEST(TriangleMeshTest, TheSplitEdgeLengthForNVerticesGivesAboutN) {
  const TriangleMesh m = MakeIcosphere(0);
  ASSERT_EQ(m.num_vertices(), 12);
  const double area = VertexAreas(m).sum();
  for (int n : {1000, 5000, 40000}) {
    SCOPED_TRACE(n);
    const double h = SplitEdgeLengthFor(area, n);
    EXPECT_NEAR(h, std::sqrt(3.0 * area / n), 1e-15);
    auto s = SplitToEdgeLength(m, h, 10 * int64_t{n});
    ASSERT_TRUE(s.has_value());
    EXPECT_GT(s->num_vertices(), 0.5 * n);
    EXPECT_LT(s->num_vertices(), 1.2 * n);
    const double even = std::sqrt(2.0 * area / (std::sqrt(3.0) * n));
    EXPECT_GT(LongestEdge(*s), 0.5 * even);
    EXPECT_LE(LongestEdge(*s), 1.5 * even);
  }
}

// CoveringRadius against brute force over a fine barycentric grid: equal
// for triangles without an obtuse angle, an upper bound (at most half the
// longest edge) for obtuse ones.
TEST(TriangleMeshTest, CoveringRadiusIsTheFarthestPointFromTheCorners) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  int acute = 0, obtuse = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d a(normal(rng), normal(rng), normal(rng));
    const Eigen::Vector3d b(normal(rng), normal(rng), normal(rng));
    const Eigen::Vector3d c(normal(rng), normal(rng), normal(rng));
    constexpr int kSteps = 300;
    double brute = 0;
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; i + j <= kSteps; ++j) {
        const Eigen::Vector3d x =
            a + (b - a) * i / kSteps + (c - a) * j / kSteps;
        brute = std::max(
            brute, std::min({(x - a).norm(), (x - b).norm(), (x - c).norm()}));
      }
    }
    const double r = CoveringRadius(a, b, c);
    const double longest =
        std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()});
    // The grid is 1 / 300 of an edge apart.
    const double grid = longest / kSteps;
    EXPECT_GE(r, brute - 1e-12);
    const bool is_obtuse = (b - a).dot(c - a) < 0 || (a - b).dot(c - b) < 0 ||
                           (a - c).dot(b - c) < 0;
    if (is_obtuse) {
      ++obtuse;
      EXPECT_LE(r, 0.5 * longest + 1e-12);
    } else {
      ++acute;
      EXPECT_NEAR(r, brute, grid);
      EXPECT_LE(r, longest / std::sqrt(3.0) + 1e-12);
    }
  }
  EXPECT_GT(acute, 20);
  EXPECT_GT(obtuse, 20);
  // Degenerate: a point, and three points on a line.
  const Eigen::Vector3d p(1, 2, 3);
  EXPECT_EQ(CoveringRadius(p, p, p), 0.0);
  EXPECT_DOUBLE_EQ(CoveringRadius(p, p + Eigen::Vector3d(1, 0, 0),
                                  p + Eigen::Vector3d(4, 0, 0)),
                   2.0);
}

}  // namespace
}  // namespace sdcb
