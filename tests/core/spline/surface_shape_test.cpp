#include "sdcb/core/spline/surface_shape.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

namespace sdcb {
namespace {

TEST(SurfaceShapeTest, SphereWithOutwardNormal) {
  // phi(u, v) = R (cos u cos v, sin u cos v, sin v) at 0: K = 1 / R^2,
  // H = 1 / R, an umbilic.
  const double r = 2.5;
  const SurfaceShape shape =
      ShapeFromDerivatives(Eigen::Vector3d(r, 0, 0), Eigen::Vector3d(0, r, 0),
                           Eigen::Vector3d(0, 0, r), Eigen::Vector3d(-r, 0, 0),
                           Eigen::Vector3d::Zero(), Eigen::Vector3d(-r, 0, 0));
  EXPECT_NEAR((shape.normal - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(shape.gaussian_curvature, 1 / (r * r), 1e-15);
  EXPECT_NEAR(shape.mean_curvature, 1 / r, 1e-15);
  const PrincipalDirections p = PrincipalDirectionsOf(shape);
  EXPECT_NEAR(p.k1, 1 / r, 1e-15);
  EXPECT_NEAR(p.k2, 1 / r, 1e-15);
  EXPECT_NEAR((p.d1 - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((p.d2 - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-15);
}

TEST(SurfaceShapeTest, Cylinder) {
  // phi(u, v) = (R cos u, R sin u, v): K = 0, H = 1 / (2 R); k1 = 1 / R
  // around, k2 = 0 along the axis.
  const double r = 0.5;
  const SurfaceShape shape =
      ShapeFromDerivatives(Eigen::Vector3d(r, 0, 0), Eigen::Vector3d(0, r, 0),
                           Eigen::Vector3d::UnitZ(), Eigen::Vector3d(-r, 0, 0),
                           Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  EXPECT_NEAR(shape.gaussian_curvature, 0.0, 1e-15);
  EXPECT_NEAR(shape.mean_curvature, 1 / (2 * r), 1e-15);
  const PrincipalDirections p = PrincipalDirectionsOf(shape);
  EXPECT_NEAR(p.k1, 1 / r, 1e-14);
  EXPECT_NEAR(p.k2, 0.0, 1e-14);
  EXPECT_NEAR(std::abs(p.d1.y()), 1.0, 1e-14);
  EXPECT_NEAR(std::abs(p.d2.z()), 1.0, 1e-14);
  EXPECT_NEAR((p.d1.cross(p.d2) - shape.normal).norm(), 0.0, 1e-14);
}

TEST(SurfaceShapeTest, GraphInASkewChartWithTangentialNoise) {
  // The graph z = h(x, y) = (a x^2 + 2 b x y + c y^2) / 2 in the chart
  // (x, y) = (u + 0.3 v, v), normal +z: K = a c - b^2, and the surface bends
  // towards its normal where h is convex, so H = -(a + c) / 2 and the
  // principal curvatures are minus the eigenvalues of h's Hessian, along its
  // eigenvectors. Tangential parts of the second derivatives change nothing.
  const double a = 1.5, b = -0.4, c = -0.7;
  const Eigen::Vector2d du(1, 0), dv(0.3, 1);  // (x, y) per (u, v)
  const Eigen::Matrix2d hessian = (Eigen::Matrix2d() << a, b, b, c).finished();
  const auto second = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    return Eigen::Vector3d(0.7, -0.2, p.dot(hessian * q));
  };
  const SurfaceShape shape = ShapeFromDerivatives(
      Eigen::Vector3d::Zero(), Eigen::Vector3d(du[0], du[1], 0),
      Eigen::Vector3d(dv[0], dv[1], 0), second(du, du), second(du, dv),
      second(dv, dv));
  EXPECT_NEAR(shape.gaussian_curvature, a * c - b * b, 1e-14);
  EXPECT_NEAR(shape.mean_curvature, -(a + c) / 2, 1e-14);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(hessian);
  const PrincipalDirections p = PrincipalDirectionsOf(shape);
  // k1 = -(smallest eigenvalue) along its eigenvector.
  EXPECT_NEAR(p.k1, -eigen.eigenvalues()[0], 1e-14);
  EXPECT_NEAR(p.k2, -eigen.eigenvalues()[1], 1e-14);
  const Eigen::Vector2d e1 = eigen.eigenvectors().col(0);
  EXPECT_NEAR(std::abs(p.d1.dot(Eigen::Vector3d(e1[0], e1[1], 0))), 1.0, 1e-14);
  EXPECT_NEAR(p.d1.z(), 0.0, 1e-15);
  EXPECT_NEAR((p.d1.cross(p.d2) - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-14);
}

TEST(SurfaceShapeTest, SingularChartGivesNaN) {
  const SurfaceShape shape = ShapeFromDerivatives(
      Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
      2 * Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(),
      Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  EXPECT_TRUE(shape.normal.isZero(0.0));
  EXPECT_TRUE(std::isnan(shape.gaussian_curvature));
  EXPECT_TRUE(std::isnan(shape.mean_curvature));
  EXPECT_TRUE(std::isnan(PrincipalDirectionsOf(shape).k1));
}

}  // namespace
}  // namespace sdcb
