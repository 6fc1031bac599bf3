// Tests core/mesh/vertex_welding.*: equal positions numbered in order of
// first appearance, and the intake's seam rule (weld what only closes
// boundary edges, leave apart what would make the mesh worse), against
// meshes and results written by hand.
#include "sdcb/core/mesh/vertex_welding.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sdcb/core/mesh/mesh_topology.h"
#include "testing/make_mesh.h"
#include "testing/seam_split_cube.h"

namespace sdcb {
namespace {

using testing::kCubeCorners;
using testing::kCubeQuads;
using testing::SeamSplitCube;

TEST(VertexWeldingTest, EqualPositionsNumberedInOrderOfFirstAppearance) {
  Eigen::MatrixX3d v(6, 3);
  v << 1, 0, 0,      //
      0, 0, 0,       //
      -0.0, 0, 0,    // equal to row 1: -0 == +0
      1, 0, 0,       //
      1, 0, 1e-300,  //
      0, 0, 0;
  EXPECT_EQ(EqualPositionNumbers(v), (std::vector<int>{0, 1, 1, 0, 2, 1}));
  EXPECT_TRUE(EqualPositionNumbers(Eigen::MatrixX3d(0, 3)).empty());
}

TEST(VertexWeldingTest, SeamSplitCubeWeldsToTheEightCornerCube) {
  const TriangleMesh split = SeamSplitCube();
  // Unwelded: six open quads.
  auto before = AnalyzeMeshTopology(split);
  ASSERT_TRUE(before.ok());
  EXPECT_EQ(before->components, 6);
  EXPECT_EQ(before->boundary_loops, 6);

  SeamWeldReport report;
  auto welded = WeldSeams(split, &report);
  ASSERT_TRUE(welded.ok()) << welded.status().message();
  EXPECT_EQ(report.merged_vertices, 16);
  EXPECT_EQ(report.declined_vertices, 0);
  EXPECT_EQ(report.Describe(),
            "merged 16 vertices split at equal positions (UV or normal "
            "seams)");
  // Corners in order of first appearance in the quad list: 0, 3, 2, 1
  // (bottom quad), then 4, 5, 6, 7 (top quad).
  const int new_of_corner[8] = {0, 3, 2, 1, 4, 5, 6, 7};
  const TriangleMesh& cube = welded->mesh;
  ASSERT_EQ(cube.num_vertices(), 8);
  ASSERT_EQ(cube.num_faces(), 12);
  for (int c = 0; c < 8; ++c) {
    EXPECT_EQ(cube.vertices.row(new_of_corner[c]),
              Eigen::RowVector3d(kCubeCorners[c][0], kCubeCorners[c][1],
                                 kCubeCorners[c][2]));
  }
  for (int q = 0; q < 6; ++q) {
    const int* c = kCubeQuads[q];
    EXPECT_EQ(cube.faces.row(2 * q),
              Eigen::RowVector3i(new_of_corner[c[0]], new_of_corner[c[1]],
                                 new_of_corner[c[2]]));
    EXPECT_EQ(cube.faces.row(2 * q + 1),
              Eigen::RowVector3i(new_of_corner[c[0]], new_of_corner[c[2]],
                                 new_of_corner[c[3]]));
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(welded->new_vertex[4 * q + k], new_of_corner[c[k]]);
    }
  }
  auto after = AnalyzeMeshTopology(cube);
  ASSERT_TRUE(after.ok());
  EXPECT_TRUE(after->ok) << DescribeTopologyProblem(*after);
  // The unit cube, outward: volume 1.
  EXPECT_DOUBLE_EQ(SignedVolume(cube.vertices, cube.faces), 1.0);
}

TEST(VertexWeldingTest, AGenuineCrackStaysOpen) {
  // The top quad lifted by 1e-6: its corners are at other positions than
  // the sides' top corners. The bottom corners (3 copies each: bottom and
  // two sides) and the sides' top corners (2 copies each) weld, 8 + 4
  // merges; the crack between the sides' top rim and the top quad stays:
  // 12 vertices, two boundary loops of 4 edges.
  SeamWeldReport report;
  auto welded = WeldSeams(SeamSplitCube(1e-6), &report);
  ASSERT_TRUE(welded.ok());
  EXPECT_EQ(report.merged_vertices, 12);
  EXPECT_EQ(welded->mesh.num_vertices(), 12);
  auto r = AnalyzeMeshTopology(welded->mesh);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->boundary_edges, 8);
  EXPECT_EQ(r->boundary_loops, 2);
  EXPECT_EQ(r->components, 2);
  EXPECT_EQ(r->non_manifold_edges, 0);
}

