// Tests core/mesh/mesh_parts.* on meshes whose parts and topology are known
// by construction: counts from Euler's formula chi = V - E + F = 2 - 2g - b,
// areas from right triangles, the problem sentences as docs/CLI.md gives
// them.
#include "sdcb/core/mesh/mesh_parts.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/param/parameterization_distortion.h"
#include "sdcb/core/spline/spline_model.h"
#include "testing/make_mesh.h"

namespace sdcb {
namespace {

using testing::MakeMesh;

// The corner tetrahedron (0,0,0), e_x, e_y, e_z scaled by `s` and shifted
// by `offset`, oriented outward: area s^2 (3/2 + sqrt(3)/2).
TriangleMesh CornerTetrahedron(double s = 1.0,
                               const Eigen::Vector3d& offset = {0, 0, 0}) {
  return MakeMesh(
      {offset, offset + Eigen::Vector3d(s, 0, 0),
       offset + Eigen::Vector3d(0, s, 0), offset + Eigen::Vector3d(0, 0, s)},
      {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}});
}

// An (nu x nv) grid on a torus, triangulated, consistently oriented:
// V = nu nv, E = 3 nu nv, F = 2 nu nv, chi = 0, genus 1.
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

std::vector<MeshPart> Split(const TriangleMesh& mesh, int max_parts = 0) {
  StatusOr<std::vector<MeshPart>> parts = SplitIntoParts(mesh, max_parts);
  EXPECT_TRUE(parts.ok()) << parts.status().message();
  return parts.ok() ? std::move(parts).value() : std::vector<MeshPart>();
}

PartReport Report(const MeshPart& part, int number) {
  StatusOr<PartReport> report = ReportPart(part, number);
  EXPECT_TRUE(report.ok()) << report.status().message();
  return report.ok() ? *report : PartReport();
}

// The single part of `mesh`.
PartReport ReportWhole(const TriangleMesh& mesh, int number = 1) {
  const std::vector<MeshPart> parts = Split(mesh);
  EXPECT_EQ(parts.size(), 1u);
  return parts.empty() ? PartReport() : Report(parts[0], number);
}

// Two triangles back to back on three vertices are closed, manifold and
// genus 0 by the counts (V - E + F = 3 - 3 + 2), but no sphere map embeds
// them: refused with a sentence that says so, not the parameterization's.
TEST(MeshPartsTest, TwoTrianglesBackToBackAreRefused) {
  const PartReport report = ReportWhole(
      testing::MakeMesh({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                         Eigen::Vector3d(0, 1, 0)},
                        {Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(0, 2, 1)}));
  EXPECT_TRUE(report.closed);
  EXPECT_FALSE(report.fittable());
  EXPECT_EQ(report.problem,
            "part 1 (2 triangles) is two triangles back to back (a closed "
            "surface of 3 vertices, no volume); sdcb fits closed parts of at "
            "least 4 vertices");
}

TEST(MeshPartsTest, TwoTetrahedraAroundAnUnreferencedVertex) {
  // Rows 0-3: tetrahedron A; row 4: used by no triangle; rows 5-8:
  // tetrahedron B. B's face comes first, so B is part 1.
  const TriangleMesh a = CornerTetrahedron(1.0);
  const TriangleMesh b = CornerTetrahedron(2.0, {5, 0, 0});
  TriangleMesh mesh;
  mesh.vertices.resize(9, 3);
  mesh.vertices.topRows(4) = a.vertices;
  mesh.vertices.row(4) << 3, 3, 3;
  mesh.vertices.bottomRows(4) = b.vertices;
  mesh.faces.resize(8, 3);
  mesh.faces << 5, 6, 8,  // B's (0, 1, 3)
      0, 2, 1,            // A
      0, 1, 3,            // A
      6, 7, 8,            // B's (1, 2, 3)
      5, 8, 7,            // B's (0, 3, 2)
      1, 2, 3,            // A
      5, 7, 6,            // B's (0, 2, 1)
      0, 3, 2;            // A

  const std::vector<MeshPart> parts = Split(mesh, 2);
  ASSERT_EQ(parts.size(), 2u);
  // Part 1 is B: its vertices in input order, its faces in input order.
  EXPECT_EQ(parts[0].input_vertices, (std::vector<int>{5, 6, 7, 8}));
  EXPECT_EQ(parts[0].input_faces, (std::vector<int>{0, 3, 4, 6}));
  EXPECT_EQ(parts[0].mesh.vertices, b.vertices);
  Eigen::MatrixX3i b_faces(4, 3);
  b_faces << 0, 1, 3, 1, 2, 3, 0, 3, 2, 0, 2, 1;
  EXPECT_EQ(parts[0].mesh.faces, b_faces);
  EXPECT_EQ(parts[1].input_vertices, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(parts[1].input_faces, (std::vector<int>{1, 2, 5, 7}));
  EXPECT_EQ(parts[1].mesh.vertices, a.vertices);
  EXPECT_EQ(parts[1].mesh.faces, a.faces);

  const double unit_area = 1.5 + std::sqrt(3.0) / 2;
  for (int p = 0; p < 2; ++p) {
    const PartReport r = Report(parts[p], p + 1);
    EXPECT_EQ(r.number, p + 1);
    EXPECT_TRUE(r.fittable()) << r.problem;
    EXPECT_TRUE(r.closed);
    EXPECT_EQ(r.topology.vertices, 4);
    EXPECT_EQ(r.topology.faces, 4);
    EXPECT_EQ(r.topology.edges, 6);
    EXPECT_EQ(r.topology.components, 1);
    EXPECT_EQ(r.topology.genus, 0);
    EXPECT_EQ(r.topology.unreferenced_vertices, 0);
    EXPECT_NEAR(r.area, (p == 0 ? 4.0 : 1.0) * unit_area, 1e-12);
  }
}

TEST(MeshPartsTest, ASingleMeshComesBackBitForBit) {
  const TriangleMesh torus = Torus(7, 5);  // irrational coordinates
  const std::vector<MeshPart> parts = Split(torus, 1);
  ASSERT_EQ(parts.size(), 1u);
  const TriangleMesh& m = parts[0].mesh;
  ASSERT_EQ(m.vertices.rows(), torus.vertices.rows());
  ASSERT_EQ(m.faces.rows(), torus.faces.rows());
  EXPECT_EQ(std::memcmp(m.vertices.data(), torus.vertices.data(),
                        sizeof(double) * torus.vertices.size()),
            0);
  EXPECT_EQ(std::memcmp(m.faces.data(), torus.faces.data(),
                        sizeof(int) * torus.faces.size()),
            0);
  for (int v = 0; v < torus.num_vertices(); ++v) {
    EXPECT_EQ(parts[0].input_vertices[v], v);
  }
  for (int f = 0; f < torus.num_faces(); ++f) {
    EXPECT_EQ(parts[0].input_faces[f], f);
  }
}

TEST(MeshPartsTest, ADiskIsOpenGenusZeroAndFittable) {
  // A square fanned around its centre: V 5, E 8, F 4, chi 1, one loop.
  const TriangleMesh disk =
      MakeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}},
               {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}});
  const PartReport r = ReportWhole(disk);
  EXPECT_TRUE(r.fittable()) << r.problem;
  EXPECT_FALSE(r.closed);
  EXPECT_EQ(r.topology.boundary_loops, 1);
  EXPECT_EQ(r.topology.boundary_edges, 4);
  EXPECT_EQ(r.topology.euler_characteristic, 1);
  EXPECT_EQ(r.topology.genus, 0);
  EXPECT_DOUBLE_EQ(r.area, 2.0);  // four right triangles of legs 1
}

