// Tests of core/cage/sphere_cage_topology: the cage is a closed, consistently
// oriented manifold of quads or triangles (edge counting, Euler's formula),
// its faces' sphere regions tile the sphere (areas add up to 4 pi, the
// closed form), and refinement is local and deterministic.
#include "sdcb/core/cage/sphere_cage_topology.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <utility>

#include "sdcb/core/common/constants.h"

namespace sdcb {
namespace {

// Area of the spherical triangle a, b, c (unit vectors): Van Oosterom and
// Strackee's formula for its solid angle.
double SphericalTriangleArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  const double numerator = a.dot(b.cross(c));
  const double denominator = 1 + a.dot(b) + b.dot(c) + c.dot(a);
  return 2 * std::atan2(numerator, denominator);
}

// Checks what every cage must be; returns the summed signed sphere area.
double CheckCage(const SphereCage& cage) {
  const int n = cage.face_size;
  std::map<std::pair<int, int>, int> directed;
  double area = 0;
  for (int f = 0; f < cage.num_faces(); ++f) {
    const auto& c = cage.faces[f];
    std::set<int> distinct;
    for (int k = 0; k < n; ++k) {
      EXPECT_GE(c[k], 0);
      EXPECT_LT(c[k], cage.num_vertices());
      distinct.insert(c[k]);
      ++directed[{c[k], c[(k + 1) % n]}];
    }
    EXPECT_EQ(static_cast<int>(distinct.size()), n) << "face " << f;
    if (n == 3) {
      EXPECT_EQ(c[3], -1);
    }
    // Signed area of the spherical polygon (fan from corner 0): positive
    // for counter-clockwise seen from outside.
    for (int k = 1; k + 1 < n; ++k) {
      const double t = SphericalTriangleArea(cage.sphere_points.row(c[0]),
                                             cage.sphere_points.row(c[k]),
                                             cage.sphere_points.row(c[k + 1]));
      EXPECT_GT(t, 0) << "face " << f << " is inverted or degenerate";
      area += t;
    }
  }
  // Closed and consistently oriented: every directed edge once, with its
  // reverse.
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u)
        << edge.first << "-" << edge.second << " is a boundary";
  }
  const int edges = static_cast<int>(directed.size()) / 2;
  EXPECT_EQ(cage.num_vertices() - edges + cage.num_faces(), 2);
  // Every vertex used, every point on the sphere.
  std::vector<int> used(cage.num_vertices(), 0);
  for (const auto& c : cage.faces) {
    for (int k = 0; k < n; ++k) used[c[k]] = 1;
  }
  for (int v = 0; v < cage.num_vertices(); ++v) {
    EXPECT_TRUE(used[v]);
    EXPECT_NEAR(cage.sphere_points.row(v).norm(), 1.0, 1e-14);
  }
  EXPECT_EQ(cage.face_cell.size(), cage.faces.size());
  return area;
}

TEST(SphereCageTopologyTest, UniformCubeSphereAndIcosphereCounts) {
  for (int levels = 0; levels <= 3; ++levels) {
    const auto quads = SphereCageTopology::Create(CageCellShape::kQuad, levels);
    const int f = 6 << (2 * levels);
    EXPECT_EQ(quads.cage().face_size, 4);
    EXPECT_EQ(quads.cage().num_faces(), f);
    EXPECT_EQ(quads.cage().num_vertices(), f + 2);  // V = F + 2 for quads
    EXPECT_NEAR(CheckCage(quads.cage()), 4 * kPi, 1e-9);

    const auto tris =
        SphereCageTopology::Create(CageCellShape::kTriangle, levels);
    const int t = 20 << (2 * levels);
    EXPECT_EQ(tris.cage().num_faces(), t);
    EXPECT_EQ(tris.cage().num_vertices(), t / 2 + 2);
    EXPECT_NEAR(CheckCage(tris.cage()), 4 * kPi, 1e-9);
  }
}

TEST(SphereCageTopologyTest, SpherePointInterpolatesTheCorners) {
  const auto quads = SphereCageTopology::Create(CageCellShape::kQuad, 1);
  const SphereCage& q = quads.cage();
  const double corner_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int f = 0; f < q.num_faces(); ++f) {
    for (int k = 0; k < 4; ++k) {
      EXPECT_LT((q.SpherePoint(f, corner_uv[k][0], corner_uv[k][1]) -
                 q.sphere_points.row(q.faces[f][k]).transpose())
                    .norm(),
                1e-15);
    }
  }
  const auto tris = SphereCageTopology::Create(CageCellShape::kTriangle, 1);
  const SphereCage& t = tris.cage();
  for (int f = 0; f < t.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT((t.SpherePoint(f, corner_uv[k == 2 ? 3 : k][0],
                               corner_uv[k == 2 ? 3 : k][1]) -
                 t.sphere_points.row(t.faces[f][k]).transpose())
                    .norm(),
                1e-15);
    }
  }
}

