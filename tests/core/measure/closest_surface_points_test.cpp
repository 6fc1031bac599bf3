// The closest-point searches (core/measure/closest_surface_points.h) against
// independent oracles: the ellipsoid's exact distance (Eberly's root), brute
// force over a dense sampling of a spline, and a plane in closed form for the
// Gauss-Newton kernel.
#include "sdcb/core/measure/closest_surface_points.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "testing/analytic_surfaces.h"
#include "testing/random_spline.h"

namespace sdcb {
namespace {

// The ellipsoid with its jet in closed form: S(p) = A p, and in the chart
// phi(u, v) = S((p + u e_u + v e_v) / |.|) the derivatives A e_u, A e_v
// (the normalization does not move p to first order along the tangents).
class EllipsoidWithJet : public testing::EllipsoidSampler {
 public:
  explicit EllipsoidWithJet(const Eigen::Vector3d& axes)
      : EllipsoidSampler(axes), axes_(axes) {}
  SurfacePoint EvaluateJet(const Eigen::Vector3d& direction) const override {
    SurfacePoint out;
    const Eigen::Vector3d p = direction.normalized();
    TangentFrame(p, &out.frame_u, &out.frame_v);
    out.position = axes_.cwiseProduct(p);
    out.du = axes_.cwiseProduct(out.frame_u);
    out.dv = axes_.cwiseProduct(out.frame_v);
    out.normal = out.du.cross(out.dv).normalized();
    return out;
  }

 private:
  Eigen::Vector3d axes_;
};

// Points near the ellipsoid (along its normal, both sides) and start
// directions a little off their feet.
void NearPoints(const EllipsoidWithJet& e, int n, unsigned seed,
                Eigen::MatrixX3d* points, Eigen::MatrixX3d* starts) {
  const Eigen::MatrixX3d u = testing::RandomUnitVectors(n, seed);
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<double> off(-0.15, 0.15), jitter(-0.1, 0.1);
  Eigen::MatrixX3d s, normals;
  e.Sample(u, &s, &normals);
  points->resize(n, 3);
  starts->resize(n, 3);
  for (int i = 0; i < n; ++i) {
    points->row(i) = s.row(i) + off(rng) * normals.row(i);
    starts->row(i) =
        (u.row(i) + Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng)))
            .normalized();
  }
}

TEST(ClosestSurfacePointsTest, BatchedSearchReachesTheEllipsoidsDistance) {
  const EllipsoidWithJet e(Eigen::Vector3d(1.0, 0.7, 0.5));
  Eigen::MatrixX3d x, u;
  NearPoints(e, 300, 3, &x, &u);
  int64_t evaluations = 0;
  const Eigen::VectorXd d = ClosestSurfacePoints(e, x, 8, &u, &evaluations);
  EXPECT_GT(evaluations, x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double exact = e.Distance(x.row(i).transpose());
    EXPECT_GE(d[i], exact - 1e-12);  // a distance to a point of the surface
    EXPECT_NEAR(d[i], exact, 1e-6) << i;
    // *directions holds where it was met.
    EXPECT_NEAR(
        (e.Evaluate(u.row(i).transpose()) - x.row(i).transpose()).norm(), d[i],
        1e-12);
  }
}

TEST(ClosestSurfacePointsTest, OnePointSearchReachesTheEllipsoidsDistance) {
  const EllipsoidWithJet e(Eigen::Vector3d(1.0, 0.7, 0.5));
  Eigen::MatrixX3d x, u;
  NearPoints(e, 300, 5, &x, &u);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    Eigen::Vector3d found;
    const double d = ClosestSurfacePoint(e, x.row(i).transpose(),
                                         u.row(i).transpose(), 20, &found);
    const double exact = e.Distance(x.row(i).transpose());
    EXPECT_GE(d, exact - 1e-12);
    EXPECT_NEAR(d, exact, 1e-7) << i;
    EXPECT_NEAR((e.Evaluate(found) - x.row(i).transpose()).norm(), d, 1e-12);
  }
}

// The smallest distance from x to the surface at 4,000 directions within
// `radius` radians of `center` (brute force).
double NearbyBruteForce(const SurfaceSampler& surface, const Eigen::Vector3d& x,
                        const Eigen::Vector3d& center, double radius,
                        unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> t(-radius, radius);
  Eigen::Vector3d e_u, e_v;
  TangentFrame(center, &e_u, &e_v);
  Eigen::MatrixX3d directions(4000, 3), points;
  for (Eigen::Index k = 0; k < directions.rows(); ++k) {
    directions.row(k) = (center + t(rng) * e_u + t(rng) * e_v).normalized();
  }
  surface.Sample(directions, &points, nullptr);
  return (points.rowwise() - x.transpose()).rowwise().norm().minCoeff();
}

