// core/mesh/triangle_mesh.h's per-vertex areas and normals against closed
// forms: a regular tetrahedron (every vertex a third of three faces, normal
// along its position by symmetry) and an icosphere (areas summing to the
// mesh's area, normals approaching the sphere's); the midpoint subdivision
// against Euler's formula, the tetrahedron's area and volume, and its faces.
#include "sdcb/core/mesh/triangle_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
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

TEST(TriangleMeshTest, MidpointSubdivisionKeepsTheSurfacePointForPoint) {
  const TriangleMesh m = RegularTetrahedron();
  const TriangleMesh s = MidpointSubdivided(m, 2);
  // Each level: V + E vertices (E = 3F / 2 on a closed mesh), 4F faces.
  ASSERT_EQ(s.num_vertices(), 4 + 6 + 24);
  ASSERT_EQ(s.num_faces(), 64);
  EXPECT_EQ(s.vertices.topRows(4), m.vertices);
  // Every edge of the result is shared by exactly two faces, once each way.
  std::map<std::pair<int, int>, int> edges;
  for (int f = 0; f < s.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k)
      ++edges[{s.faces(f, k), s.faces(f, (k + 1) % 3)}];
  }
  ASSERT_EQ(edges.size(), 2u * 96u);
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  // Area 4 * 2 sqrt 3 and volume (2 sqrt 2)^3 / (6 sqrt 2) = 8 / 3, signed
  // by the faces' orientation.
  EXPECT_NEAR(VertexAreas(s).sum(), 8.0 * std::sqrt(3.0), 1e-12);
  double volume = 0.0;
  for (int f = 0; f < s.num_faces(); ++f) {
    const Eigen::Vector3d a = s.vertices.row(s.faces(f, 0));
    const Eigen::Vector3d b = s.vertices.row(s.faces(f, 1));
    const Eigen::Vector3d c = s.vertices.row(s.faces(f, 2));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  EXPECT_NEAR(volume, 8.0 / 3.0, 1e-12);
  // Every vertex lies in the plane of one of the tetrahedron's faces.
  for (int v = 0; v < s.num_vertices(); ++v) {
    const Eigen::Vector3d x = s.vertices.row(v);
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
  EXPECT_EQ(MidpointSubdivided(m, 0).vertices, m.vertices);
}

}  // namespace
}  // namespace sdcb
