// RepairFolds (core/fit/fold_repair.h) on a sphere: a spline fitted to it by
// least squares, one control point dragged sideways so that the surface turns
// over beside it. The oracle for a fold is the sphere's own: the spline's
// normal against the radial direction of its point (the icosphere's faces
// are within 3 degrees of it), at random points, not the lattice the repair
// works on.
#include "sdcb/core/fit/fold_repair.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/design_matrix.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "testing/random_sphere_points.h"

namespace sdcb {
namespace {

// Points of `points` where the spline's normal points into the sphere.
int Inverted(const SphericalSpline& spline, const Eigen::MatrixX3d& points) {
  int inverted = 0;
  for (const SurfacePoint& s :
       spline.EvaluateDifferentialMany(points, JetOrder::kGradient)) {
    if (s.normal.dot(s.position.normalized()) < 0) ++inverted;
  }
  return inverted;
}

// The unit sphere fitted by least squares at `samples` random points on
// `knots` random knots: the basis, the fit's regularized normal matrix and
// its control points.
DcbBasis BasisOnRandomKnots(int knots, int degree) {
  const Eigen::MatrixX3d k = testing::RandomUnitVectors(knots, 7);
  auto configurations = ComputeDelaunayConfigurations(k, degree);
  EXPECT_TRUE(configurations.ok());
  return std::move(DcbBasis::Create(k, *configurations)).value();
}

struct SphereFit {
  SphereFit(int knots, int degree, int samples)
      : basis(BasisOnRandomKnots(knots, degree)) {
    const Eigen::MatrixX3d& k = basis.knots();
    const Eigen::MatrixX3d points = testing::RandomUnitVectors(samples, 11);
    const DesignMatrix design =
        BuildFormDesignMatrix(basis, points, BasisForm::kNormalized);
    Eigen::MatrixX3d fallback(basis.size(), 3);
    for (int i = 0; i < basis.size(); ++i) {
      fallback.row(i) = k.row(basis.configuration_set(i).knots[0]);
    }
    control_points =
        std::move(SolveRegularizedLeastSquares(
                      design, points, GrevillePrior(design, points, fallback)))
            .value();
    normal = RegularizedNormalMatrixLower(design,
                                          LeastSquaresOptions().regularization);
  }
  DcbBasis basis;
  Eigen::SparseMatrix<double> normal;
  Eigen::MatrixX3d control_points;
};

// The measurement that finds the folds: surface -> mesh at a lattice.
DeviationOptions Lattice(int samples) {
  DeviationOptions lattice;
  lattice.min_surface_samples = samples;
  lattice.closest_points = false;
  lattice.mesh_to_surface = false;
  return lattice;
}

TEST(FoldRepairTest, ADraggedControlPointsFoldIsRemovedNearIt) {
  const TriangleMesh sphere = MakeIcosphere(4);
  const SphereFit fit(80, 3, 20000);
  const DcbBasis& basis = fit.basis;
  const Eigen::SparseMatrix<double>& normal = fit.normal;
  const int m = basis.size();

  // Control point 0 dragged along the sphere by 0.8 (its support spans
  // about 0.5 radians).
  Eigen::MatrixX3d dragged = fit.control_points;
  const Eigen::Vector3d at = dragged.row(0).transpose().normalized();
  const Eigen::Vector3d along = at.unitOrthogonal();
  dragged.row(0) += 0.8 * along.transpose();

  const Eigen::MatrixX3d probes = testing::RandomUnitVectors(200000, 13);
  auto fitted_spline = SphericalSpline::Create(basis, fit.control_points,
                                               BasisForm::kNormalized);
  auto dragged_spline =
      SphericalSpline::Create(basis, dragged, BasisForm::kNormalized);
  ASSERT_TRUE(fitted_spline.ok() && dragged_spline.ok());
  ASSERT_EQ(Inverted(*fitted_spline, probes), 0);
  ASSERT_GT(Inverted(*dragged_spline, probes), 50) << "the drag folds";

  auto distance = MeshDistance::Create(sphere);
  ASSERT_TRUE(distance.ok());
  const DeviationOptions lattice = Lattice(40000);
  // The default leaves folds above 0.1 % of the area alone.
  Eigen::MatrixX3d repaired = dragged;
  auto result = RepairFolds(basis, BasisForm::kNormalized, normal, sphere,
                            *distance, lattice, FoldRepairOptions(), &repaired);
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_GT(result->folded_before_percent, 0.1);
  EXPECT_EQ(result->iterations, 0);
  EXPECT_FALSE(result->changed);
  EXPECT_TRUE(repaired == dragged);

  // Steps damped so much that they cannot halve the folds: not kept, the
  // given control points returned bit for bit.
  FoldRepairOptions options;
  options.max_folded_percent = 1;
  options.damping = 1e6;
  options.max_iterations = 3;
  result = RepairFolds(basis, BasisForm::kNormalized, normal, sphere, *distance,
                       lattice, options, &repaired);
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_EQ(result->iterations, 3);
  EXPECT_FALSE(result->changed);
  EXPECT_TRUE(repaired == dragged);

  // Steps that would move the surface farther from the sphere than the drag
  // did (2.4 % of the unit) are dropped: the repair may then not finish, but
  // the lattice's distance never grows.
  options.damping = FoldRepairOptions().damping;
  options.max_iterations = FoldRepairOptions().max_iterations;
  result = RepairFolds(basis, BasisForm::kNormalized, normal, sphere, *distance,
                       lattice, options, &repaired);
  ASSERT_TRUE(result.ok()) << result.status().message();
  auto within =
      SphericalSpline::Create(basis, repaired, BasisForm::kNormalized);
  ASSERT_TRUE(within.ok());
  auto before = MeasureSurfaceDeviation(*dragged_spline, sphere, lattice,
                                        nullptr, &*distance);
  auto after =
      MeasureSurfaceDeviation(*within, sphere, lattice, nullptr, &*distance);
  ASSERT_TRUE(before.ok() && after.ok());
  EXPECT_LE(after->surface_to_mesh_max_percent,
            before->surface_to_mesh_max_percent + 1e-9);
  EXPECT_LT(result->folded_after_percent, result->folded_before_percent);
  repaired = dragged;

  // The drag moved the surface 2.4 % of the unit off the sphere at most; the
  // repair may move it up to 5 %.
  options = FoldRepairOptions();
  options.max_folded_percent = 1;
  options.max_distance_percent = 5;
  result = RepairFolds(basis, BasisForm::kNormalized, normal, sphere, *distance,
                       lattice, options, &repaired);
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_TRUE(result->changed);
  EXPECT_EQ(result->folded_after_percent, 0.0);
  EXPECT_GT(result->iterations, 0);

  auto repaired_spline =
      SphericalSpline::Create(basis, repaired, BasisForm::kNormalized);
  ASSERT_TRUE(repaired_spline.ok());
  EXPECT_EQ(Inverted(*repaired_spline, probes), 0);

  // Only control points near the fold moved; the others are the dragged
  // ones, bit for bit.
  int moved = 0;
  for (int i = 0; i < m; ++i) moved += repaired.row(i) != dragged.row(i);
  EXPECT_GT(moved, 0);
  EXPECT_LE(moved, result->moved_control_points);
  EXPECT_LT(moved, m / 3) << "of " << m;
}

// The lattice measured again after a change of a few control points
// (RemeasureSurfaceToMesh, which the repair's steps use) against a whole
// measurement of the changed spline: the same samples, distances, folds and
// figures.
TEST(FoldRepairTest, TheLatticeMeasuredAgainEqualsAWholeMeasurement) {
  const TriangleMesh sphere = MakeIcosphere(4);
  const SphereFit fit(80, 3, 20000);
  auto distance = MeshDistance::Create(sphere);
  ASSERT_TRUE(distance.ok());
  const DeviationOptions lattice = Lattice(20000);
  auto fitted = SphericalSpline::Create(fit.basis, fit.control_points,
                                        BasisForm::kNormalized);
  ASSERT_TRUE(fitted.ok());
  auto measured =
      MeasureSurfaceDeviation(*fitted, sphere, lattice, nullptr, &*distance);
  ASSERT_TRUE(measured.ok());
  EXPECT_EQ(measured->folded_area_percent, 0.0);
  const DesignMatrix values = BuildFormDesignMatrix(
      fit.basis, measured->surface_sample_points, BasisForm::kNormalized);

  Eigen::MatrixX3d dragged = fit.control_points;
  const std::vector<int> changed = {0, 5};
  for (const int j : changed) {
    dragged.row(j) +=
        0.8 * dragged.row(j).transpose().normalized().unitOrthogonal();
  }
  auto moved =
      SphericalSpline::Create(fit.basis, dragged, BasisForm::kNormalized);
  ASSERT_TRUE(moved.ok());
  auto whole =
      MeasureSurfaceDeviation(*moved, sphere, lattice, nullptr, &*distance);
  ASSERT_TRUE(whole.ok());
  ASSERT_GT(whole->folded_area_percent, 0.0) << "the drag folds";

  SurfaceDeviation again = *measured;
  ASSERT_TRUE(RemeasureSurfaceToMesh(*moved, *distance, lattice, values,
                                     changed, &again)
                  .ok());
  const Eigen::Index ns = whole->surface_samples;
  ASSERT_EQ(again.surface_sample_points.rows(), ns);
  int kept = 0;
  for (Eigen::Index i = 0; i < ns; ++i) {
    EXPECT_LT((again.surface_sample_positions.row(i) -
               whole->surface_sample_positions.row(i))
                  .norm(),
              1e-10);
    EXPECT_NEAR(again.surface_sample_distance_percent[i],
                whole->surface_sample_distance_percent[i], 1e-8);
    EXPECT_NEAR(again.surface_sample_weight[i], whole->surface_sample_weight[i],
                1e-12);
    EXPECT_EQ(again.surface_sample_folded[i], whole->surface_sample_folded[i]);
    kept += again.surface_sample_positions.row(i) ==
            measured->surface_sample_positions.row(i);
  }
  EXPECT_GT(kept, ns / 2) << "the samples the change cannot reach are kept";
  EXPECT_NEAR(again.folded_area_percent, whole->folded_area_percent, 1e-9);
  EXPECT_NEAR(again.surface_to_mesh_rms_percent,
              whole->surface_to_mesh_rms_percent, 1e-9);
  EXPECT_NEAR(again.surface_to_mesh_max_percent,
              whole->surface_to_mesh_max_percent, 1e-9);
  EXPECT_NEAR(again.surface_area, whole->surface_area, 1e-9);

  // Values of another lattice, or a measurement with the mesh's half, are
  // refused.
  const DesignMatrix other = BuildFormDesignMatrix(
      fit.basis, testing::RandomUnitVectors(100, 3), BasisForm::kNormalized);
  EXPECT_EQ(
      RemeasureSurfaceToMesh(*moved, *distance, lattice, other, changed, &again)
          .code(),
      StatusCode::kInvalidArgument);
  DeviationOptions two_sided = lattice;
  two_sided.mesh_to_surface = true;
  EXPECT_EQ(RemeasureSurfaceToMesh(*moved, *distance, two_sided, values,
                                   changed, &again)
                .code(),
            StatusCode::kInvalidArgument);
}

// A spline that does not fold is returned as it is, with no step taken.
TEST(FoldRepairTest, ASplineWithoutFoldsIsLeftAlone) {
  const TriangleMesh sphere = MakeIcosphere(3);
  const SphereFit fit(40, 2, 5000);
  auto distance = MeshDistance::Create(sphere);
  ASSERT_TRUE(distance.ok());
  Eigen::MatrixX3d control_points = fit.control_points;
  auto result = RepairFolds(fit.basis, BasisForm::kNormalized, fit.normal,
                            sphere, *distance, Lattice(10000),
                            FoldRepairOptions(), &control_points);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->folded_before_percent, 0.0);
  EXPECT_EQ(result->iterations, 0);
  EXPECT_FALSE(result->changed);
  EXPECT_TRUE(control_points == fit.control_points);
}

}  // namespace
}  // namespace sdcb
