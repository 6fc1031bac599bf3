// Tests core/mesh/hole_filling.* on parts cut from an icosphere (a disk, a
// tube, a sphere with three holes, a small cap whose hole is most of the
// sphere): the result must be closed genus 0 by AnalyzeMeshTopology, keep
// the part's rows, and name the loops a brute-force boundary walk finds.
#include "sdcb/core/mesh/hole_filling.h"

#include <gtest/gtest.h>

#include <set>
#include <utility>
#include <vector>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "testing/icosphere_patches.h"

namespace sdcb {
namespace {

// Checks every promise of the header for the part, and that its loops are
// `expected_loops` in number.
void ExpectFilled(const TriangleMesh& part, int expected_loops) {
  const StatusOr<FilledMesh> filled = FillHoles(part);
  ASSERT_TRUE(filled.ok()) << filled.status().message();
  const TriangleMesh& m = filled->mesh;
  // Closed, manifold, genus 0.
  const StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(m);
  ASSERT_TRUE(topology.ok());
  EXPECT_TRUE(topology->ok) << DescribeTopologyProblem(*topology);
  EXPECT_EQ(topology->boundary_loops, 0);
  EXPECT_EQ(topology->genus, 0);
  EXPECT_EQ(topology->components, 1);
  // The part's rows first, unchanged; the fill only adds.
  EXPECT_EQ(filled->input_vertices, part.num_vertices());
  EXPECT_EQ(filled->input_faces, part.num_faces());
  ASSERT_GE(m.num_vertices(), part.num_vertices());
  ASSERT_GT(m.num_faces(), part.num_faces());
  EXPECT_TRUE(m.vertices.topRows(part.num_vertices()) == part.vertices);
  EXPECT_TRUE(m.faces.topRows(part.num_faces()) == part.faces);
  // The loops: as many as expected, equal to the brute-force walk (which
  // follows the part's own directed edges, so each loop edge a -> b is an
  // edge of a part face), one method each.
  bool simple = false;
  const std::vector<std::vector<int>> loops = testing::BruteForceLoops(
      part, std::vector<bool>(part.num_faces(), true), &simple);
  ASSERT_TRUE(simple);
  ASSERT_EQ(static_cast<int>(loops.size()), expected_loops);
  EXPECT_EQ(filled->boundary_loops, loops);
  EXPECT_EQ(filled->fill_methods.size(), loops.size());
  // Every loop edge a -> b is in a part face as a -> b, and no fill face
  // uses it that way (the fill's face beside it runs b -> a).
  std::set<std::pair<int, int>> part_edges, fill_edges;
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      (f < part.num_faces() ? part_edges : fill_edges)
          .emplace(m.faces(f, k), m.faces(f, (k + 1) % 3));
    }
  }
  for (const std::vector<int>& loop : filled->boundary_loops) {
    for (size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      EXPECT_TRUE(part_edges.count({a, b})) << a << " -> " << b;
      EXPECT_TRUE(fill_edges.count({b, a})) << b << " -> " << a;
    }
  }
}

TEST(FillHolesTest, HemisphereDisk) {
  const TriangleMesh sphere = MakeIcosphere(3);
  ExpectFilled(testing::Submesh(
                   sphere, testing::FacesWhere(sphere,
                                               [](const Eigen::Vector3d& c) {
                                                 return c.z() > 0;
                                               })),
               1);
}

TEST(FillHolesTest, Tube) {
  const TriangleMesh sphere = MakeIcosphere(3);
  ExpectFilled(testing::Submesh(
                   sphere, testing::FacesWhere(sphere,
                                               [](const Eigen::Vector3d& c) {
                                                 return std::abs(c.z()) < 0.6;
                                               })),
               2);
}

TEST(FillHolesTest, SphereWithThreeHoles) {
  const TriangleMesh sphere = MakeIcosphere(4);
  ExpectFilled(testing::Submesh(sphere, testing::FacesWhere(
                                            sphere,
                                            [](const Eigen::Vector3d& c) {
                                              return c.x() < 0.9 &&
                                                     c.y() < 0.8 && c.z() < 0.7;
                                            })),
               3);
}

TEST(FillHolesTest, SmallCapWithAHoleOfMostOfTheSphere) {
  const TriangleMesh sphere = MakeIcosphere(5);
  ExpectFilled(testing::Submesh(
                   sphere, testing::FacesWhere(sphere,
                                               [](const Eigen::Vector3d& c) {
                                                 return c.z() > 0.9;
                                               })),
               1);
}

// Triangulated, a lone triangle's hole would be the triangle reversed: two
// triangles back to back on three vertices, which no sphere map embeds (the
// fit said "the base mesh's Tutte embedding has a folded triangle"). A fan
// from a fourth vertex gives a tetrahedron's combinatorics: 4 vertices,
// 4 faces.
TEST(FillHolesTest, SingleTriangleBecomesATetrahedron) {
  TriangleMesh triangle;
  triangle.vertices.resize(3, 3);
  triangle.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  triangle.faces.resize(1, 3);
  triangle.faces << 0, 1, 2;
  ExpectFilled(triangle, 1);
  const StatusOr<FilledMesh> filled = FillHoles(triangle);
  ASSERT_TRUE(filled.ok());
  EXPECT_EQ(filled->mesh.num_vertices(), 4);
  EXPECT_EQ(filled->mesh.num_faces(), 4);
  EXPECT_EQ(filled->fill_methods,
            std::vector<HoleFillMethod>{HoleFillMethod::kFan});
}

TEST(FillHolesTest, IcosahedronWithoutAFaceGetsItBack) {
  TriangleMesh open = MakeIcosphere(0);
  std::vector<bool> keep(open.num_faces(), true);
  keep[7] = false;
  open = testing::Submesh(open, keep);
  ExpectFilled(open, 1);
  const StatusOr<FilledMesh> filled = FillHoles(open);
  ASSERT_TRUE(filled.ok());
  // A 3-edge hole takes one triangle and no new vertex.
  EXPECT_EQ(filled->mesh.num_faces(), open.num_faces() + 1);
  EXPECT_EQ(filled->mesh.num_vertices(), open.num_vertices());
  EXPECT_EQ(filled->fill_methods[0], HoleFillMethod::kTriangulated);
}

TEST(FillHolesTest, ClosedPartComesBackUnchanged) {
  const TriangleMesh sphere = MakeIcosphere(2);
  const StatusOr<FilledMesh> filled = FillHoles(sphere);
  ASSERT_TRUE(filled.ok()) << filled.status().message();
  EXPECT_TRUE(filled->mesh.vertices == sphere.vertices);
  EXPECT_TRUE(filled->mesh.faces == sphere.faces);
  EXPECT_TRUE(filled->boundary_loops.empty());
}

TEST(FillHolesTest, IndexOutOfRangeIsInvalidInput) {
  TriangleMesh bad = MakeIcosphere(0);
  bad.faces(3, 1) = 99;
  const StatusOr<FilledMesh> filled = FillHoles(bad);
  ASSERT_FALSE(filled.ok());
  EXPECT_EQ(filled.status().code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace sdcb
