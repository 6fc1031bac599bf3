// Tests core/mesh_topology.* on small meshes whose topology is known by
// construction (Euler's formula chi = 2 - 2g - b per component).
#include "sdcb/core/mesh/mesh_topology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "testing/fan_mesh.h"

namespace sdcb {
namespace {

TriangleMesh Tetrahedron() { return testing::RegularTetrahedron(); }

// An (nu x nv) grid on a torus, triangulated, consistently oriented.
TriangleMesh Torus(int nu, int nv) {
  TriangleMesh m;
  m.vertices.resize(nu * nv, 3);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      m.vertices.row(i * nv + j) << (2 + std::cos(v)) * std::cos(u),
          (2 + std::cos(v)) * std::sin(u), std::sin(v);
    }
  }
  m.faces.resize(2 * nu * nv, 3);
  int f = 0;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j,
                c = ((i + 1) % nu) * nv + (j + 1) % nv,
                d = i * nv + (j + 1) % nv;
      m.faces.row(f++) << a, b, c;
      m.faces.row(f++) << a, c, d;
    }
  }
  return m;
}

// Disjoint union of two meshes.
TriangleMesh Union(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m;
  m.vertices.resize(a.num_vertices() + b.num_vertices(), 3);
  m.vertices << a.vertices, b.vertices;
  m.faces.resize(a.num_faces() + b.num_faces(), 3);
  m.faces << a.faces, (b.faces.array() + a.num_vertices()).matrix();
  return m;
}

MeshTopologyReport Analyze(const TriangleMesh& m) {
  auto r = AnalyzeMeshTopology(m);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return *r;
}

TEST(MeshTopologyTest, TetrahedronIsClosedGenusZero) {
  const MeshTopologyReport r = Analyze(Tetrahedron());
  EXPECT_EQ(r.vertices, 4);
  EXPECT_EQ(r.edges, 6);
  EXPECT_EQ(r.faces, 4);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.components, 1);
  EXPECT_TRUE(r.ok);
  EXPECT_TRUE(RequireClosedGenusZero(Tetrahedron()).ok());
  EXPECT_EQ(DescribeTopologyProblem(r), "");
}

TEST(MeshTopologyTest, TorusHasGenusOneAtEveryResolution) {
  for (int n : {3, 5, 12}) {
    const MeshTopologyReport r = Analyze(Torus(n, n + 1));
    EXPECT_EQ(r.edges, 3 * n * (n + 1));
    EXPECT_EQ(r.euler_characteristic, 0);
    EXPECT_EQ(r.genus, 1);
    EXPECT_EQ(r.boundary_edges, 0);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(DescribeTopologyProblem(r).find("genus 1"), std::string::npos);
  }
  const Status s = RequireClosedGenusZero(Torus(4, 4));
  EXPECT_EQ(s.code(), StatusCode::kUnsupported);
}

TEST(MeshTopologyTest, TwoToriAddTheirGenus) {
  const MeshTopologyReport r = Analyze(Union(Torus(4, 5), Torus(6, 3)));
  EXPECT_EQ(r.components, 2);
  EXPECT_EQ(r.genus, 2);
  EXPECT_FALSE(r.ok);
}

TEST(MeshTopologyTest, RemovedFaceLeavesOneBoundaryLoop) {
  TriangleMesh m = Tetrahedron();
  m.faces.conservativeResize(3, 3);
  const MeshTopologyReport r = Analyze(m);
  EXPECT_EQ(r.boundary_edges, 3);
  EXPECT_EQ(r.boundary_loops, 1);
  EXPECT_EQ(r.genus, 0);  // a disk
  EXPECT_FALSE(r.ok);
  EXPECT_NE(DescribeTopologyProblem(r).find("3 boundary edges"),
            std::string::npos);
}

TEST(MeshTopologyTest, OpenTorusStripHasTwoBoundaryLoops) {
  // Drop one ring of faces from the torus: a cylinder (genus 0, b = 2).
  TriangleMesh torus = Torus(6, 5);
  TriangleMesh m = torus;
  m.faces.resize(torus.num_faces() - 2 * 5, 3);
  m.faces = torus.faces.topRows(torus.num_faces() - 2 * 5);
  const MeshTopologyReport r = Analyze(m);
  EXPECT_EQ(r.boundary_loops, 2);
  EXPECT_EQ(r.boundary_edges, 10);
  EXPECT_EQ(r.genus, 0);
}

TEST(MeshTopologyTest, BoundaryEdgesAreTheHalfEdgesNoOtherFaceShares) {
  // The torus strip's 10 boundary edges against brute force: a half-edge
  // (a, b) of a face is on the boundary when no face uses a-b either way.
  TriangleMesh torus = Torus(6, 5);
  TriangleMesh m = torus;
  m.faces = torus.faces.topRows(torus.num_faces() - 2 * 5);
  StatusOr<Eigen::MatrixX2i> edges = BoundaryEdges(m);
  ASSERT_TRUE(edges.ok());
  std::vector<std::pair<int, int>> expected;
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = m.faces(f, k), b = m.faces(f, (k + 1) % 3);
      int uses = 0;
      for (int g = 0; g < m.num_faces(); ++g) {
        for (int j = 0; j < 3; ++j) {
          const int c = m.faces(g, j), d = m.faces(g, (j + 1) % 3);
          uses += (c == a && d == b) || (c == b && d == a);
        }
      }
      if (uses == 1) expected.emplace_back(a, b);
    }
  }
  std::sort(expected.begin(), expected.end(), [](auto x, auto y) {
    return std::minmax(x.first, x.second) < std::minmax(y.first, y.second);
  });
  ASSERT_EQ(edges->rows(), 10);
  ASSERT_EQ(expected.size(), 10u);
  for (Eigen::Index e = 0; e < edges->rows(); ++e) {
    EXPECT_EQ((*edges)(e, 0), expected[e].first);
    EXPECT_EQ((*edges)(e, 1), expected[e].second);
  }
  EXPECT_EQ(BoundaryEdges(Tetrahedron())->rows(), 0);
  m.faces(0, 0) = -1;
  EXPECT_EQ(BoundaryEdges(m).status().code(), StatusCode::kInvalidInput);
}

