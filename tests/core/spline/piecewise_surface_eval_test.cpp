// PiecewiseSurface's shapes (positions, normals, forms, curvatures from the
// region polynomials' derivatives) against the reference evaluator
// (SphericalSpline::EvaluateShape, from the basis functions' R^3 Hessians),
// against Gauss-Bonnet, and against finite differences of its own normals.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "testing/random_spline.h"

namespace sdcb {
namespace {

// A smooth closed surface: degree 4 on `n` random knots, each control point
// the normalized mean of its set's knots (so F is close to a unit sphere).
SphericalSpline SmoothSpline(int n, unsigned seed) {
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(n, seed);
  StatusOr<DelaunayConfigurations> c = ComputeDelaunayConfigurations(knots, 4);
  EXPECT_TRUE(c.ok());
  StatusOr<DcbBasis> basis = DcbBasis::Create(knots, *c);
  EXPECT_TRUE(basis.ok());
  Eigen::MatrixX3d cp(basis->size(), 3);
  for (int i = 0; i < basis->size(); ++i) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int k : basis->configuration_set(i).knots) mean += knots.row(k);
    cp.row(i) = mean.normalized().transpose();
  }
  return std::move(SphericalSpline::Create(std::move(*basis), cp)).value();
}

TEST(PiecewiseSurfaceShapeTest, AgreesWithTheReferenceEvaluator) {
  for (int degree : {2, 3, 4, -4}) {
    // -4: degree 4 with the raw basis of eq. 4 (F = N / |x|^k).
    SCOPED_TRACE(degree);
    const BasisForm form =
        degree < 0 ? BasisForm::kRaw : BasisForm::kNormalized;
    degree = std::abs(degree);
    const SphericalSpline spline =
        testing::RandomSpline(degree, 60, 5 + degree, form, 0.1);
    const PiecewiseSurface fast(spline);
    const Eigen::MatrixX3d points = testing::RandomUnitVectors(3000, 99);
    std::vector<SurfaceShape> shapes;
    fast.EvaluateShapeMany(points, &shapes);
    Eigen::VectorXd gaussian, mean;
    fast.EvaluateCurvatureMany(points, &gaussian, &mean);
    int wrong = 0, not_as_single = 0;
    for (Eigen::Index r = 0; r < points.rows(); ++r) {
      const Eigen::Vector3d p = points.row(r).transpose();
      const SurfaceShape e = spline.EvaluateShape(p);
      const SurfaceShape& f = shapes[r];
      // Errors relative to the size of each quantity (curvatures of order
      // 1 or more: this spline folds, |K| reaches 1e5).
      const double scale = e.du.norm() + e.dv.norm();
      const double k = std::max(1.0, std::abs(e.gaussian_curvature));
      const double h = std::max(1.0, std::abs(e.mean_curvature));
      const bool ok =
          (f.position - e.position).norm() <= 1e-12 * e.position.norm() &&
          (f.du - e.du).norm() + (f.dv - e.dv).norm() <= 1e-10 * scale &&
          (f.normal - e.normal).norm() <= 1e-9 &&
          (f.first_form - e.first_form).norm() <= 1e-10 * e.first_form.norm() &&
          (f.second_form - e.second_form).norm() <=
              1e-9 * e.second_form.norm() &&
          std::abs(f.gaussian_curvature - e.gaussian_curvature) <= 1e-8 * k &&
          std::abs(f.mean_curvature - e.mean_curvature) <= 1e-8 * h;
      wrong += !ok;
      // One point at a time and the curvature batch give the same bits.
      const SurfaceShape single = fast.EvaluateShape(p);
      not_as_single += !(single.second_form == f.second_form &&
                         single.gaussian_curvature == gaussian[r] &&
                         single.mean_curvature == mean[r]);
    }
    EXPECT_EQ(wrong, 0) << "of " << points.rows() << " points";
    EXPECT_EQ(not_as_single, 0);
  }
}

// The quadrature of K and H over the surface on an icosphere of `level`:
// K and H at the centroid directions of its faces times the areas of the
// faces' images. Also the total area.
struct Integrals {
  double gaussian = 0.0, mean = 0.0, area = 0.0;
};
Integrals Integrate(const PiecewiseSurface& surface, int level) {
  const TriangleMesh sphere = MakeIcosphere(level);
  Eigen::MatrixX3d centroids(sphere.faces.rows(), 3), positions;
  for (Eigen::Index f = 0; f < sphere.faces.rows(); ++f) {
    centroids.row(f) = (sphere.vertices.row(sphere.faces(f, 0)) +
                        sphere.vertices.row(sphere.faces(f, 1)) +
                        sphere.vertices.row(sphere.faces(f, 2)))
                           .normalized();
  }
  Eigen::VectorXd gaussian, mean;
  surface.EvaluateCurvatureMany(centroids, &gaussian, &mean);
  surface.EvaluateMany(sphere.vertices, &positions, nullptr);
  Integrals out;
  for (Eigen::Index f = 0; f < sphere.faces.rows(); ++f) {
    const Eigen::Vector3d a = positions.row(sphere.faces(f, 0));
    const Eigen::Vector3d b = positions.row(sphere.faces(f, 1));
    const Eigen::Vector3d c = positions.row(sphere.faces(f, 2));
    const double da = 0.5 * (b - a).cross(c - a).norm();
    out.gaussian += gaussian[f] * da;
    out.mean += mean[f] * da;
    out.area += da;
  }
  return out;
}

