// Tests core/mesh/cgal_mesh.*'s hole filler on a cone over a planar
// 12-gon: each method forced by the options, the result checked by
// AnalyzeMeshTopology and by counts (an n-gon takes n - 2 triangles, a fan
// n).
#include "sdcb/core/mesh/cgal_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/mesh_topology.h"

namespace sdcb {
namespace {

// A cone: apex (0, 0, 0.5) over a regular 12-gon in z = 0, open at the rim.
TriangleMesh Cone() {
  const int n = 12;
  TriangleMesh cone;
  cone.vertices.resize(n + 1, 3);
  cone.vertices.row(0) << 0, 0, 0.5;
  cone.faces.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double phi = 2 * kPi * i / n;
    cone.vertices.row(1 + i) << std::cos(phi), std::sin(phi), 0;
    cone.faces.row(i) << 0, 1 + i, 1 + (i + 1) % n;
  }
  return cone;
}

// Fills the cone's one hole with `options`; the method used, and the mesh
// must come out closed genus 0 with `faces` faces.
HoleFillMethod FillCone(const CgalHoleFillOptions& options, int faces) {
  CgalMesh mesh;
  EXPECT_TRUE(ToCgalMesh(Cone(), &mesh));
  CgalMesh::Halfedge_index border;
  for (CgalMesh::Halfedge_index h : mesh.halfedges()) {
    if (mesh.is_border(h)) border = h;
  }
  int added_faces = 0, added_vertices = 0;
  const std::optional<HoleFillMethod> method =
      FillCgalHole(border, options, &mesh, &added_faces, &added_vertices);
  EXPECT_TRUE(method.has_value());
  const TriangleMesh filled = FromCgalMesh(mesh);
  EXPECT_EQ(filled.num_faces(), faces);
  EXPECT_EQ(added_faces, faces - 12);
  EXPECT_EQ(added_vertices, filled.num_vertices() - 13);
  const StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(filled);
  EXPECT_TRUE(topology.ok() && topology->ok)
      << DescribeTopologyProblem(*topology);
  return method.value_or(HoleFillMethod::kFan);
}

TEST(FillCgalHoleTest, PlanarRimByTwoDimensionalDelaunay) {
  CgalHoleFillOptions options;
  options.use_2d_delaunay = true;
  options.refine = false;
  // A 12-gon takes 10 triangles.
  EXPECT_EQ(FillCone(options, 12 + 10), HoleFillMethod::kTriangulated);
}

TEST(FillCgalHoleTest, FanWhenCgalDoesNotTriangulate) {
  CgalHoleFillOptions options;
  options.cgal_triangulation = false;
  options.fan_fallback = true;
  options.refine = false;
  EXPECT_EQ(FillCone(options, 12 + 12), HoleFillMethod::kFan);
}

TEST(FillCgalHoleTest, NothingWithoutAFallbackLeavesTheMeshAlone) {
  CgalMesh mesh;
  ASSERT_TRUE(ToCgalMesh(Cone(), &mesh));
  CgalMesh::Halfedge_index border;
  for (CgalMesh::Halfedge_index h : mesh.halfedges()) {
    if (mesh.is_border(h)) border = h;
  }
  CgalHoleFillOptions options;
  options.cgal_triangulation = false;
  EXPECT_FALSE(FillCgalHole(border, options, &mesh, nullptr, nullptr));
  EXPECT_EQ(mesh.number_of_faces(), 12u);
  EXPECT_EQ(mesh.number_of_vertices(), 13u);
}

TEST(FillCgalHoleTest, RefinedAndFairedPatchStaysClosed) {
  CgalHoleFillOptions options;
  options.use_2d_delaunay = true;
  options.max_fair_vertices = 1000;
  CgalMesh mesh;
  ASSERT_TRUE(ToCgalMesh(Cone(), &mesh));
  CgalMesh::Halfedge_index border;
  for (CgalMesh::Halfedge_index h : mesh.halfedges()) {
    if (mesh.is_border(h)) border = h;
  }
  int added_faces = 0, added_vertices = 0;
  const std::optional<HoleFillMethod> method =
      FillCgalHole(border, options, &mesh, &added_faces, &added_vertices);
  ASSERT_TRUE(method.has_value());
  // The rim's edges (0.52) are shorter than the 12-gon's span: refine adds
  // vertices, so the patch is faired.
  EXPECT_GT(added_vertices, 0);
  EXPECT_EQ(*method, HoleFillMethod::kFaired);
  const StatusOr<MeshTopologyReport> topology =
      AnalyzeMeshTopology(FromCgalMesh(mesh));
  EXPECT_TRUE(topology.ok() && topology->ok);
}

}  // namespace
}  // namespace sdcb
