// Tests core/sphere/sphere_triangle_locator.*: located triangles and their
// weights against a brute-force scan that solves for each triangle's
// weights with a dense solve, on a rotated icosphere with some triangles
// turned over, and on half of it (directions outside find nothing); and
// against a scan of every triangle with the exact predicate, bit for bit,
// on a sphere crowded towards a pole (the grid's fullest cell, unsplit,
// lists a hundred triangles), at random directions, exactly on its vertices
// and edges, and within ~1e-15 of its edges.
#include "sdcb/core/sphere/sphere_triangle_locator.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <random>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/sphere/cube_atlas.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/sphere/spherical_barycentric.h"
#include "testing/crowded_sphere.h"

namespace sdcb {
namespace {

Eigen::Vector3d RandomDirection(std::mt19937* rng) {
  std::normal_distribution<double> g;
  return Eigen::Vector3d(g(*rng), g(*rng), g(*rng)).normalized();
}

// lambda with [t0 t1 t2] lambda = d (the ray meets the flat triangle at
// lambda / sum(lambda)).
Eigen::Vector3d Weights(const Eigen::MatrixX3d& p, const Eigen::MatrixX3i& f,
                        int face, const Eigen::Vector3d& d) {
  Eigen::Matrix3d m;
  for (int c = 0; c < 3; ++c) m.col(c) = p.row(f(face, c)).transpose();
  return m.fullPivLu().solve(d);
}

void CheckAgainstBruteForce(const Eigen::MatrixX3d& points,
                            const Eigen::MatrixX3i& faces, int queries,
                            int* found) {
  const SphereTriangleLocator locator(points, faces);
  std::mt19937 rng(11);
  for (int i = 0; i < queries; ++i) {
    const Eigen::Vector3d d = RandomDirection(&rng);
    int strictly_inside = -1;
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      const Eigen::Vector3d w = Weights(points, faces, f, d);
      if (w.minCoeff() > 1e-9) strictly_inside = static_cast<int>(f);
    }
    const SphereTriangleLocator::Location at = locator.Locate(d);
    if (strictly_inside >= 0) {
      ASSERT_EQ(at.face, strictly_inside);
    }
    if (at.face < 0) {
      ASSERT_EQ(strictly_inside, -1);
      continue;
    }
    ++*found;
    const Eigen::Vector3d w = Weights(points, faces, at.face, d);
    EXPECT_GT(w.minCoeff(), -1e-12);
    EXPECT_LT((at.barycentric - w / w.sum()).norm(), 1e-12);
  }
}

TEST(SphereTriangleLocatorTest, MatchesBruteForceOnARotatedSphere) {
  const TriangleMesh sphere = MakeIcosphere(3);
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())
          .toRotationMatrix();
  Eigen::MatrixX3d points = sphere.vertices * r.transpose();
  points.rowwise().normalize();
  Eigen::MatrixX3i faces = sphere.faces;
  for (Eigen::Index f = 0; f < faces.rows(); f += 3) {
    std::swap(faces(f, 1), faces(f, 2));  // either orientation is accepted
  }
  int found = 0;
  CheckAgainstBruteForce(points, faces, 3000, &found);
  EXPECT_EQ(found, 3000);  // a closed triangulation holds every direction
}

TEST(SphereTriangleLocatorTest, DirectionsOutsideAnOpenRegionFindNothing) {
  const TriangleMesh sphere = MakeIcosphere(2);
  Eigen::MatrixX3d points = sphere.vertices;
  points.rowwise().normalize();
  std::vector<int> kept;
  for (Eigen::Index f = 0; f < sphere.faces.rows(); ++f) {
    const Eigen::Vector3d c = points.row(sphere.faces(f, 0)) +
                              points.row(sphere.faces(f, 1)) +
                              points.row(sphere.faces(f, 2));
    if (c.z() > 0.2) kept.push_back(static_cast<int>(f));
  }
  Eigen::MatrixX3i faces(kept.size(), 3);
  for (size_t i = 0; i < kept.size(); ++i)
    faces.row(i) = sphere.faces.row(kept[i]);
  int found = 0;
  CheckAgainstBruteForce(points, faces, 2000, &found);
  EXPECT_GT(found, 400);
  EXPECT_LT(found, 1200);
  const SphereTriangleLocator locator(points, faces);
  EXPECT_EQ(locator.Locate(Eigen::Vector3d(0, 0, -1)).face, -1);
}

// What Locate must answer, from every triangle: the lowest-numbered one
// that holds `d` (exact, boundary included: Det3Sign, CGAL's predicate, on
// the corners counter-clockwise), and its weights computed as the contract
// says (eq. 2 with the corners counter-clockwise, normalized, in the
// caller's corner order), so the comparison is bit for bit.
SphereTriangleLocator::Location BruteForce(const Eigen::MatrixX3d& points,
                                           const Eigen::MatrixX3i& faces,
                                           const Eigen::Vector3d& d) {
  SphereTriangleLocator::Location out;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    Eigen::Vector3d t[3];
    for (int c = 0; c < 3; ++c) t[c] = points.row(faces(f, c)).transpose();
    const int orientation = Det3Sign(t[0], t[1], t[2]);
    const bool flipped = orientation < 0;
    if (flipped) std::swap(t[1], t[2]);
    if (orientation == 0 || Det3Sign(t[0], t[1], d) < 0 ||
        Det3Sign(t[1], t[2], d) < 0 || Det3Sign(t[2], t[0], d) < 0) {
      continue;
    }
    Eigen::Vector3d b = SphericalBarycentric(d, t[0], t[1], t[2]);
    b /= b.sum();
    if (flipped) std::swap(b[1], b[2]);
    out.face = static_cast<int>(f);
    out.barycentric = b;
    return out;
  }
  return out;
}

