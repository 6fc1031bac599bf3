// Tests core/mesh/self_intersections.*: counts known by construction, a
// brute-force oracle (every pair of vertex-disjoint triangles through
// CGAL::do_intersect), and CGAL's Polygon_mesh_processing::self_intersections
// (an independent implementation of the same rule) on crumpled spheres.
#include "sdcb/core/mesh/self_intersections.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sdcb/core/mesh/cgal_mesh.h"
#include "sdcb/core/mesh/icosphere.h"
#include "testing/fan_mesh.h"

namespace sdcb {
namespace {

// A tetrahedron flattened into the plane z = 0: the outer triangle ABC and
// the three triangles ABD, BCD, CAD around D inside it. ABC overlaps each
// of the three inner triangles (they lie on the same side of their shared
// edge); the inner ones only touch along their shared edges.
TriangleMesh FlatTetrahedron() {
  TriangleMesh m;
  m.vertices.resize(4, 3);
  m.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.25, 0;
  m.faces.resize(4, 3);
  m.faces << 0, 2, 1,  // ABC (seen from below: the outside of the solid)
      0, 1, 3, 1, 2, 3, 2, 0, 3;
  return m;
}

// Pairs of triangles without a common vertex that intersect (exactly).
int64_t BruteForceDisjointPairs(const TriangleMesh& m) {
  using K = CGAL::Exact_predicates_exact_constructions_kernel;
  auto triangle = [&](int f) {
    auto p = [&](int k) {
      const int v = m.faces(f, k);
      return K::Point_3(m.vertices(v, 0), m.vertices(v, 1), m.vertices(v, 2));
    };
    return K::Triangle_3(p(0), p(1), p(2));
  };
  int64_t pairs = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int g = f + 1; g < m.num_faces(); ++g) {
      bool share = false;
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) share |= m.faces(f, a) == m.faces(g, b);
      }
      if (!share && CGAL::do_intersect(triangle(f), triangle(g))) ++pairs;
    }
  }
  return pairs;
}

// Pairs PMP::self_intersections reports, without the (f, f) it gives for a
// degenerate face.
int64_t CgalPairs(const TriangleMesh& m) {
  CgalMesh surface;
  EXPECT_TRUE(ToCgalMesh(m, &surface));
  std::vector<std::pair<CgalMesh::Face_index, CgalMesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(surface,
                                                    std::back_inserter(pairs));
  int64_t count = 0;
  for (const auto& [f, g] : pairs) count += f != g;
  return count;
}

TEST(SelfIntersections, SphereHasNone) {
  auto r = FindSelfIntersections(MakeIcosphere(3));
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->checked);
  EXPECT_EQ(r->intersecting_pairs, 0);
}

TEST(SelfIntersections, FlatTetrahedronHasThreeOverlaps) {
  auto r = FindSelfIntersections(FlatTetrahedron());
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->checked);
  EXPECT_EQ(r->intersecting_pairs, 3);
}

TEST(SelfIntersections, CrumpledSphereAgreesWithBruteForce) {
  // One vertex pushed through the sphere to the far side: its fan pierces
  // the opposite triangles.
  TriangleMesh m = MakeIcosphere(2);
  m.vertices.row(0) *= -1.5;
  const int64_t disjoint = BruteForceDisjointPairs(m);
  ASSERT_GT(disjoint, 0);
  auto r = FindSelfIntersections(m);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->checked);
  // PMP also counts pairs that share a vertex and overlap beyond it.
  EXPECT_GE(r->intersecting_pairs, disjoint);
  EXPECT_LE(r->intersecting_pairs, disjoint + 3 * m.num_faces());
}

// Crumpled spheres (random vertices pushed through the surface, and one
// triangle folded onto its neighbour's plane, on the neighbour's side of
// their shared edge, a coplanar overlap): the same count as CGAL's
// implementation.
TEST(SelfIntersections, AgreesWithCgalOnCrumpledSpheres) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    TriangleMesh m = MakeIcosphere(2 + trial % 2);
    std::uniform_int_distribution<int> vertex(0, m.num_vertices() - 1);
    for (int k = 0; k < trial; ++k) {
      m.vertices.row(vertex(random)) *= (k % 2 == 0) ? -1.5 : 0.3;
    }
    // Face f = (a, b, c) and its neighbour (b, a, d) across edge ab, all
    // four moved onto the plane z = 1 (exactly coplanar), d's x and y to
    // (a + b + 2 c) / 4 (inside f).
    const int f = 11 * trial;
    const int a = m.faces(f, 0), b = m.faces(f, 1), c = m.faces(f, 2);
    for (int g = 0; g < m.num_faces(); ++g) {
      for (int k = 0; k < 3; ++k) {
        if (m.faces(g, k) != b || m.faces(g, (k + 1) % 3) != a) continue;
        const int d = m.faces(g, (k + 2) % 3);
        for (int j = 0; j < 2; ++j) {
          m.vertices(d, j) = 0.25 * (m.vertices(a, j) + m.vertices(b, j) +
                                     2 * m.vertices(c, j));
        }
        for (int v : {a, b, c, d}) m.vertices(v, 2) = 1.0;
      }
    }
    auto r = FindSelfIntersections(m);
    ASSERT_TRUE(r.ok());
    ASSERT_TRUE(r->checked);
    EXPECT_GT(r->intersecting_pairs, 0);
    EXPECT_EQ(r->intersecting_pairs, CgalPairs(m));
  }
}

