#include "sdcb/core/tessellate/optimal_triangle_count.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "sdcb/core/common/constants.h"
#include "testing/analytic_surfaces.h"

namespace sdcb {
namespace {

// The peanut S(u) = (1/2 + u_z^2) u: a surface of revolution with a waist
// (saddle points around the equator, convex caps). Its profile over the
// polar angle t is rho = r sin t, z = r cos t with r = 1/2 + cos^2 t, and
// K = z' (rho' z'' - z' rho'') / (rho (rho'^2 + z'^2)^2).
struct Profile {
  double rho, z, d_rho, d_z, dd_rho, dd_z;
};

Profile PeanutProfile(double t) {
  const double s = std::sin(t), c = std::cos(t);
  const double r = 0.5 + c * c, dr = -2 * s * c, ddr = -2 * (c * c - s * s);
  return {r * s,
          r * c,
          dr * s + r * c,
          dr * c - r * s,
          ddr * s + 2 * dr * c - r * s,
          ddr * c - 2 * dr * s - r * c};
}

double PeanutGaussian(const Profile& p) {
  const double speed2 = p.d_rho * p.d_rho + p.d_z * p.d_z;
  return p.d_z * (p.d_rho * p.dd_z - p.d_z * p.dd_rho) /
         (p.rho * speed2 * speed2);
}

class PeanutSampler : public SurfaceSampler {
 public:
  void Sample(const Eigen::MatrixX3d& d, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override {
    positions->resize(d.rows(), 3);
    if (normals) normals->setZero(d.rows(), 3);
    for (Eigen::Index i = 0; i < d.rows(); ++i) {
      const Eigen::Vector3d u = d.row(i).transpose();
      positions->row(i) = ((0.5 + u.z() * u.z()) * u).transpose();
      const double planar = std::hypot(u.x(), u.y());
      if (!normals) continue;
      if (planar < 1e-12) {
        (*normals)(i, 2) = u.z() > 0 ? 1.0 : -1.0;
        continue;
      }
      // Outward normal (-z' cos phi, -z' sin phi, rho').
      const Profile p = PeanutProfile(std::atan2(planar, u.z()));
      normals->row(i) = Eigen::Vector3d(-p.d_z * u.x() / planar,
                                        -p.d_z * u.y() / planar, p.d_rho)
                            .normalized()
                            .transpose();
    }
  }
  bool SampleCurvature(const Eigen::MatrixX3d& d, Eigen::VectorXd* gaussian,
                       Eigen::VectorXd* mean) const override {
    gaussian->resize(d.rows());
    mean->setConstant(d.rows(), std::nan(""));
    for (Eigen::Index i = 0; i < d.rows(); ++i) {
      const double planar = std::hypot(d(i, 0), d(i, 1));
      (*gaussian)[i] =
          PeanutGaussian(PeanutProfile(std::atan2(planar, d(i, 2))));
    }
    return true;
  }
};

TEST(OptimalTriangleCountTest, WholeSurfaceQuadratureMatchesAProfileIntegral) {
  // Oracle: the integrals of the surface of revolution as one-dimensional
  // integrals over its profile (dA = 2 pi rho |profile'| dt), midpoint rule
  // on 200,000 steps. Gauss-Bonnet (int K dA = 4 pi) checks the curvature
  // formula the sampler and the oracle share.
  const int steps = 200000;
  double area = 0, convex = 0, saddle = 0, total_k = 0;
  for (int i = 0; i < steps; ++i) {
    const double t = (i + 0.5) * kPi / steps;
    const Profile p = PeanutProfile(t);
    const double da =
        2 * kPi * p.rho * std::hypot(p.d_rho, p.d_z) * (kPi / steps);
    const double k = PeanutGaussian(p);
    area += da;
    total_k += k * da;
    (k > 0 ? convex : saddle) += std::sqrt(std::abs(k)) * da;
  }
  ASSERT_NEAR(total_k, 4 * kPi, 1e-6);
  ASSERT_GT(saddle, 0.1 * convex);  // the waist is a real saddle band

  const StatusOr<CurvatureIntegrals> k =
      IntegrateCurvatureOverSurface(PeanutSampler());
  ASSERT_TRUE(k.ok()) << k.status().message();
  EXPECT_NEAR(k->area, area, 2e-3 * area);
  EXPECT_NEAR(k->convex, convex, 3e-3 * convex);
  EXPECT_NEAR(k->saddle, saddle, 3e-3 * saddle);
  // The coarsest pattern is far off: the level matters.
  const StatusOr<CurvatureIntegrals> coarse =
      IntegrateCurvatureOverSurface(PeanutSampler(), 1);
  ASSERT_TRUE(coarse.ok());
  EXPECT_GT(std::abs(coarse->saddle - saddle), 0.01 * saddle);
}

TEST(OptimalTriangleCountTest, WholeSurfaceQuadratureOnAnEllipsoid) {
  // Oracle: the parametric integral over (theta, phi) of the ellipsoid
  // x = (a sin t cos p, b sin t sin p, c cos t) with the closed-form
  // K = 1 / (a b c sum x_i^2 / a_i^4)^2, midpoint rule on 1000 x 2000.
  const Eigen::Vector3d axes(1.0, 0.7, 0.4);
  const int nt = 1000, np = 2000;
  const double dt = kPi / nt, dp = 2 * kPi / np;
  double area = 0, convex = 0;
  for (int i = 0; i < nt; ++i) {
    const double t = (i + 0.5) * dt;
    for (int j = 0; j < np; ++j) {
      const double p = (j + 0.5) * dp;
      const Eigen::Vector3d x(axes[0] * std::sin(t) * std::cos(p),
                              axes[1] * std::sin(t) * std::sin(p),
                              axes[2] * std::cos(t));
      const Eigen::Vector3d xt(axes[0] * std::cos(t) * std::cos(p),
                               axes[1] * std::cos(t) * std::sin(p),
                               -axes[2] * std::sin(t));
      const Eigen::Vector3d xp(-axes[0] * std::sin(t) * std::sin(p),
                               axes[1] * std::sin(t) * std::cos(p), 0.0);
      const double da = xt.cross(xp).norm() * dt * dp;
      double s = 0;
      for (int k = 0; k < 3; ++k) s += x[k] * x[k] / std::pow(axes[k], 4);
      const double abc = axes.prod();
      area += da;
      convex += da / (abc * s);  // sqrt(K)
    }
  }
  const StatusOr<CurvatureIntegrals> k =
      IntegrateCurvatureOverSurface(testing::EllipsoidSampler(axes));
  ASSERT_TRUE(k.ok()) << k.status().message();
  EXPECT_NEAR(k->area, area, 2e-3 * area);
  EXPECT_NEAR(k->convex, convex, 2e-3 * convex);
  EXPECT_EQ(k->saddle, 0.0);
  EXPECT_FALSE(
      IntegrateCurvatureOverSurface(testing::EllipsoidSampler(axes), 9).ok());
}

}  // namespace
}  // namespace sdcb