TEST(MeshTopologyTest, TwoComponentsAreRefused) {
  const MeshTopologyReport r = Analyze(Union(Tetrahedron(), Tetrahedron()));
  EXPECT_EQ(r.components, 2);
  EXPECT_EQ(r.euler_characteristic, 4);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.duplicate_vertices, 4);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(DescribeTopologyProblem(r).find("2 connected components"),
            std::string::npos);
}

TEST(MeshTopologyTest, ThreeTrianglesOnOneEdgeAreNonManifold) {
  TriangleMesh m = Tetrahedron();
  m.vertices.conservativeResize(5, 3);
  m.vertices.row(4) << 3, 3, 3;
  m.faces.conservativeResize(5, 3);
  m.faces.row(4) << 0, 1, 4;
  const MeshTopologyReport r = Analyze(m);
  EXPECT_EQ(r.non_manifold_edges, 1);
  EXPECT_FALSE(r.ok);
}

TEST(MeshTopologyTest, BowtieVertexIsNonManifold) {
  // Two tetrahedra sharing exactly one vertex.
  TriangleMesh a = Tetrahedron();
  TriangleMesh m = Union(a, a);
  m.vertices.bottomRows(4).rowwise() += Eigen::RowVector3d(2, 2, 2);
  // Glue vertex 4 (first of the second copy) onto vertex 0.
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (m.faces(f, k) == 4) m.faces(f, k) = 0;
    }
  }
  const MeshTopologyReport r = Analyze(m);
  EXPECT_EQ(r.non_manifold_vertices, 1);
  EXPECT_EQ(r.non_manifold_edges, 0);
  EXPECT_EQ(r.unreferenced_vertices, 1);
  EXPECT_EQ(r.components, 1);
  EXPECT_FALSE(r.ok);
}

TEST(MeshTopologyTest, FlippedFaceIsInconsistent) {
  TriangleMesh m = Tetrahedron();
  std::swap(m.faces(2, 1), m.faces(2, 2));
  const MeshTopologyReport r = Analyze(m);
  EXPECT_EQ(r.inconsistently_oriented_edges, 3);
  EXPECT_FALSE(r.ok);
}

TEST(MeshTopologyTest, CollinearAndRepeatedCornersAreDegenerate) {
  // Octahedron-like closed mesh where one vertex sits exactly at an edge
  // midpoint of the base: its two triangles using that edge line become
  // collinear. Simpler: a tetrahedron whose apex lies on a base edge line.
  TriangleMesh m = Tetrahedron();
  m.vertices.row(3) = 0.5 * (m.vertices.row(0) + m.vertices.row(1));
  const MeshTopologyReport r = Analyze(m);
  // Face (0,3,1) has three collinear corners.
  EXPECT_EQ(r.degenerate_faces, 1);
  EXPECT_FALSE(r.ok);

  TriangleMesh rep = Tetrahedron();
  rep.faces.row(0) << 0, 0, 2;
  EXPECT_GE(Analyze(rep).degenerate_faces, 1);
}

TEST(MeshTopologyTest, NearlyCollinearIsNotDegenerate) {
  // The exact predicate does not confuse tiny with zero.
  TriangleMesh m = Tetrahedron();
  m.vertices.row(3) = 0.5 * (m.vertices.row(0) + m.vertices.row(1));
  m.vertices(3, 2) += 1e-300;
  EXPECT_EQ(Analyze(m).degenerate_faces, 0);
}

TEST(MeshTopologyTest, UnreferencedVertexIsReported) {
  TriangleMesh m = Tetrahedron();
  m.vertices.conservativeResize(5, 3);
  m.vertices.row(4) << 9, 9, 9;
  const MeshTopologyReport r = Analyze(m);
  EXPECT_EQ(r.unreferenced_vertices, 1);
  EXPECT_EQ(r.genus, 0);
  EXPECT_FALSE(r.ok);
}

TEST(MeshTopologyTest, OutOfRangeIndexIsAnError) {
  TriangleMesh m = Tetrahedron();
  m.faces(1, 2) = 7;
  auto r = AnalyzeMeshTopology(m);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidInput);
  m.faces(1, 2) = -1;
  EXPECT_FALSE(AnalyzeMeshTopology(m).ok());
}

TEST(MeshTopologyTest, EmptyMeshIsNotOk) {
  TriangleMesh m;
  const MeshTopologyReport r = Analyze(m);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(DescribeTopologyProblem(r).find("no faces"), std::string::npos);
}

}  // namespace
}  // namespace sdcb
