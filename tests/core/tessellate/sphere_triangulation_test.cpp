#include "sdcb/core/tessellate/sphere_triangulation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <map>
#include <random>
#include <set>

namespace sdcb {
namespace {

// Closed, manifold, consistently oriented, genus 0, every face positively
// oriented on the sphere: checked from the faces alone.
void ExpectSphereTriangulation(const SphereTriangulation& t) {
  const Eigen::MatrixX3i f = t.Faces();
  const std::vector<int> alive = t.AliveVertices();
  Eigen::MatrixX3d v(alive.size(), 3);
  for (size_t i = 0; i < alive.size(); ++i) v.row(i) = t.vertex(alive[i]);
  std::map<std::pair<int, int>, int> directed;
  std::set<int> used;
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    const Eigen::Vector3d a = v.row(f(i, 0)), b = v.row(f(i, 1)),
                          c = v.row(f(i, 2));
    EXPECT_GT(a.cross(b).dot(c), 0.0) << "face " << i << " is inverted";
    for (int k = 0; k < 3; ++k) {
      ++directed[{f(i, k), f(i, (k + 1) % 3)}];
      used.insert(f(i, k));
    }
  }
  for (const auto& [e, count] : directed) {
    EXPECT_EQ(count, 1) << "edge used twice in one direction";
    EXPECT_EQ(directed.count({e.second, e.first}), 1u) << "boundary edge";
  }
  const long long edges = static_cast<long long>(directed.size()) / 2;
  EXPECT_EQ(static_cast<long long>(used.size()) - edges + f.rows(), 2);
  EXPECT_EQ(used.size(), alive.size());
  // The spherical triangles tile the sphere: their areas sum to 4 pi.
  double area = 0.0;
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    const Eigen::Vector3d a = v.row(f(i, 0)), b = v.row(f(i, 1)),
                          c = v.row(f(i, 2));
    // Van Oosterom & Strackee's solid angle.
    area += 2.0 *
            std::atan2(a.dot(b.cross(c)), 1.0 + a.dot(b) + b.dot(c) + c.dot(a));
  }
  EXPECT_NEAR(area, 4.0 * M_PI, 1e-9);
}

TEST(SphereTriangulationTest, IcosahedronIsASphere) {
  const auto t = SphereTriangulation::Icosahedron([](int, int) { return 1.0; });
  EXPECT_EQ(t.num_vertices(), 12);
  EXPECT_EQ(t.num_faces(), 20);
  ExpectSphereTriangulation(t);
}

TEST(SphereTriangulationTest, RandomBisectionsStayConforming) {
  // Domain lengths scaled by a random factor in [1, 1.5] per edge (fixed
  // per edge: a surface metric), random faces: long LEPP paths.
  std::mt19937 rng(3);
  SphereTriangulation* current = nullptr;
  const auto length = [&](int a, int b) {
    return (current->vertex(a) - current->vertex(b)).norm() *
           std::uniform_real_distribution<>(1.0, 1.5)(rng);
  };
  SphereTriangulation t = SphereTriangulation::Icosahedron([](int a, int b) {
    return 1.0 + 0.01 * std::min(a, b) + 0.001 * std::max(a, b);
  });
  current = &t;
  int created = 0;
  for (int step = 0; step < 2000; ++step) {
    std::vector<int> alive;
    for (int f = 0; f < t.num_face_slots(); ++f) {
      if (t.alive(f)) alive.push_back(f);
    }
    const int f = alive[rng() % alive.size()];
    const int before = t.num_vertices();
    t.Bisect(f, length, [&](int v) {
      EXPECT_GE(v, before);
      ++created;
    });
    EXPECT_FALSE(t.alive(f));
  }
  EXPECT_EQ(t.num_vertices(), 12 + created);
  ExpectSphereTriangulation(t);
  // Each split adds one vertex and two faces.
  EXPECT_EQ(t.num_faces(), 20 + 2 * created);
}

TEST(SphereTriangulationTest, RandomEdgeSplitsStayConforming) {
  // Any edge (not only longest ones) split at its midpoint, mixed with
  // collapses: still a sphere, two faces more per split.
  std::mt19937 rng(5);
  const auto length = [](int a, int b) { return 1.0; };
  SphereTriangulation t = SphereTriangulation::Icosahedron(length);
  int created = 0;
  for (int step = 0; step < 1500; ++step) {
    const std::vector<std::array<int, 2>> edges = t.Edges();
    const auto [a, b] = edges[rng() % edges.size()];
    const int before_faces = t.num_faces();
    const int before = t.num_vertices();
    int added = -1;
    t.SplitEdge(a, b, length, [&](int v) {
      added = v;
      ++created;
    });
    ASSERT_EQ(added, before);
    EXPECT_FALSE(t.HasEdge(a, b));
    EXPECT_TRUE(t.HasEdge(a, added) && t.HasEdge(added, b));
    EXPECT_NEAR(t.vertex(added).norm(), 1.0, 1e-15);
    EXPECT_EQ(t.num_faces(), before_faces + 2);
  }
  EXPECT_EQ(t.num_vertices(), 12 + created);
  ExpectSphereTriangulation(t);
  // Star and FaceOf against a brute-force scan of the faces: Star(v)[i] is
  // the face (v, ring[i], ring[i + 1]), the only face with that directed
  // edge.
  for (int v = 0; v < t.num_vertices(); ++v) {
    const std::vector<int> ring = t.Ring(v), star = t.Star(v);
    ASSERT_EQ(star.size(), ring.size());
    int faces_of_v = 0;
    for (int f = 0; f < t.num_face_slots(); ++f) {
      const auto& face = t.face(f);
      faces_of_v +=
          t.alive(f) && (face[0] == v || face[1] == v || face[2] == v);
    }
    EXPECT_EQ(faces_of_v, static_cast<int>(star.size()));
    const int n = static_cast<int>(ring.size());
    for (int i = 0; i < n; ++i) {
      const int x = ring[i], y = ring[(i + 1) % n];
      int found = -1;
      for (int f = 0; f < t.num_face_slots(); ++f) {
        if (!t.alive(f)) continue;
        const auto& face = t.face(f);
        for (int k = 0; k < 3; ++k) {
          if (face[k] == v && face[(k + 1) % 3] == x &&
              face[(k + 2) % 3] == y) {
            found = f;
          }
        }
      }
      EXPECT_EQ(star[i], found);
      EXPECT_EQ(t.FaceOf(v, x), found);
      EXPECT_TRUE(SphereTriangulation::IsPositive(t.vertex(v), t.vertex(x),
                                                  t.vertex(y)));
      EXPECT_FALSE(SphereTriangulation::IsPositive(t.vertex(v), t.vertex(y),
                                                   t.vertex(x)));
    }
  }
}

}  // namespace
}  // namespace sdcb
