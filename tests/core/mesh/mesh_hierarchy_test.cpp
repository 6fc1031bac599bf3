#include "sdcb/core/mesh/mesh_hierarchy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>

#include "sdcb/core/mesh/mesh_topology.h"
#include "testing/fan_mesh.h"
#include "testing/off_test_mesh.h"

namespace sdcb {
namespace {

using Triangle = std::array<int, 3>;

// Rotation-invariant key of an oriented triangle.
Triangle Canonical(Triangle t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

TriangleMesh AliveMesh(const TriangleMesh& input, const Eigen::MatrixX3i& faces,
                       const std::vector<bool>& face_alive) {
  TriangleMesh m;
  m.vertices = input.vertices;
  std::vector<int> alive;
  for (int f = 0; f < faces.rows(); ++f) {
    if (face_alive[f]) alive.push_back(f);
  }
  m.faces.resize(alive.size(), 3);
  for (size_t i = 0; i < alive.size(); ++i)
    m.faces.row(i) = faces.row(alive[i]);
  return m;
}

TEST(MeshHierarchy, CollapsesAreManifoldAndUndoExactly) {
  const TriangleMesh mesh_value = testing::LoadOffTestMesh("cow.off");
  const TriangleMesh* mesh = &mesh_value;
  MeshHierarchyOptions options;
  options.base_vertices = 50;
  auto h = BuildMeshHierarchy(*mesh, options);
  ASSERT_TRUE(h.ok());
  const int base = mesh->num_vertices() - static_cast<int>(h->collapses.size());
  EXPECT_LE(base, 100);  // the guards may stop it a little early
  EXPECT_GE(base, 50);
  int alive_vertices = 0;
  for (bool a : h->vertex_alive) alive_vertices += a;
  EXPECT_EQ(alive_vertices, base);

  Eigen::MatrixX3i faces = h->faces;
  std::vector<bool> face_alive = h->face_alive, vertex_alive = h->vertex_alive;
  // The base mesh is itself a closed genus-0 manifold (independent check by
  // the topology analysis; the unreferenced removed vertices are dropped).
  {
    TriangleMesh base_mesh = AliveMesh(*mesh, faces, face_alive);
    auto report = AnalyzeMeshTopology(base_mesh);
    ASSERT_TRUE(report.ok());
    EXPECT_EQ(report->genus, 0);
    EXPECT_EQ(report->boundary_edges, 0);
    EXPECT_EQ(report->non_manifold_edges, 0);
    EXPECT_EQ(report->inconsistently_oriented_edges, 0);
    EXPECT_EQ(report->unreferenced_vertices, mesh->num_vertices() - base);
    EXPECT_EQ(report->euler_characteristic, 2);
  }
  for (size_t j = h->collapses.size(); j-- > 0;) {
    const HalfEdgeCollapse& c = h->collapses[j];
    // Before the split, the removed vertex's link is fanned from `kept`.
    std::set<Triangle> current;
    for (int f = 0; f < faces.rows(); ++f) {
      if (face_alive[f])
        current.insert(Canonical({faces(f, 0), faces(f, 1), faces(f, 2)}));
    }
    for (size_t i = 1; i + 1 < c.link.size(); ++i) {
      ASSERT_TRUE(current.count(Canonical({c.kept, c.link[i], c.link[i + 1]})))
          << "collapse " << j;
    }
    EXPECT_FALSE(vertex_alive[c.removed]);
    UndoCollapse(c, &faces, &face_alive, &vertex_alive);
  }
  // All splits undone: exactly the input faces, in the input order.
  EXPECT_EQ(faces, mesh->faces);
  EXPECT_TRUE(std::all_of(face_alive.begin(), face_alive.end(),
                          [](bool a) { return a; }));
  EXPECT_TRUE(std::all_of(vertex_alive.begin(), vertex_alive.end(),
                          [](bool a) { return a; }));
}

TEST(MeshHierarchy, FanHubsStayAndRemovedVerticesHaveBoundedValence) {
  const TriangleMesh mesh = testing::DoubleCone(3000);
  ASSERT_TRUE(RequireClosedGenusZero(mesh).ok());
  MeshHierarchyOptions options;
  auto h = BuildMeshHierarchy(mesh, options);
  ASSERT_TRUE(h.ok());
  // The ring collapses down to the base size; the hubs (valence 3000 >
  // max_removed_valence) stay.
  const int base = mesh.num_vertices() - static_cast<int>(h->collapses.size());
  EXPECT_LE(base, options.base_vertices + 10);
  EXPECT_TRUE(h->vertex_alive[0]);
  EXPECT_TRUE(h->vertex_alive[1]);
  for (const HalfEdgeCollapse& c : h->collapses) {
    ASSERT_LE(static_cast<int>(c.link.size()), options.max_removed_valence);
  }
  TriangleMesh base_mesh = AliveMesh(mesh, h->faces, h->face_alive);
  auto report = AnalyzeMeshTopology(base_mesh);
  ASSERT_TRUE(report.ok());
  EXPECT_EQ(report->euler_characteristic, 2);
  EXPECT_EQ(report->boundary_edges, 0);
  EXPECT_EQ(report->non_manifold_edges, 0);
  EXPECT_EQ(report->inconsistently_oriented_edges, 0);
  // Undoing every collapse gives the input back.
  Eigen::MatrixX3i faces = h->faces;
  std::vector<bool> face_alive = h->face_alive, vertex_alive = h->vertex_alive;
  for (size_t j = h->collapses.size(); j-- > 0;) {
    UndoCollapse(h->collapses[j], &faces, &face_alive, &vertex_alive);
  }
  EXPECT_EQ(faces, mesh.faces);
}

TEST(MeshHierarchy, RejectsTooSmallBase) {
  const TriangleMesh mesh = testing::LoadOffTestMesh("sphere966.off");
  MeshHierarchyOptions options;
  options.base_vertices = 3;
  EXPECT_EQ(BuildMeshHierarchy(mesh, options).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
