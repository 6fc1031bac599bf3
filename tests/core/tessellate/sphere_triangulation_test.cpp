#include "sdcb/core/tessellate/sphere_triangulation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <map>
#include <random>
#include <set>

#include "sdcb/core/common/constants.h"

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
  EXPECT_NEAR(area, 4.0 * kPi, 1e-9);
}

// The corner table against a brute-force scan of the faces: every alive
// half-edge's twin runs the other way and is its twin's twin; Star(v) lists
// exactly the faces with corner v, faces[i] = (v, ring[i], ring[i + 1]);
// HalfEdge finds the only face with that directed edge.
void ExpectConsistentAdjacency(const SphereTriangulation& t) {
  std::map<std::pair<int, int>, int> owner;
  for (int f = 0; f < t.num_face_slots(); ++f) {
    if (!t.alive(f)) continue;
    for (int e = 0; e < 3; ++e) {
      const int h = 3 * f + e;
      owner[{t.Origin(h), t.Target(h)}] = h;
      const int g = t.Twin(h);
      ASSERT_GE(g, 0);
      ASSERT_TRUE(t.alive(g / 3));
      EXPECT_EQ(t.Twin(g), h);
      EXPECT_EQ(t.Origin(g), t.Target(h));
      EXPECT_EQ(t.Target(g), t.Origin(h));
    }
  }
  std::vector<int> star, ring;
  for (int v = 0; v < t.num_vertices(); ++v) {
    if (!t.vertex_alive(v)) continue;
    t.Star(v, &star, &ring);
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
      const int h = t.HalfEdge(v, ring[i]);
      ASSERT_GE(h, 0);
      EXPECT_EQ(h, owner.at({v, ring[i]}));
      EXPECT_EQ(h / 3, star[i]);
      EXPECT_EQ(t.Apex(h), ring[(i + 1) % n]);
    }
  }
}

TEST(SphereTriangulationTest, IcosphereIsASphere) {
  for (int level : {0, 2}) {
    const SphereTriangulation t = SphereTriangulation::Icosphere(level);
    EXPECT_EQ(t.num_vertices(), 10 * (1 << (2 * level)) + 2);
    EXPECT_EQ(t.num_faces(), 20 * (1 << (2 * level)));
    ExpectSphereTriangulation(t);
    ExpectConsistentAdjacency(t);
  }
}

TEST(SphereTriangulationTest, FromFacesRefusesOpenOrInconsistentFaces) {
  const SphereTriangulation ico = SphereTriangulation::Icosphere(0);
  Eigen::MatrixX3d directions(12, 3);
  for (int v = 0; v < 12; ++v) directions.row(v) = ico.vertex(v);
  Eigen::MatrixX3i faces = ico.Faces();
  EXPECT_TRUE(SphereTriangulation::FromFaces(directions, faces).ok());
  Eigen::MatrixX3i open = faces.topRows(19);  // a hole
  EXPECT_FALSE(SphereTriangulation::FromFaces(directions, open).ok());
  Eigen::MatrixX3i flipped = faces;  // one face turned over
  std::swap(flipped(3, 0), flipped(3, 1));
  EXPECT_FALSE(SphereTriangulation::FromFaces(directions, flipped).ok());
  Eigen::MatrixX3i bad = faces;
  bad(0, 0) = 12;  // no such vertex
  EXPECT_FALSE(SphereTriangulation::FromFaces(directions, bad).ok());
}

