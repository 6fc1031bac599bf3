// The central projection of a star-shaped mesh
// (core/param/central_projection.h).
#include "sdcb/core/param/central_projection.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "testing/make_mesh.h"

namespace sdcb {
namespace {

// The octahedron with vertices +-e_i (shifted by `offset`), outward
// triangles; `apex` replaces the +z vertex.
TriangleMesh Octahedron(const Eigen::Vector3d& offset,
                        const Eigen::Vector3d& apex) {
  return testing::MakeMesh(
      {Eigen::Vector3d(1, 0, 0) + offset, Eigen::Vector3d(0, 1, 0) + offset,
       Eigen::Vector3d(-1, 0, 0) + offset, Eigen::Vector3d(0, -1, 0) + offset,
       apex + offset, Eigen::Vector3d(0, 0, -1) + offset},
      {{0, 1, 4},
       {1, 2, 4},
       {2, 3, 4},
       {3, 0, 4},
       {1, 0, 5},
       {2, 1, 5},
       {3, 2, 5},
       {0, 3, 5}});
}

TEST(CentralProjection, AConvexSolidProjectsFromItsCentroid) {
  const Eigen::Vector3d offset(3, -2, 5);
  auto sphere = CentralProjection(Octahedron(offset, {0, 0, 1}));
  ASSERT_TRUE(sphere.has_value());
  // The centroid is the offset: each vertex's direction from it.
  EXPECT_LT((sphere->row(0) - Eigen::RowVector3d(1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((sphere->row(4) - Eigen::RowVector3d(0, 0, 1)).norm(), 1e-15);
  // Every triangle keeps its orientation on the sphere.
  const TriangleMesh mesh = Octahedron(offset, {0, 0, 1});
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = sphere->row(mesh.faces(f, 0));
    const Eigen::Vector3d b = sphere->row(mesh.faces(f, 1));
    const Eigen::Vector3d c = sphere->row(mesh.faces(f, 2));
    EXPECT_GT(a.cross(b).dot(c), 0.0);
  }
}

// Faces that all point inward (CGAL's beam and tetrahedron are stored so):
// the directions mirrored in x, every sphere triangle still counter-
// clockwise in the faces' order.
TEST(CentralProjection, AnInwardSolidIsMirroredToKeepItsTrianglesOrder) {
  TriangleMesh inward = Octahedron(Eigen::Vector3d(1, 1, 1), {0, 0, 1});
  inward.faces.col(1).swap(inward.faces.col(2));
  auto sphere = CentralProjection(inward);
  ASSERT_TRUE(sphere.has_value());
  EXPECT_LT((sphere->row(0) - Eigen::RowVector3d(-1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((sphere->row(1) - Eigen::RowVector3d(0, 1, 0)).norm(), 1e-15);
  for (Eigen::Index f = 0; f < inward.faces.rows(); ++f) {
    const Eigen::Vector3d a = sphere->row(inward.faces(f, 0));
    const Eigen::Vector3d b = sphere->row(inward.faces(f, 1));
    const Eigen::Vector3d c = sphere->row(inward.faces(f, 2));
    EXPECT_GT(a.cross(b).dot(c), 0.0);
  }
  // Faces pointing both ways: no projection keeps them all.
  TriangleMesh mixed = Octahedron(Eigen::Vector3d::Zero(), {0, 0, 1});
  mixed.faces.row(0) = Eigen::RowVector3i(mixed.faces(0, 0), mixed.faces(0, 2),
                                          mixed.faces(0, 1));
  EXPECT_FALSE(CentralProjection(mixed).has_value());
}

TEST(CentralProjection, AFaceThatDoesNotSeeTheCentroidRefuses) {
  // The apex pulled in below the equator: its four triangles face away
  // from the centroid.
  EXPECT_FALSE(
      CentralProjection(Octahedron(Eigen::Vector3d::Zero(), {0, 0, -0.2}))
          .has_value());
}

}  // namespace
}  // namespace sdcb
