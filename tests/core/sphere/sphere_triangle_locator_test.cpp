// Tests core/sphere/sphere_triangle_locator.*: located triangles and their
// weights against a brute-force scan that solves for each triangle's
// weights with a dense solve, on a rotated icosphere with some triangles
// turned over, and on half of it (directions outside find nothing).
#include "sdcb/core/sphere/sphere_triangle_locator.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <random>

#include "sdcb/core/mesh/icosphere.h"

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

}  // namespace
}  // namespace sdcb