TEST(SphereTriangleLocatorTest, MatchesEveryTriangleScanOnACrowdedSphere) {
  // Area ratio ~10^4 between the poles' triangles: a grid cell at the south
  // pole meets about a hundred. Rotated twice: the dense pole at a cube
  // face's centre, and near a cube corner (three faces meet there).
  const TriangleMesh crowded = testing::CrowdedIcosphere(3, 0.1);
  const Eigen::Matrix3d rotations[2] = {
      Eigen::Matrix3d::Identity(),
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d(0, 0, -1),
                                         Eigen::Vector3d(1, 1.1, 0.9))
          .toRotationMatrix()};
  for (const Eigen::Matrix3d& r : rotations) {
    // Coordinates on a 2^-40 grid (unit within 1e-11), so that a + b and
    // 3 a + b are exact: directions exactly on an edge's great arc.
    Eigen::MatrixX3d points = crowded.vertices * r.transpose();
    points = (points * 0x1p40).array().round() / 0x1p40;
    Eigen::MatrixX3i faces = crowded.faces;
    for (Eigen::Index f = 0; f < faces.rows(); f += 3) {
      std::swap(faces(f, 1), faces(f, 2));  // either orientation is accepted
    }
    const SphereTriangleLocator locator(points, faces);
    // The crowded cells were split (unsplit, the grid's fullest cell lists
    // 101 triangles with the dense pole at a face's centre, 39 near a cube
    // corner), within the memory bound.
    const SphereTriangleLocator::CellStats stats = locator.Stats();
    EXPECT_LE(stats.longest, 16);
    EXPECT_LE(stats.entries, 8 * faces.rows());
    std::vector<Eigen::Vector3d> directions;
    std::mt19937 rng(5);
    for (int i = 0; i < 2000; ++i) directions.push_back(RandomDirection(&rng));
    // Random points of random triangles: mostly in the crowded region.
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::uniform_int_distribution<int> pick(0,
                                            static_cast<int>(faces.rows()) - 1);
    for (int i = 0; i < 3000; ++i) {
      const int f = pick(rng);
      directions.push_back(u(rng) * points.row(faces(f, 0)).transpose() +
                           u(rng) * points.row(faces(f, 1)).transpose() +
                           u(rng) * points.row(faces(f, 2)).transpose());
    }
    // A lattice on every cube face, its edges included (ties between faces).
    for (int face = 0; face < 6; ++face) {
      for (int i = -16; i <= 16; ++i) {
        for (int j = -16; j <= 16; ++j) {
          directions.push_back(
              DirectionOnFace(face, Eigen::Vector2d(i / 16.0, j / 16.0)));
        }
      }
    }
    int on_edges = 0;
    for (Eigen::Index v = 0; v < points.rows(); ++v) {
      directions.push_back(points.row(v).transpose());
    }
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector3d a = points.row(faces(f, c)).transpose();
        const Eigen::Vector3d b = points.row(faces(f, (c + 1) % 3)).transpose();
        for (const Eigen::Vector3d& d :
             {Eigen::Vector3d(a + b), Eigen::Vector3d(3 * a + b)}) {
          ASSERT_EQ(Det3Sign(a, b, d), 0);
          directions.push_back(d);
          ++on_edges;
        }
      }
    }
    ASSERT_EQ(on_edges, 6 * faces.rows());
    // Off the edges by ~1e-15 relative to the corners' length: determinants
    // too small for a floating-point sign, where the exact predicate
    // decides.
    for (Eigen::Index f = 0; f < faces.rows(); f += 7) {
      const Eigen::Vector3d a = points.row(faces(f, 0)).transpose();
      const Eigen::Vector3d b = points.row(faces(f, 1)).transpose();
      const Eigen::Vector3d c = points.row(faces(f, 2)).transpose();
      for (double e : {1e-15, -1e-15, 1e-13, -1e-13}) {
        directions.push_back(a + b + e * (c - a));
      }
    }
    int found = 0;
    for (const Eigen::Vector3d& d : directions) {
      const SphereTriangleLocator::Location want = BruteForce(points, faces, d);
      const SphereTriangleLocator::Location at = locator.Locate(d);
      ASSERT_EQ(at.face, want.face) << d.transpose();
      ASSERT_EQ(at.barycentric, want.barycentric) << d.transpose();
      found += at.face >= 0;
    }
    EXPECT_EQ(found, static_cast<int>(directions.size()));
  }
}

}  // namespace
}  // namespace sdcb
