// Tests core/curvature.* against closed forms: spheres (k = 1/r), ellipsoid
// axis points (a/b^2, a/c^2), cylinders (1/r and 0), planes (0), and the
// invariances of curvature (scale, rigid motion).
#include "sdcb/core/mesh/curvature.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {
namespace {

// Open grid on a cylinder of radius r around the z axis, z in [0, height],
// outward oriented. Vertex (i, j) has index i * n_theta + j.
TriangleMesh Cylinder(double r, double height, int n_theta, int n_z) {
  TriangleMesh m;
  m.vertices.resize((n_z + 1) * n_theta, 3);
  for (int i = 0; i <= n_z; ++i) {
    for (int j = 0; j < n_theta; ++j) {
      const double phi = 2 * kPi * j / n_theta;
      m.vertices.row(i * n_theta + j) << r * std::cos(phi), r * std::sin(phi),
          height * i / n_z;
    }
  }
  m.faces.resize(2 * n_z * n_theta, 3);
  int f = 0;
  for (int i = 0; i < n_z; ++i) {
    for (int j = 0; j < n_theta; ++j) {
      const int a = i * n_theta + j, b = i * n_theta + (j + 1) % n_theta,
                c = (i + 1) * n_theta + (j + 1) % n_theta,
                d = (i + 1) * n_theta + j;
      m.faces.row(f++) << a, b, c;
      m.faces.row(f++) << a, c, d;
    }
  }
  return m;
}

int NearestVertex(const TriangleMesh& m, const Eigen::Vector3d& p) {
  Eigen::Index best;
  (m.vertices.rowwise() - p.transpose())
      .rowwise()
      .squaredNorm()
      .minCoeff(&best);
  return static_cast<int>(best);
}

TEST(CurvatureTest, SphereHasCurvatureOneOverRadius) {
  const double r = 2.5;
  TriangleMesh m = MakeIcosphere(5);
  m.vertices *= r;
  const auto k = EstimatePrincipalCurvatures(m);
  ASSERT_TRUE(k.ok()) << k.status().message();
  EXPECT_EQ(k->fallback_vertices, 0);
  for (int v = 0; v < m.num_vertices(); ++v) {
    ASSERT_NEAR(k->k_max[v], 1 / r, 0.01 / r) << v;
    ASSERT_NEAR(k->k_min[v], 1 / r, 0.01 / r) << v;
  }
  const auto kappa = Curvedness(m);
  ASSERT_TRUE(kappa.ok());
  EXPECT_NEAR(kappa->mean(), 2 / r, 0.01 / r);
}

TEST(CurvatureTest, EllipsoidAxisPoints) {
  // x^2/a^2 + y^2/b^2 + z^2/c^2 = 1: at (a,0,0) the principal curvatures
  // are a/b^2 and a/c^2 (and cyclically).
  const double a = 3, b = 2, c = 1.5;
  TriangleMesh m = MakeIcosphere(6);
  m.vertices.col(0) *= a;
  m.vertices.col(1) *= b;
  m.vertices.col(2) *= c;
  const auto k = EstimatePrincipalCurvatures(m);
  ASSERT_TRUE(k.ok()) << k.status().message();
  struct Case {
    Eigen::Vector3d point;
    double k1, k2;
  };
  const Case cases[] = {{{a, 0, 0}, a / (c * c), a / (b * b)},
                        {{0, -b, 0}, b / (c * c), b / (a * a)},
                        {{0, 0, c}, c / (b * b), c / (a * a)}};
  for (const Case& test : cases) {
    const int v = NearestVertex(m, test.point);
    ASSERT_LT((m.vertices.row(v).transpose() - test.point).norm(), 1e-12);
    EXPECT_NEAR(k->k_max[v], test.k1, 0.02 * test.k1) << test.point;
    EXPECT_NEAR(k->k_min[v], test.k2, 0.02 * test.k2) << test.point;
  }
}

// On a cylinder of radius r the principal curvatures are 1/r and 0: checks
// rows [first_row, last_row] of Cylinder(r, height, n_theta, n_z) to within
// `tolerance` / r, and that no value is NaN anywhere.
void ExpectCylinderCurvatures(double r, double height, int n_theta, int n_z,
                              int first_row, int last_row, double tolerance) {
  const TriangleMesh m = Cylinder(r, height, n_theta, n_z);
  const auto k = EstimatePrincipalCurvatures(m);
  ASSERT_TRUE(k.ok()) << k.status().message();
  ASSERT_TRUE(k->k_max.allFinite() && k->k_min.allFinite());
  for (int i = first_row; i <= last_row; ++i) {
    for (int j = 0; j < n_theta; ++j) {
      const int v = i * n_theta + j;
      ASSERT_NEAR(k->k_max[v], 1 / r, tolerance / r) << v;
      ASSERT_NEAR(k->k_min[v], 0, tolerance / r) << v;
    }
  }
}

TEST(CurvatureTest, CylinderHasOneOverRadiusAndZero) {
  // Away from the open ends (boundary rings give one-sided fits).
  ExpectCylinderCurvatures(2, 6, 96, 40, 8, 32, 0.005);
}

TEST(CurvatureTest, CylinderWithLongThinTrianglesStaysAccurate) {
  // Aspect ratio ~ 20: height step 0.5 against 2*pi*r/512 ~ 0.025 around;
  // the middle row.
  ExpectCylinderCurvatures(2, 3, 512, 6, 3, 3, 0.02);
}

TEST(CurvatureTest, PlaneHasZeroCurvature) {
  // Jittered planar grid, tilted out of the coordinate planes.
  const int n = 30;
  TriangleMesh m;
  m.vertices.resize(n * n, 3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  const Eigen::Vector3d u = Eigen::Vector3d(1, 2, 0.5).normalized();
  const Eigen::Vector3d w = u.cross(Eigen::Vector3d(0, 0, 1)).normalized();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      m.vertices.row(i * n + j) =
          ((i + jitter(rng)) * u + (j + jitter(rng)) * w).transpose();
    }
  }
  m.faces.resize(2 * (n - 1) * (n - 1), 3);
  int f = 0;
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j + 1 < n; ++j) {
      const int a = i * n + j;
      m.faces.row(f++) << a, a + n, a + n + 1;
      m.faces.row(f++) << a, a + n + 1, a + 1;
    }
  }
  const auto kappa = Curvedness(m);
  ASSERT_TRUE(kappa.ok()) << kappa.status().message();
  EXPECT_LT(kappa->maxCoeff(), 1e-9);
}

