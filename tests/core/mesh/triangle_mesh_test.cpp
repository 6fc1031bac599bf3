// core/mesh/triangle_mesh.h's per-vertex areas and normals against closed
// forms: a regular tetrahedron (every vertex a third of three faces, normal
// along its position by symmetry) and an icosphere (areas summing to the
// mesh's area, normals approaching the sphere's).
#include "sdcb/core/mesh/triangle_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {
namespace {

TEST(TriangleMeshTest, RegularTetrahedronAreasAndNormalsInClosedForm) {
  TriangleMesh m;
  m.vertices.resize(4, 3);
  m.vertices << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  m.faces.resize(4, 3);
  m.faces << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
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

}  // namespace
}  // namespace sdcb