TEST(ClosestSurfacePointsTest, BothSearchesOnASplineAgainstBruteForce) {
  // A random spline through its polynomials (it folds, and a global closest
  // point can lie on another sheet: the searches are local). From a start
  // about 0.06 rad off each point's foot both searches end nearer than the
  // start, at a point of the surface, and never below the true distance:
  // not below the nearest of 400,000 surface samples by more than their
  // spacing allows. Where Gauss-Newton stalls (large residual against the
  // curvature: no halved step gains) they end above the nearby minimum;
  // brute force around the end measures by how much.
  const SphericalSpline spline =
      testing::RandomSpline(3, 40, 11, BasisForm::kNormalized, 0.02);
  const std::unique_ptr<SurfaceSampler> surface =
      MakeSplineSampler(spline, true);
  const Eigen::MatrixX3d dense = testing::RandomUnitVectors(400000, 12);
  Eigen::MatrixX3d dense_points;
  surface->Sample(dense, &dense_points, nullptr);
  const Eigen::MatrixX3d feet = testing::RandomUnitVectors(40, 13);
  Eigen::MatrixX3d on, normals;
  surface->Sample(feet, &on, &normals);
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> off(-0.02, 0.02), jitter(-0.06, 0.06);
  Eigen::MatrixX3d x(feet.rows(), 3), starts(feet.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    x.row(i) = on.row(i) + off(rng) * normals.row(i);
    starts.row(i) = (feet.row(i) +
                     Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng)))
                        .normalized();
  }
  Eigen::MatrixX3d met = starts;
  const Eigen::VectorXd batched = ClosestSurfacePoints(*surface, x, 8, &met);
  int stalled = 0;
  double worst_stall = 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Eigen::Vector3d xi = x.row(i).transpose();
    const double from =
        (surface->Evaluate(starts.row(i).transpose()) - xi).norm();
    const double brute =
        (dense_points.rowwise() - x.row(i)).rowwise().norm().minCoeff();
    Eigen::Vector3d found;
    const double one =
        ClosestSurfacePoint(*surface, xi, starts.row(i).transpose(), 8, &found);
    EXPECT_LE(one, from) << i;
    EXPECT_LE(batched[i], from) << i;
    EXPECT_NEAR((surface->Evaluate(found) - xi).norm(), one, 1e-12) << i;
    EXPECT_NEAR((surface->Evaluate(met.row(i).transpose()) - xi).norm(),
                batched[i], 1e-12)
        << i;
    // The samples are ~0.006 rad apart on a surface of size ~1.
    EXPECT_GE(one, brute - 5e-3) << i;
    EXPECT_GE(batched[i], brute - 5e-3) << i;
    const double nearby = NearbyBruteForce(*surface, xi, found, 0.02, 100 + i);
    if (nearby < one - 1e-6) {
      ++stalled;
      worst_stall = std::max(worst_stall, one - nearby);
    }
  }
  std::printf(
      "one-point search stalled above the nearby minimum at %d of %d "
      "points, by at most %.3g\n",
      stalled, static_cast<int>(x.rows()), worst_stall);
}

TEST(GaussNewtonClosestTest, OneStepToThePlanesFoot) {
  // The plane S(u, v) = o + u a + v b: one Gauss-Newton step lands on the
  // foot of x (the closed-form least-squares solution).
  const Eigen::Vector3d o(0.5, -1, 2), a(1, 0.2, 0), b(0.1, 1, 0.3);
  const Eigen::Vector3d x(2, 1.5, -1);
  Eigen::Matrix<double, 3, 2> j;
  j << a, b;
  const Eigen::Vector2d foot =
      (j.transpose() * j).ldlt().solve(j.transpose() * (x - o));
  const double exact = (o + j * foot - x).norm();
  Eigen::Vector2d uv(0, 0), candidate;
  ChartPoint start;
  start.position = o;
  start.du = a;
  start.dv = b;
  int evaluations = 0;
  const double d = GaussNewtonClosest(
      x, start, 5, 0.0,
      [&](const Eigen::Vector2d& step, ChartPoint* p) {
        ++evaluations;
        candidate = uv + step;
        p->position = o + j * candidate;
        p->du = a;
        p->dv = b;
      },
      [&] { uv = candidate; });
  EXPECT_NEAR(d, exact, 1e-12);
  EXPECT_TRUE(uv.isApprox(foot, 1e-12));
  // The first step reaches the foot; the second cannot improve (4 halvings).
  EXPECT_EQ(evaluations, 1 + 4);
}

TEST(GaussNewtonClosestTest, StepsAreShortenedToTheMaximum) {
  const Eigen::Vector3d x(10, 0, 1);
  Eigen::Vector2d uv(0, 0), candidate;
  ChartPoint start;
  start.du = Eigen::Vector3d::UnitX();
  start.dv = Eigen::Vector3d::UnitY();
  double longest = 0;
  GaussNewtonClosest(
      x, start, 3, 0.5,
      [&](const Eigen::Vector2d& step, ChartPoint* p) {
        longest = std::max(longest, step.norm());
        candidate = uv + step;
        p->position = Eigen::Vector3d(candidate[0], candidate[1], 0);
        p->du = Eigen::Vector3d::UnitX();
        p->dv = Eigen::Vector3d::UnitY();
      },
      [&] { uv = candidate; });
  EXPECT_NEAR(longest, 0.5, 1e-15);
  EXPECT_NEAR(uv[0], 1.5, 1e-12);  // three steps of 0.5
}

}  // namespace
}  // namespace sdcb