// Random local refinements, several rounds deep: the closure (2:1 balance,
// green triangles, quad templates and parity) always gives a valid cage
// that tiles the sphere, and only where asked (plus the closure).
TEST(SphereCageTopologyTest, AdaptiveRefinementStaysConforming) {
  for (CageCellShape shape : {CageCellShape::kQuad, CageCellShape::kTriangle}) {
    std::mt19937 rng(shape == CageCellShape::kQuad ? 3 : 4);
    auto topology = SphereCageTopology::Create(shape, 1);
    for (int round = 0; round < 6; ++round) {
      // Refine the leaves of faces near a random direction (a local blob),
      // plus a few random ones.
      std::normal_distribution<double> gauss(0, 1);
      const Eigen::Vector3d d =
          Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
      const SphereCage& cage = topology.cage();
      std::vector<int> cells;
      for (int f = 0; f < cage.num_faces(); ++f) {
        const Eigen::Vector3d p = cage.SpherePoint(f, 0.3, 0.3);
        if (p.dot(d) > 0.9 || rng() % 50 == 0) {
          cells.push_back(cage.face_cell[f]);
        }
      }
      const int before = topology.cage().num_faces();
      topology.Refine(cells);
      SCOPED_TRACE(::testing::Message() << "round " << round);
      EXPECT_GT(topology.cage().num_faces(), before);
      EXPECT_NEAR(CheckCage(topology.cage()), 4 * kPi, 1e-9);
      if (shape == CageCellShape::kQuad) {
        EXPECT_EQ(topology.cage().face_size, 4);
      }
    }
  }
}

// Refining toward one direction, five rounds deep, touches a small part of
// the sphere: far fewer faces than the uniform cage of that depth.
TEST(SphereCageTopologyTest, RefinementIsLocal) {
  const Eigen::Vector3d d = Eigen::Vector3d(1, 2, 3).normalized();
  for (CageCellShape shape : {CageCellShape::kQuad, CageCellShape::kTriangle}) {
    auto topology = SphereCageTopology::Create(shape, 1);
    for (int round = 0; round < 5; ++round) {
      // The leaf whose face centre is nearest to d.
      const SphereCage& cage = topology.cage();
      int best = 0;
      for (int f = 1; f < cage.num_faces(); ++f) {
        if (cage.SpherePoint(f, 0.3, 0.3).dot(d) >
            cage.SpherePoint(best, 0.3, 0.3).dot(d)) {
          best = f;
        }
      }
      topology.Refine({cage.face_cell[best]});
    }
    EXPECT_NEAR(CheckCage(topology.cage()), 4 * kPi, 1e-9);
    int deepest = 0;
    for (int c : topology.cage().face_cell) {
      deepest = std::max(deepest, topology.level(c));
    }
    EXPECT_EQ(deepest, 6);
    const int uniform = (shape == CageCellShape::kQuad ? 6 : 20)
                        << (2 * deepest);
    EXPECT_LT(topology.cage().num_faces(), uniform / 8);
  }
}

TEST(SphereCageTopologyTest, Deterministic) {
  for (CageCellShape shape : {CageCellShape::kQuad, CageCellShape::kTriangle}) {
    auto a = SphereCageTopology::Create(shape, 1);
    auto b = SphereCageTopology::Create(shape, 1);
    for (int round = 0; round < 3; ++round) {
      std::vector<int> cells;
      for (int f = 0; f < a.cage().num_faces(); f += 7) {
        cells.push_back(a.cage().face_cell[f]);
      }
      a.Refine(cells);
      b.Refine(cells);
    }
    EXPECT_EQ(a.cage().faces, b.cage().faces);
    EXPECT_EQ(a.cage().sphere_points, b.cage().sphere_points);
  }
}

// A single refined quad next to unrefined ones leaves its neighbours with
// one hanging point each: the parity repair must close them with quads.
TEST(SphereCageTopologyTest, OneRefinedQuadIsClosedWithQuads) {
  auto topology = SphereCageTopology::Create(CageCellShape::kQuad, 2);
  topology.Refine({topology.cage().face_cell[0]});
  EXPECT_EQ(topology.cage().face_size, 4);
  EXPECT_NEAR(CheckCage(topology.cage()), 4 * kPi, 1e-9);
  // 96 faces, one split into 4, four neighbours closed: more than 99, far
  // fewer than the next uniform level.
  EXPECT_GT(topology.cage().num_faces(), 99);
  EXPECT_LT(topology.cage().num_faces(), 200);
}

}  // namespace
}  // namespace sdcb