// A star-shaped bumpy closed surface: radius 1 + 0.2 sin(3x) cos(2y) ...
TriangleMesh Bumpy() {
  TriangleMesh m = MakeIcosphere(4);
  for (int v = 0; v < m.num_vertices(); ++v) {
    const Eigen::Vector3d p = m.vertices.row(v);
    const double s = 1 + 0.2 * std::sin(3 * p.x()) * std::cos(2 * p.y()) +
                     0.1 * p.z() * p.z();
    m.vertices.row(v) *= s;
  }
  return m;
}

TEST(CurvatureTest, ScalesAsOneOverLengthAndIgnoresRigidMotions) {
  const TriangleMesh m = Bumpy();
  const auto kappa = Curvedness(m);
  ASSERT_TRUE(kappa.ok());

  const double s = 7.25;
  TriangleMesh scaled = m;
  scaled.vertices *= s;
  const auto kappa_scaled = Curvedness(scaled);
  ASSERT_TRUE(kappa_scaled.ok());

  TriangleMesh moved = m;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 3).normalized())
          .toRotationMatrix();
  moved.vertices = (m.vertices * rotation.transpose()).rowwise() +
                   Eigen::RowVector3d(5, -3, 2);
  const auto kappa_moved = Curvedness(moved);
  ASSERT_TRUE(kappa_moved.ok());

  EXPECT_GT(kappa->maxCoeff(), 2 * kappa->minCoeff());  // not a sphere
  for (int v = 0; v < m.num_vertices(); ++v) {
    ASSERT_NEAR((*kappa_scaled)[v] * s, (*kappa)[v], 1e-8 * (*kappa)[v]);
    ASSERT_NEAR((*kappa_moved)[v], (*kappa)[v], 1e-7 * (*kappa)[v]);
  }
}

TEST(CurvatureTest, SameResultForAnyThreadCount) {
  const TriangleMesh m = Bumpy();
  Eigen::VectorXd one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = *Curvedness(m);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = *Curvedness(m);
  }
  EXPECT_EQ(one, two);
}

TEST(CurvatureTest, UnreferencedVertexFallsBackWithoutNaN) {
  TriangleMesh m = MakeIcosphere(3);
  m.vertices.conservativeResize(m.num_vertices() + 1, 3);
  m.vertices.row(m.num_vertices() - 1) << 10, 10, 10;
  const auto k = EstimatePrincipalCurvatures(m);
  ASSERT_TRUE(k.ok());
  EXPECT_EQ(k->fallback_vertices, 1);
  EXPECT_EQ(k->k_max[m.num_vertices() - 1], 0);
  EXPECT_TRUE(k->k_max.allFinite() && k->k_min.allFinite());
}

TEST(CurvatureTest, RejectsBadInput) {
  TriangleMesh m = MakeIcosphere(1);
  m.faces(3, 1) = m.num_vertices();
  EXPECT_EQ(Curvedness(m).status().code(), StatusCode::kInvalidInput);
  m = MakeIcosphere(1);
  m.vertices(2, 0) = std::nan("");
  EXPECT_EQ(Curvedness(m).status().code(), StatusCode::kInvalidInput);
  CurvatureOptions options;
  options.min_points = 3;
  EXPECT_EQ(Curvedness(MakeIcosphere(1), options).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