// Non-manifold soups are checked too (CGAL's implementation needs a
// manifold). The flat tetrahedron's three overlaps, plus a copy of its outer
// triangle on edge (0, 1): it coincides with the outer one and overlaps the
// three inner ones the same way (3 + 1 + 3).
TEST(SelfIntersections, NonManifoldSoupsAreChecked) {
  TriangleMesh m = FlatTetrahedron();
  m.faces.conservativeResize(5, 3);
  m.faces.row(4) << 0, 1, 2;
  auto r = FindSelfIntersections(m);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->checked);
  EXPECT_EQ(r->intersecting_pairs, 7);
  m.faces(4, 2) = 7;
  EXPECT_EQ(FindSelfIntersections(m).status().code(),
            StatusCode::kInvalidInput);
}

TEST(SelfIntersections, HugeFansAreSkippedWithinTheBudget) {
  // Two fans of n triangles around the poles: every pair of triangles of a
  // fan overlaps in its bounding box at the pole.
  const int n = 1000;
  const TriangleMesh m = testing::DoubleCone(n);
  SelfIntersectionOptions tight;
  tight.max_pairs_per_face = 10;
  tight.max_extra_pairs = 0;
  auto skipped = FindSelfIntersections(m, tight);
  ASSERT_TRUE(skipped.ok());
  EXPECT_FALSE(skipped->checked);
  EXPECT_NE(skipped->skipped_because.find("fan"), std::string::npos);
  // With room for the n^2 pairs the test runs and finds nothing.
  SelfIntersectionOptions roomy;
  roomy.max_extra_pairs = int64_t{4} * n * n;
  auto checked = FindSelfIntersections(m, roomy);
  ASSERT_TRUE(checked.ok());
  EXPECT_TRUE(checked->checked);
  EXPECT_EQ(checked->intersecting_pairs, 0);
}

TEST(SelfIntersections, TheBudgetHoldsOnEitherSideOfTheSplit) {
  // A fan pair of 2n triangles beside 2n small disjoint triangles: the box
  // search's split falls between them, so one side's search (the one run
  // beside the other, or the one waiting for it) spends the budget alone.
  const int n = 1000;
  const TriangleMesh cone = testing::DoubleCone(n);
  for (const double side : {1.0, -1.0}) {
    TriangleMesh m;
    const int nc = cone.num_vertices();
    const int small = 2 * n;
    m.vertices.resize(nc + 3 * small, 3);
    m.faces.resize(cone.num_faces() + small, 3);
    m.vertices.topRows(nc) = cone.vertices;
    m.vertices.col(0).head(nc).array() += side * 100.0;
    m.faces.topRows(cone.num_faces()) = cone.faces;
    for (int i = 0; i < small; ++i) {
      const double x = -side * (100.0 + 3.0 * i);
      m.vertices.row(nc + 3 * i) << x, 0, 0;
      m.vertices.row(nc + 3 * i + 1) << x + 1, 0, 0;
      m.vertices.row(nc + 3 * i + 2) << x, 1, 0;
      m.faces.row(cone.num_faces() + i) << nc + 3 * i, nc + 3 * i + 1,
          nc + 3 * i + 2;
    }
    SelfIntersectionOptions tight;
    tight.max_pairs_per_face = 10;
    tight.max_extra_pairs = 0;
    auto skipped = FindSelfIntersections(m, tight);
    ASSERT_TRUE(skipped.ok());
    EXPECT_FALSE(skipped->checked) << side;
    SelfIntersectionOptions roomy;
    roomy.max_extra_pairs = int64_t{4} * n * n;
    auto checked = FindSelfIntersections(m, roomy);
    ASSERT_TRUE(checked.ok());
    EXPECT_TRUE(checked->checked) << side;
    EXPECT_EQ(checked->intersecting_pairs, 0) << side;
  }
}

}  // namespace
}  // namespace sdcb