TEST(SphereTriangulationTest, RandomSplitsCollapsesAndFlipsStayASphere) {
  // Random edges split at their midpoints, random vertices collapsed into a
  // random neighbour where the preview allows it, random edges flipped:
  // after each step the corner table matches the faces, and the result is
  // a triangulation of the sphere. Each split adds a vertex and two faces;
  // each collapse removes a vertex and two faces.
  std::mt19937 rng(5);
  SphereTriangulation t = SphereTriangulation::Icosphere(1);
  int vertices = t.num_vertices(), faces = t.num_faces();
  int splits = 0, collapses = 0, flips = 0;
  std::vector<SphereTriangulation::Face> preview;
  std::vector<int> slots, ring;
  for (int step = 0; step < 3000; ++step) {
    std::vector<int> alive;
    for (int f = 0; f < t.num_face_slots(); ++f) {
      if (t.alive(f)) alive.push_back(f);
    }
    const int h = 3 * alive[rng() % alive.size()] + int(rng() % 3);
    const int kind = step < 600 ? 0 : int(rng() % 3);
    if (kind == 0) {
      const int a = t.Origin(h), b = t.Target(h);
      const int m = t.SplitEdge(h, (t.vertex(a) + t.vertex(b)).normalized());
      EXPECT_EQ(m, vertices);
      EXPECT_LT(t.HalfEdge(a, b), 0);
      EXPECT_GE(t.HalfEdge(a, m), 0);
      EXPECT_GE(t.HalfEdge(m, b), 0);
      ++vertices;
      faces += 2;
      ++splits;
    } else if (kind == 1) {
      const int v = t.Origin(h);
      t.Star(v, nullptr, &ring);
      const int w = ring[rng() % ring.size()];
      if (!t.PreviewCollapse(v, w, &preview, &slots)) continue;
      EXPECT_EQ(preview.size(), ring.size() - 2);
      t.Collapse(v, w);
      EXPECT_FALSE(t.vertex_alive(v));
      // The slots hold the previewed faces (up to rotation).
      for (size_t i = 0; i < slots.size(); ++i) {
        auto face = t.face(slots[i]);
        auto expected = preview[i];
        std::rotate(face.begin(),
                    std::find(face.begin(), face.end(), expected[0]),
                    face.end());
        EXPECT_EQ(face, expected);
      }
      faces -= 2;
      ++collapses;
    } else {
      std::array<SphereTriangulation::Face, 2> flipped;
      if (!t.PreviewFlip(h, &flipped)) continue;
      const int f = h / 3, g = t.Twin(h) / 3;
      t.Flip(h);
      EXPECT_EQ(t.face(f), flipped[0]);
      EXPECT_EQ(t.face(g), flipped[1]);
      ++flips;
    }
    EXPECT_EQ(t.num_faces(), faces);
    if (step % 250 == 0) ExpectConsistentAdjacency(t);
  }
  EXPECT_GT(collapses, 100);
  EXPECT_GT(flips, 100);
  EXPECT_EQ(static_cast<int>(t.AliveVertices().size()),
            12 + 30 + splits - collapses);
  ExpectSphereTriangulation(t);
  ExpectConsistentAdjacency(t);
}

TEST(SphereTriangulationTest, CollapseKeepsTheLinkCondition) {
  // On the icosahedron every vertex has valence 5; collapsing one into a
  // neighbour is valid (their two common neighbours are the edge's apexes).
  // Collapsing on the octahedron-like pinch of a valence-3 vertex next to
  // another is refused.
  SphereTriangulation t = SphereTriangulation::Icosphere(0);
  std::vector<SphereTriangulation::Face> preview;
  std::vector<int> slots, ring;
  t.Star(0, nullptr, &ring);
  ASSERT_TRUE(t.PreviewCollapse(0, ring[0], &preview, &slots));
  t.Collapse(0, ring[0]);
  ExpectSphereTriangulation(t);
  // Collapse until refused everywhere: never below a tetrahedron.
  bool any = true;
  while (any) {
    any = false;
    for (int v : t.AliveVertices()) {
      t.Star(v, nullptr, &ring);
      for (int w : ring) {
        if (t.PreviewCollapse(v, w, &preview, &slots)) {
          t.Collapse(v, w);
          any = true;
          break;
        }
      }
      if (any) break;
    }
  }
  EXPECT_GE(t.num_faces(), 4);
  ExpectSphereTriangulation(t);
  ExpectConsistentAdjacency(t);
}

}  // namespace
}  // namespace sdcb