TEST(PiecewiseSurfaceShapeTest, GaussBonnet) {
  // Oracle: the integral of K over a closed genus-0 surface is 4 pi. The
  // quadrature's error falls as h^2 (0.30, 0.087, 0.023 at levels 4, 5, 6
  // here), so levels 5 and 6 extrapolated (Richardson) leave ~1e-4.
  const SphericalSpline spline = SmoothSpline(80, 3);
  const PiecewiseSurface fast(spline);
  const Integrals coarse = Integrate(fast, 5), fine = Integrate(fast, 6);
  EXPECT_NEAR((4 * fine.gaussian - coarse.gaussian) / 3, 4 * kPi,
              3e-4 * 4 * kPi);
  // The mean curvature of a surface close to a sphere: close to 1 / R for
  // the sphere of the same area.
  const double radius = std::sqrt(fine.area / (4 * kPi));
  EXPECT_NEAR(fine.mean / fine.area, 1.0 / radius, 0.05 / radius);
}

TEST(PiecewiseSurfaceShapeTest, ScalingTheControlPointsScalesTheCurvatures) {
  // F -> 3 F + d: K / 9, H / 3, forms 9 I and 3 II, same normal.
  const SphericalSpline spline =
      testing::RandomSpline(3, 50, 8, BasisForm::kNormalized, 0.1);
  const SphericalSpline scaled =
      std::move(SphericalSpline::Create(
                    spline.basis(), (3.0 * spline.control_points()).rowwise() +
                                        Eigen::RowVector3d(1.0, -2.0, 0.5)))
          .value();
  const PiecewiseSurface a(spline), b(scaled);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(500, 4);
  std::vector<SurfaceShape> sa, sb;
  a.EvaluateShapeMany(points, &sa);
  b.EvaluateShapeMany(points, &sb);
  for (Eigen::Index r = 0; r < points.rows(); ++r) {
    const double k = std::max(1.0, std::abs(sa[r].gaussian_curvature));
    const double h = std::max(1.0, std::abs(sa[r].mean_curvature));
    EXPECT_NEAR(sb[r].gaussian_curvature * 9, sa[r].gaussian_curvature,
                1e-9 * k);
    EXPECT_NEAR(sb[r].mean_curvature * 3, sa[r].mean_curvature, 1e-9 * h);
    EXPECT_LE((sb[r].normal - sa[r].normal).norm(), 1e-9);
    EXPECT_LE((sb[r].first_form - 9 * sa[r].first_form).norm(),
              1e-9 * sb[r].first_form.norm());
  }
}

TEST(PiecewiseSurfaceShapeTest, PrincipalDirectionsTurnTheNormal) {
  // Rodrigues: along a principal direction d (a unit tangent, image of the
  // parameter direction x), the normal turns as dn = k d ds; central
  // differences of the evaluator's own normals, step 1e-5 rad.
  const SphericalSpline spline = SmoothSpline(60, 11);
  const PiecewiseSurface fast(spline);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(200, 12);
  const double step = 1e-5;
  for (Eigen::Index r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r).transpose();
    const SurfaceShape shape = fast.EvaluateShape(p);
    const PrincipalDirections principal = PrincipalDirectionsOf(shape);
    EXPECT_NEAR(principal.k1 * principal.k2, shape.gaussian_curvature,
                1e-9 * (1 + std::abs(shape.gaussian_curvature)));
    EXPECT_NEAR(principal.k1 + principal.k2, 2 * shape.mean_curvature,
                1e-9 * (1 + std::abs(shape.mean_curvature)));
    EXPECT_NEAR(principal.d1.dot(principal.d2), 0.0, 1e-9);
    EXPECT_LE((principal.d1.cross(principal.d2) - shape.normal).norm(), 1e-9);
    Eigen::Vector3d e_u, e_v;
    TangentFrame(p, &e_u, &e_v);
    Eigen::Matrix<double, 3, 2> tangents;
    tangents << shape.du, shape.dv;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d d = i == 0 ? principal.d1 : principal.d2;
      const double k = i == 0 ? principal.k1 : principal.k2;
      // The parameter direction x with du x0 + dv x1 = d.
      const Eigen::Vector2d x = tangents.colPivHouseholderQr().solve(d);
      const Eigen::Vector3d dir = x[0] * e_u + x[1] * e_v;
      Eigen::Vector3d plus, minus, n_plus, n_minus;
      fast.EvaluateWithNormal(p + step * dir, &plus, &n_plus);
      fast.EvaluateWithNormal(p - step * dir, &minus, &n_minus);
      const Eigen::Vector3d dn = (n_plus - n_minus) / (2 * step);
      EXPECT_LE((dn - k * d).norm(), 1e-4 * (1 + std::abs(k)))
          << "point " << r << " direction " << i;
    }
  }
}

TEST(PiecewiseSurfaceShapeTest, SameBitsForAnyThreadCountAndOrder) {
  // Regions built by a batch on two threads and by single points in reverse
  // order on one: the same bits.
  const SphericalSpline spline =
      testing::RandomSpline(4, 60, 21, BasisForm::kNormalized, 0.1);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(5000, 22);
  Eigen::VectorXd gaussian, mean;
  Eigen::MatrixX3d positions;
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    const PiecewiseSurface fast(spline);
    fast.EvaluateCurvatureMany(points, &gaussian, &mean);
    fast.EvaluateMany(points, &positions, nullptr);
  }
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const PiecewiseSurface fast(spline);
  int differ = 0;
  for (Eigen::Index r = points.rows() - 1; r >= 0; --r) {
    const Eigen::Vector3d p = points.row(r).transpose();
    const SurfaceShape shape = fast.EvaluateShape(p);
    differ += !(shape.gaussian_curvature == gaussian[r] &&
                shape.mean_curvature == mean[r] &&
                fast.Evaluate(p) == positions.row(r).transpose());
  }
  EXPECT_EQ(differ, 0);
}

}  // namespace
}  // namespace sdcb
