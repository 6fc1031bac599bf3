#include "sdcb/core/mesh/mesh_hierarchy.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
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

// Brute force: before every collapse, all edges of the current mesh sorted
// by (length, lower index, higher index), and the first one whose collapse
// the rules allow (lower -> higher first) is taken; each rule recomputed
// from the current face list. On a mesh whose valences stay below
// max_removed_valence this is what the queue-based hierarchy must do.
std::vector<std::pair<int, int>> BruteForceCollapses(
    const TriangleMesh& mesh, const MeshHierarchyOptions& options) {
  std::vector<Triangle> faces;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    faces.push_back({mesh.faces(f, 0), mesh.faces(f, 1), mesh.faces(f, 2)});
  }
  std::vector<bool> alive(faces.size(), true);
  auto p = [&](int v) -> Eigen::Vector3d {
    return mesh.vertices.row(v).transpose();
  };
  // Neighbor sets of the current mesh, recomputed from the faces before
  // every collapse.
  std::vector<std::set<int>> adjacent;
  auto recompute_neighbors = [&] {
    adjacent.assign(mesh.num_vertices(), {});
    for (size_t f = 0; f < faces.size(); ++f) {
      if (!alive[f]) continue;
      for (int i = 0; i < 3; ++i) {
        adjacent[faces[f][i]].insert(faces[f][(i + 1) % 3]);
        adjacent[faces[f][(i + 1) % 3]].insert(faces[f][i]);
      }
    }
  };
  auto neighbors = [&](int v) { return adjacent[v]; };
  auto contains = [](const Triangle& t, int v) {
    return t[0] == v || t[1] == v || t[2] == v;
  };
  auto replaced = [&](Triangle t, int from, int to) {
    for (int& x : t) x = x == from ? to : x;
    return t;
  };
  auto normal = [&](const Triangle& t) {
    return Eigen::Vector3d((p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])));
  };
  auto quality = [&](const Triangle& t) {
    const double squares = (p(t[1]) - p(t[0])).squaredNorm() +
                           (p(t[2]) - p(t[1])).squaredNorm() +
                           (p(t[0]) - p(t[2])).squaredNorm();
    return squares == 0.0 ? 0.0
                          : 2.0 * std::sqrt(3.0) * normal(t).norm() / squares;
  };
  const double cos_turn =
      std::cos(options.max_normal_turn_degrees * kPi / 180.0);
  auto allowed = [&](int v, int u) {
    const std::set<int> nv = neighbors(v), nu = neighbors(u);
    if (static_cast<int>(nv.size()) > options.max_removed_valence) return false;
    int common = 0, edge_faces = 0;
    for (int w : nv) common += nu.count(w) > 0;
    for (size_t f = 0; f < faces.size(); ++f) {
      if (!alive[f] || !contains(faces[f], v)) continue;
      if (contains(faces[f], u)) {
        ++edge_faces;
        continue;
      }
      const Eigen::Vector3d before = normal(faces[f]);
      const Eigen::Vector3d after = normal(replaced(faces[f], v, u));
      const double nb = before.norm(), na = after.norm();
      if (!(na > 1e-14 * nb) || before.dot(after) < cos_turn * nb * na) {
        return false;
      }
      if (quality(replaced(faces[f], v, u)) <
          std::min(options.min_triangle_quality, quality(faces[f]))) {
        return false;
      }
    }
    return common == 2 && edge_faces == 2;
  };
  std::vector<std::pair<int, int>> result;
  int alive_vertices = mesh.num_vertices();
  while (alive_vertices > options.base_vertices) {
    recompute_neighbors();
    std::vector<std::tuple<double, int, int>> edges;
    for (int a = 0; a < mesh.num_vertices(); ++a) {
      for (int b : neighbors(a)) {
        if (a >= b) continue;
        const Eigen::Vector3d d = p(a) - p(b);
        edges.emplace_back(
            std::sqrt(d.x() * d.x() + (d.y() * d.y() + d.z() * d.z())), a, b);
      }
    }
    std::sort(edges.begin(), edges.end());
    bool done = false;
    for (const auto& [length, a, b] : edges) {
      for (const auto& [v, u] : {std::pair(a, b), std::pair(b, a)}) {
        if (!allowed(v, u)) continue;
        for (size_t f = 0; f < faces.size(); ++f) {
          if (!alive[f] || !contains(faces[f], v)) continue;
          if (contains(faces[f], u)) {
            alive[f] = false;
          } else {
            faces[f] = replaced(faces[f], v, u);
          }
        }
        result.emplace_back(v, u);
        --alive_vertices;
        done = true;
        break;
      }
      if (done) break;
    }
    if (!done) break;
  }
  return result;
}

TEST(MeshHierarchy, ShortestAllowedCollapseFirstAsBruteForce) {
  for (const char* name : {"sphere966.off", "cube-meshed.off", "oblong.off"}) {
    const TriangleMesh mesh = testing::LoadOffTestMesh(name);
    MeshHierarchyOptions options;
    options.base_vertices = 40;
    auto h = BuildMeshHierarchy(mesh, options);
    ASSERT_TRUE(h.ok());
    const std::vector<std::pair<int, int>> expected =
        BruteForceCollapses(mesh, options);
    ASSERT_EQ(h->collapses.size(), expected.size()) << name;
    for (size_t i = 0; i < expected.size(); ++i) {
      ASSERT_EQ(h->collapses[i].removed, expected[i].first) << name << " " << i;
      ASSERT_EQ(h->collapses[i].kept, expected[i].second) << name << " " << i;
    }
  }
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