TEST(MeshPartsTest, ATubeHasTwoLoopsAndIsFittable) {
  // n quads around, two rings: V 2n, E 4n, F 2n, chi 0, two loops, genus 0.
  const int n = 6;
  TriangleMesh tube;
  tube.vertices.resize(2 * n, 3);
  tube.faces.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2 * kPi * i / n;
    tube.vertices.row(i) << std::cos(t), std::sin(t), 0;
    tube.vertices.row(n + i) << std::cos(t), std::sin(t), 1;
    const int j = (i + 1) % n;
    tube.faces.row(2 * i) << i, j, n + j;
    tube.faces.row(2 * i + 1) << i, n + j, n + i;
  }
  const PartReport r = ReportWhole(tube);
  EXPECT_TRUE(r.fittable()) << r.problem;
  EXPECT_FALSE(r.closed);
  EXPECT_EQ(r.topology.boundary_loops, 2);
  EXPECT_EQ(r.topology.edges, 4 * n);
  EXPECT_EQ(r.topology.euler_characteristic, 0);
  EXPECT_EQ(r.topology.genus, 0);
  // n rectangles of height 1 and width the chord 2 sin(pi / n) = 1.
  EXPECT_NEAR(r.area, n * 2 * std::sin(kPi / n), 1e-12);
}