// WeldSeams leaves `mesh` as it is, reporting `declined` vertices left
// apart `because` (0 and "": nothing reported).
void ExpectLeftAsItIs(const TriangleMesh& mesh, int declined,
                      const std::string& because) {
  SeamWeldReport report;
  auto welded = WeldSeams(mesh, &report);
  ASSERT_TRUE(welded.ok());
  EXPECT_EQ(report.merged_vertices, 0);
  EXPECT_EQ(report.declined_vertices, declined);
  EXPECT_EQ(report.declined_because, because);
  EXPECT_EQ(welded->mesh.vertices, mesh.vertices);
  EXPECT_EQ(welded->mesh.faces, mesh.faces);
  std::vector<int> identity(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) identity[v] = v;
  EXPECT_EQ(welded->new_vertex, identity);
}

using V = Eigen::Vector3d;
using F = Eigen::Vector3i;

TEST(VertexWeldingTest, AMeshWithoutEqualPositionsComesBackBitForBit) {
  ExpectLeftAsItIs(
      testing::MakeMesh({V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), V(0, 0, 1)},
                        {F(0, 2, 1), F(0, 1, 3), F(0, 3, 2), F(1, 2, 3)}),
      0, "");
}

TEST(VertexWeldingTest, CopiesNoTriangleUsesAreLeftWithoutAWord) {
  // A tetrahedron and an unreferenced copy of its vertex 2.
  ExpectLeftAsItIs(
      testing::MakeMesh(
          {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), V(0, 0, 1), V(0, 1, 0)},
          {F(0, 2, 1), F(0, 1, 3), F(0, 3, 2), F(1, 2, 3)}),
      0, "");
}

TEST(VertexWeldingTest, AWeldThatMakesAnEdgeNonManifoldIsNotDone) {
  // Three fins on the segment (0,0,0)-(0,0,1), each triangle with its own
  // copies of the segment's ends: welding would give that edge three
  // triangles.
  const V bottom(0, 0, 0), top(0, 0, 1);
  ExpectLeftAsItIs(
      testing::MakeMesh({bottom, top, V(1, 0, 0.5), bottom, top, V(0, 1, 0.5),
                         bottom, top, V(-1, -1, 0.5)},
                        {F(0, 1, 2), F(3, 4, 5), F(6, 7, 8)}),
      4, "merging them would make 1 edge non-manifold");
}

TEST(VertexWeldingTest, AClosedMeshIsNeverWelded) {
  // Two tetrahedra, each closed, touching at the origin through two
  // vertices there: welding would close no boundary edge (and make the
  // origin a non-manifold vertex), so it is neither done nor reported.
  ExpectLeftAsItIs(
      testing::MakeMesh({V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), V(0, 0, 1),
                         V(0, 0, 0), V(-1, 0, 0), V(0, -1, 0), V(0, 0, -1)},
                        {F(0, 2, 1), F(0, 1, 3), F(0, 3, 2), F(1, 2, 3),
                         F(4, 6, 5), F(4, 5, 7), F(4, 7, 6), F(5, 6, 7)}),
      0, "");
}

TEST(VertexWeldingTest, AWeldThatPinchesAVertexIsNotDone) {
  // Two fins hinged on one segment, and a third fin whose corner touches
  // the first fin's tip: welding closes the hinge's boundary edge but
  // pinches the tip into a non-manifold vertex.
  const V bottom(0, 0, 0), top(0, 0, 1), tip(1, 0, 0.5);
  ExpectLeftAsItIs(
      testing::MakeMesh({bottom, top, tip, bottom, top, V(0, 1, 0.5), tip,
                         V(3, 0, 0), V(3, 0, 1)},
                        {F(0, 1, 2), F(4, 3, 5), F(6, 7, 8)}),
      3, "merging them would make 1 vertex non-manifold");
}

}  // namespace
}  // namespace sdcb
