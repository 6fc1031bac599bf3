// Tests core/mesh/mesh_repair.*: damage of known extent is done to meshes
// whose topology is known, and the repair must undo it (closed genus 0,
// the expected counts in the report) or refuse what it cannot undo.
#include "sdcb/core/mesh/mesh_repair.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_topology.h"

namespace sdcb {
namespace {

// Every triangle with its own three vertices (what STL stores).
TriangleMesh Soup(const TriangleMesh& m) {
  TriangleMesh s;
  s.vertices.resize(3 * m.num_faces(), 3);
  s.faces.resize(m.num_faces(), 3);
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      s.vertices.row(3 * f + k) = m.vertices.row(m.faces(f, k));
      s.faces(f, k) = 3 * f + k;
    }
  }
  return s;
}

TriangleMesh WithoutFaces(const TriangleMesh& m, const std::vector<int>& drop) {
  TriangleMesh out;
  out.vertices = m.vertices;
  out.faces.resize(m.num_faces() - static_cast<int>(drop.size()), 3);
  int row = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    if (std::find(drop.begin(), drop.end(), f) == drop.end())
      out.faces.row(row++) = m.faces.row(f);
  }
  return out;
}

double SignedVolume(const TriangleMesh& m) {
  double v = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.vertices.row(m.faces(f, 0));
    const Eigen::Vector3d b = m.vertices.row(m.faces(f, 1));
    const Eigen::Vector3d c = m.vertices.row(m.faces(f, 2));
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}

TEST(MeshRepair, CleanMeshIsUnchanged) {
  const TriangleMesh sphere = MakeIcosphere(2);
  MeshRepairReport report;
  auto repaired = RepairMesh(sphere, {}, &report);
  ASSERT_TRUE(repaired.ok()) << repaired.status().message();
  EXPECT_FALSE(report.changed()) << report.Describe();
  EXPECT_EQ(report.Describe(), "nothing to repair");
  EXPECT_EQ(repaired->num_vertices(), sphere.num_vertices());
  EXPECT_EQ(repaired->num_faces(), sphere.num_faces());
}

TEST(MeshRepair, SoupWithHolesDuplicatesAndFlipsBecomesTheSphere) {
  const TriangleMesh sphere = MakeIcosphere(2);  // 162 vertices, 320 faces
  // Two holes far apart (single triangles), one flipped face, one repeated
  // face, one face using a vertex twice, then every vertex duplicated per
  // triangle.
  TriangleMesh damaged = WithoutFaces(sphere, {0, 200});
  damaged.faces.row(5) = damaged.faces.row(5).reverse().eval();
  const int n = damaged.num_faces();
  damaged.faces.conservativeResize(n + 2, 3);
  damaged.faces.row(n) = damaged.faces.row(7);
  damaged.faces.row(n + 1) << damaged.faces(9, 0), damaged.faces(9, 0),
      damaged.faces(9, 1);
  damaged = Soup(damaged);
  ASSERT_FALSE(RequireClosedGenusZero(damaged).ok());

  MeshRepairReport report;
  auto repaired = RepairMesh(damaged, {}, &report);
  ASSERT_TRUE(repaired.ok()) << repaired.status().message();
  EXPECT_TRUE(RequireClosedGenusZero(*repaired).ok());
  // 3 x 320 soup vertices become the sphere's 162 (a vertex only the
  // degenerate face used still counts as merged, then unreferenced: none
  // here, its two positions are sphere vertices).
  EXPECT_EQ(report.merged_vertices, 3 * 320 - 162);
  EXPECT_EQ(report.dropped_duplicate_faces, 1);
  EXPECT_EQ(report.dropped_degenerate_faces, 1);
  EXPECT_EQ(report.filled_holes, 2);
  EXPECT_GE(report.added_faces, 2);
  EXPECT_EQ(repaired->num_faces(), 320 - 2 + report.added_faces);
  EXPECT_EQ(repaired->num_vertices(), 162 + report.added_vertices);
  EXPECT_GE(report.reoriented_faces, 1);
  EXPECT_GT(SignedVolume(*repaired), 0) << "outward";
  EXPECT_NE(report.Describe().find("merged 798 duplicate vertices"),
            std::string::npos)
      << report.Describe();
  EXPECT_NE(report.Describe().find("filled 2 holes"), std::string::npos)
      << report.Describe();
}

TEST(MeshRepair, InsideOutMeshIsTurnedOutward) {
  TriangleMesh sphere = MakeIcosphere(1);
  for (int f = 0; f < sphere.num_faces(); ++f) {
    std::swap(sphere.faces(f, 1), sphere.faces(f, 2));
  }
  ASSERT_LT(SignedVolume(sphere), 0);
  MeshRepairReport report;
  auto repaired = RepairMesh(sphere, {}, &report);
  ASSERT_TRUE(repaired.ok());
  EXPECT_GT(SignedVolume(*repaired), 0);
  EXPECT_EQ(report.reoriented_faces, sphere.num_faces());
}

TEST(MeshRepair, RefusesWhatCannotBecomeGenusZero) {
  // A torus stays genus 1.
  const int nu = 12, nv = 8;
  TriangleMesh torus;
  torus.vertices.resize(nu * nv, 3);
  torus.faces.resize(2 * nu * nv, 3);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      torus.vertices.row(i * nv + j) << (2 + std::cos(v)) * std::cos(u),
          (2 + std::cos(v)) * std::sin(u), std::sin(v);
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j,
                c = ((i + 1) % nu) * nv + (j + 1) % nv,
                d = i * nv + (j + 1) % nv;
      torus.faces.row(2 * (i * nv + j)) << a, b, c;
      torus.faces.row(2 * (i * nv + j) + 1) << a, c, d;
    }
  }
  auto t = RepairMesh(torus, {}, nullptr);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(t.status().message().find("genus 1"), std::string::npos)
      << t.status().message();

  // Half a sphere: its hole is far too large to fill.
  const TriangleMesh sphere = MakeIcosphere(2);
  std::vector<int> south;
  for (int f = 0; f < sphere.num_faces(); ++f) {
    if (sphere.vertices(sphere.faces(f, 0), 2) < -0.1) south.push_back(f);
  }
  auto h = RepairMesh(WithoutFaces(sphere, south), {}, nullptr);
  ASSERT_FALSE(h.ok());
  EXPECT_NE(h.status().message().find("open surface"), std::string::npos)
      << h.status().message();
  EXPECT_NE(h.status().message().find("stay open"), std::string::npos);
  EXPECT_EQ(h.status().message().find('\n'), std::string::npos);
}

}  // namespace
}  // namespace sdcb