TEST(MeshPartsTest, ATorusIsRefusedWithItsGenus) {
  const TriangleMesh torus = Torus(8, 6);  // 96 triangles
  const PartReport r = ReportWhole(torus);
  EXPECT_FALSE(r.fittable());
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.problem,
            "part 1 (96 triangles) has genus 1; sdcb fits genus-0 parts");

  // Without one triangle: one boundary loop, chi = -1, still genus 1.
  TriangleMesh open = torus;
  open.faces.conservativeResize(95, 3);
  const PartReport o = ReportWhole(open, 3);
  EXPECT_FALSE(o.closed);
  EXPECT_EQ(o.problem,
            "part 3 (95 triangles) has genus 1 and 1 boundary loop; sdcb fits "
            "genus-0 parts");
}

TEST(MeshPartsTest, NonManifoldPartsAreRefused) {
  // A bowtie: two triangles sharing one vertex, two fans there.
  const TriangleMesh bowtie =
      MakeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}},
               {{0, 1, 2}, {0, 3, 4}});
  const PartReport r = ReportWhole(bowtie);
  EXPECT_EQ(r.topology.non_manifold_vertices, 1);
  EXPECT_EQ(r.problem,
            "part 1 (2 triangles) is not manifold (1 vertex where several "
            "sheets meet); sdcb fits manifold parts");

  // Three triangles on the edge 0-1.
  const TriangleMesh book =
      MakeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, -1, 0}},
               {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  const PartReport b = ReportWhole(book, 2);
  EXPECT_EQ(b.problem,
            "part 2 (3 triangles) is not manifold (1 edge with three or more "
            "triangles); sdcb fits manifold parts");
}

TEST(MeshPartsTest, AZeroAreaPartIsRefusedByNumber) {
  // Part 1 a tetrahedron, part 2 one triangle on a line.
  const TriangleMesh mesh =
      MakeMesh({{0, 0, 0},
                {1, 0, 0},
                {0, 1, 0},
                {0, 0, 1},
                {5, 0, 0},
                {6, 0, 0},
                {7, 0, 0}},
               {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}, {4, 5, 6}});
  const std::vector<MeshPart> parts = Split(mesh);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_TRUE(Report(parts[0], 1).fittable());
  const PartReport r = Report(parts[1], 2);
  EXPECT_EQ(r.area, 0.0);
  EXPECT_EQ(r.problem,
            "part 2 (1 triangle) has no area; sdcb fits parts "
            "with area");
}

TEST(MeshPartsTest, DegenerateAndMisorientedTrianglesAreNamed) {
  // The corner tetrahedron a b c d with a point m on the edge a-b: the
  // triangle (a, b, m) lies on a line and closes the surface with the
  // faces (a, m, d) and (m, b, d) in place of (a, b, d). V 5, E 9, F 6.
  const TriangleMesh with_needle = MakeMesh(
      {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {1, 0, 0}},
      {{0, 2, 1}, {0, 4, 3}, {4, 1, 3}, {1, 2, 3}, {0, 3, 2}, {0, 1, 4}});
  const PartReport r = ReportWhole(with_needle);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.topology.genus, 0);
  EXPECT_EQ(r.problem,
            "part 1 (6 triangles) has 1 degenerate (zero-area) triangle; "
            "sdcb fits parts without degenerate triangles");

  // One face turned over: its three edges are each used twice one way.
  TriangleMesh flipped = CornerTetrahedron();
  flipped.faces.row(0) << 0, 1, 2;
  EXPECT_EQ(ReportWhole(flipped).problem,
            "part 1 (4 triangles) is not consistently oriented (3 edges are "
            "used twice in the same direction); sdcb fits consistently "
            "oriented parts");
}

TEST(MeshPartsTest, CoordinatesTheFitCannotUseAreRefusedAsTheFitRefusesThem) {
  // A vertex at 1e308: the faces there have cross products of norm about
  // 1e308, whose squares (the norm's sum) overflow.
  TriangleMesh big = CornerTetrahedron();
  big.vertices(3, 2) = 1e308;
  const PartReport r = ReportWhole(big);
  EXPECT_FALSE(r.fittable());
  EXPECT_EQ(r.problem,
            "part 1 (4 triangles) has coordinates too large for doubles (its "
            "area or bounding box overflows); sdcb fits parts whose area and "
            "bounding box are finite");
  EXPECT_FALSE(AreaScaleToUnitSphere(big).ok());  // the fit's refusal

  // Scaled by 1e100: each cross product is ~1e200 and its square 1e400
  // overflows; by 1e50 the squares are ~1e200 and all is finite.
  const PartReport huge = ReportWhole(CornerTetrahedron(1e100));
  EXPECT_FALSE(huge.fittable());
  EXPECT_EQ(huge.problem.find("part 1 (4 triangles) has coordinates too "
                              "large"),
            0u)
      << huge.problem;
  const PartReport large = ReportWhole(CornerTetrahedron(1e50));
  EXPECT_TRUE(large.fittable()) << large.problem;
  EXPECT_NEAR(large.area / 1e100, 1.5 + std::sqrt(3.0) / 2, 1e-12);
  EXPECT_TRUE(ComputeNormalizingTransform(CornerTetrahedron(1e50)).ok());

  // Scaled by 1e-170: no triangle is degenerate (exact test), but each
  // cross product, ~1e-340, underflows to 0.
  const TriangleMesh tiny = CornerTetrahedron(1e-170);
  const PartReport t = ReportWhole(tiny);
  EXPECT_EQ(t.topology.degenerate_faces, 0);
  EXPECT_EQ(t.problem,
            "part 1 (4 triangles) has coordinates too small for doubles (its "
            "area underflows to 0); sdcb fits parts with area");
  EXPECT_FALSE(AreaScaleToUnitSphere(tiny).ok());  // the fit's refusal

  // Vertices at -1e308 and 1e308: the bounding box's side overflows.
  const TriangleMesh wide =
      MakeMesh({{-1e308, 0, 0}, {1e308, 0, 0}, {0, 1, 0}, {0, 0, 1}},
               {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}});
  EXPECT_FALSE(ReportWhole(wide).fittable());
  EXPECT_FALSE(ComputeNormalizingTransform(wide).ok());
}

TEST(MeshPartsTest, TooManyPartsAreRefusedBeforeAnyIsBuilt) {
  // 10,000 disjoint triangles: 10,000 parts by construction.
  const int n = 10000;
  TriangleMesh soup;
  soup.vertices.resize(3 * n, 3);
  soup.faces.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    soup.vertices.row(3 * i) << i, 0, 0;
    soup.vertices.row(3 * i + 1) << i + 0.5, 0, 0;
    soup.vertices.row(3 * i + 2) << i, 0.5, 0;
    soup.faces.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  }
  const StatusOr<std::vector<MeshPart>> refused =
      SplitIntoParts(soup, kDefaultMaxParts);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kUnsupported);
  EXPECT_EQ(refused.status().message(),
            "mesh has 10,000 parts, more than --max-parts 1000");
  EXPECT_FALSE(SplitIntoParts(soup, n - 1).ok());
  // At the limit, or without one, every triangle is its own part.
  for (int max_parts : {n, 0}) {
    const std::vector<MeshPart> parts = Split(soup, max_parts);
    ASSERT_EQ(parts.size(), static_cast<size_t>(n));
    EXPECT_EQ(parts[n - 1].input_faces, (std::vector<int>{n - 1}));
    EXPECT_EQ(parts[n - 1].input_vertices,
              (std::vector<int>{3 * n - 3, 3 * n - 2, 3 * n - 1}));
  }
}

TEST(MeshPartsTest, BadIndicesAndEmptyMeshes) {
  TriangleMesh bad = CornerTetrahedron();
  bad.faces(2, 1) = 4;
  EXPECT_EQ(SplitIntoParts(bad, 0).status().code(), StatusCode::kInvalidInput);
  EXPECT_TRUE(Split(TriangleMesh()).empty());
  // Vertices and no triangles: no parts.
  TriangleMesh points = CornerTetrahedron();
  points.faces.resize(0, 3);
  EXPECT_TRUE(Split(points).empty());
}

}  // namespace
}  // namespace sdcb
