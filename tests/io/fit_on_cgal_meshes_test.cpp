// The fitting driver on CGAL's meshes (in the io binary because it reads
// them): reaches the targets, errors are honest, output deterministic.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

TriangleMesh Load(const std::string& name) {
  auto mesh = ReadMesh(testing::MeshPath(name));
  EXPECT_TRUE(mesh.ok()) << mesh.status().message();
  return std::move(mesh).value();
}

// The paper's vertex errors recomputed independently: evaluate the model's
// surface at the stored parameters, map back to input coordinates, compare
// with the mesh.
void ExpectHonestVertexErrors(const TriangleMesh& mesh, const FitResult& fit) {
  const SplineModel& m = fit.model;
  ASSERT_EQ(m.parameters.rows(), mesh.num_vertices());
  auto surface = SurfaceFromModel(m);
  ASSERT_TRUE(surface.ok()) << surface.status().message();
  const Eigen::MatrixX3d f =
      m.transform.ToInput(surface->EvaluateMany(m.parameters));
  const double side =
      (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff())
          .maxCoeff();
  const Eigen::VectorXd e = 100.0 * (f - mesh.vertices).rowwise().norm() / side;
  const double rmse = std::sqrt(e.squaredNorm() / e.size());
  const RoundStatistics& r = m.statistics.final_result;
  EXPECT_NEAR(rmse, r.vertex_rmse_percent, 1e-6 * r.vertex_rmse_percent);
  EXPECT_NEAR(e.maxCoeff(), r.vertex_max_error_percent,
              1e-6 * r.vertex_max_error_percent);
}

// Distance from q to the mesh over every triangle (projection onto the
// plane when it falls inside, else the nearest edge point).
double BruteForceDistance(const TriangleMesh& mesh, const Eigen::Vector3d& q) {
  auto segment = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d d = b - a;
    const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (q - a - t * d).norm();
  };
  double best = 1e300;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.squaredNorm() > 0)) continue;
    const Eigen::Vector3d u = n.normalized();
    const Eigen::Vector3d p = q - u * u.dot(q - a);
    if ((b - a).cross(p - a).dot(u) >= 0 && (c - b).cross(p - b).dot(u) >= 0 &&
        (a - c).cross(p - c).dot(u) >= 0) {
      best = std::min(best, (q - p).norm());
    } else {
      best = std::min({best, segment(a, b), segment(b, c), segment(c, a)});
    }
  }
  return best;
}

// The surface -> mesh half of the reported error against brute force at
// random sphere points (area-weighted by |du x dv|), in input coordinates.
void ExpectHonestSurfaceErrors(const TriangleMesh& mesh, const FitResult& fit,
                               int points) {
  auto surface = SurfaceFromModel(fit.model);
  ASSERT_TRUE(surface.ok());
  const double side =
      (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff())
          .maxCoeff();
  std::mt19937 rng(17);
  std::normal_distribution<double> gauss;
  double weight = 0, squares = 0, max = 0;
  for (int i = 0; i < points; ++i) {
    const Eigen::Vector3d p =
        Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const SurfacePoint s =
        surface->EvaluateDifferential(p, JetOrder::kGradient);
    const Eigen::Vector3d x =
        fit.model.transform.ToInput(s.position.transpose()).row(0).transpose();
    const double w = s.du.cross(s.dv).norm();
    const double e = 100 * BruteForceDistance(mesh, x) / side;
    weight += w;
    squares += w * e * e;
    max = std::max(max, e);
  }
  const RoundStatistics& r = fit.model.statistics.final_result;
  // The reported maximum is two-sided and densely sampled: at least what
  // random surface points find; the two-sided rms is at least half of the
  // surface -> mesh one (sqrt of the mean of the two mean squares).
  EXPECT_GE(r.max_error_percent, 0.95 * max);
  EXPECT_GE(r.rmse_percent, 0.9 * std::sqrt(squares / weight / 2));
}

TEST(AdaptiveFitTest, BlobbyReachesTheHonestTargetAtDegreesThreeToFive) {
  const TriangleMesh mesh = Load("blobby.off");
  for (int degree : {3, 4, 5}) {
    SCOPED_TRACE("degree " + std::to_string(degree));
    FitOptions options;
    options.degree = degree;
    options.rmse_percent = 0.1;
    auto fit = FitSphericalSpline(mesh, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
    const RoundStatistics& r = fit->model.statistics.final_result;
    EXPECT_LE(r.rmse_percent, 0.1);
    EXPECT_EQ(r.folded_area_percent, 0.0);
    EXPECT_EQ(fit->model.statistics.error_measure,
              ErrorMeasure::kDenseTwoSided);
    ExpectHonestVertexErrors(mesh, *fit);
    ExpectHonestSurfaceErrors(mesh, *fit, 3000);
  }
}

// The coarse cow (2,904 vertices) needs more control points than vertices.
// Fitted at its vertices alone, its surface strayed 141 % of the bounding
// box between them, folded over 42 % of its area, and reported 0.82 %.
// Fitted to its piecewise-linear surface, and measured densely, it follows
// the mesh everywhere; what it reports is what brute force finds.
TEST(AdaptiveFitTest, TheCoarseCowFollowsItsMeshEverywhere) {
  const TriangleMesh mesh = Load("cow.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  options.max_rounds = 4;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const RoundStatistics& r = fit->model.statistics.final_result;
  EXPECT_LT(r.max_error_percent, 2.0);
  EXPECT_LT(r.folded_area_percent, 1.0);
  if (!fit->reached_target()) {
    EXPECT_FALSE(fit->shortfall.empty());
    // The returned round is, by brute force over the rounds, the one with
    // the smallest rms among those without folds (among all when every
    // round folds), and the message names it when it is not the last.
    const std::vector<RoundStatistics>& rounds = fit->model.statistics.rounds;
    const bool any_unfolded =
        std::any_of(rounds.begin(), rounds.end(),
                    [](const auto& x) { return x.folded_area_percent == 0; });
    // (By the rounds' own measurements; the returned model's are measured
    // again densely, as a reached one's: what ExpectHonestSurfaceErrors
    // checks.)
    const RoundStatistics& kept = rounds[r.round];
    for (const RoundStatistics& other : rounds) {
      if (any_unfolded && other.folded_area_percent > 0) continue;
      EXPECT_LE(kept.rmse_percent, other.rmse_percent) << other.round;
    }
    EXPECT_NE(fit->shortfall.find("measured densely"), std::string::npos);
    const bool named =
        fit->shortfall.find("returned round " + std::to_string(r.round)) !=
        std::string::npos;
    EXPECT_EQ(named, r.round != rounds.back().round) << fit->shortfall;
  }
  ExpectHonestVertexErrors(mesh, *fit);
  ExpectHonestSurfaceErrors(mesh, *fit, 4000);
}

TEST(AdaptiveFitTest, SameInputSameBytesForAnyThreadCount) {
  const TriangleMesh mesh = Load("blobby.off");
  FitOptions options;
  options.rmse_percent = 0.02;
  options.max_rounds = 2;
  std::string bytes[2];
  for (int threads : {1, 2}) {
    options.threads = threads;
    auto fit = FitSphericalSpline(mesh, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    auto serialized = SerializeSdcb(fit->model);
    ASSERT_TRUE(serialized.ok()) << serialized.status().message();
    bytes[threads - 1] = *serialized;
  }
  EXPECT_EQ(bytes[0], bytes[1]);
}

// Each round adds max(K, knots_growth x the knots so far), truncated: with
// K = 20 and a growth of a quarter, 20, 40, 60, 80, 100, then 125, 156, ...
// The option is recorded in the model and survives the file.
TEST(AdaptiveFitTest, RoundsGrowGeometricallyPastFourTimesK) {
  FitOptions options;
  options.knots_per_round = 20;
  options.knots_growth = 0.25;
  options.rmse_percent = 0.001;  // not reached: every round is run
  options.max_rounds = 7;
  auto fit = FitSphericalSpline(Load("blobby.off"), options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const std::vector<RoundStatistics>& rounds = fit->model.statistics.rounds;
  ASSERT_GE(rounds.size(), 6u);
  const int expected[] = {20, 40, 60, 80, 100, 125, 156};
  for (size_t i = 0; i < rounds.size(); ++i) {
    EXPECT_EQ(rounds[i].knots, expected[i]) << "round " << i;
  }
  auto bytes = SerializeSdcb(fit->model);
  ASSERT_TRUE(bytes.ok());
  auto read = ParseSdcb(*bytes);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->statistics.options.knots_growth, 0.25);
  options.knots_growth = -1;
  EXPECT_EQ(FitSphericalSpline(Load("blobby.off"), options).status().code(),
            StatusCode::kInvalidArgument);
}

// A fit that meets its rms but not its Hausdorff target goes on: blobby at
// 0.1 % stops in the first round whose rms is met; asked also for half that
// round's Hausdorff distance, it adds rounds until brute force, at random
// surface points, finds nothing farther from the mesh than the target (or it
// says why not). The default target, ten times the rms, is recorded.
TEST(AdaptiveFitTest, AHausdorffTargetKeepsTheRoundsGoing) {
  const TriangleMesh mesh = Load("blobby.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto first = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(first.ok()) << first.status().message();
  ASSERT_TRUE(first->reached_target()) << first->shortfall;
  const FitStatistics& s0 = first->model.statistics;
  EXPECT_DOUBLE_EQ(s0.options.max_error_percent, 1.0);
  const double target = 0.5 * s0.final_result.max_error_percent;
  options.max_error_percent = target;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const FitStatistics& s = fit->model.statistics;
  EXPECT_GT(s.rounds.size(), s0.rounds.size());
  EXPECT_EQ(s.options.max_error_percent, target);
  if (fit->reached_target()) {
    EXPECT_LE(s.final_result.max_error_percent, target);
    EXPECT_LE(s.final_result.rmse_percent, 0.1);
  } else {
    EXPECT_NE(fit->shortfall.find("Hausdorff"), std::string::npos)
        << fit->shortfall;
  }
  ExpectHonestSurfaceErrors(mesh, *fit, 3000);
  options.max_error_percent = std::nan("");
  EXPECT_EQ(FitSphericalSpline(mesh, options).status().code(),
            StatusCode::kInvalidArgument);
}

// The 8-vertex beam: its rounds bound the mesh -> surface distance by the
// vertices' parametric residual, which its corners keep far above the target
// (0.39 % rms in the round that reaches it, where the surface is within
// 0.09 %). The round's first-order estimate (the residuals along the mesh's
// normals) meets the target, so that round is measured densely, and passes:
// the fit ends there, and brute force at random surface points agrees with
// what it reports. Before the estimate the fit went on until the knots ran
// out of room (11 rounds, 7,909 control points instead of 8 and 7,109).
TEST(AdaptiveFitTest, AFirstOrderEstimateSendsARoundToTheDenseMeasurement) {
  const TriangleMesh mesh = Load("beam.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const FitStatistics& s = fit->model.statistics;
  ASSERT_EQ(fit->round_details.size(), s.rounds.size());
  const RoundDetails& last = fit->round_details.back();
  EXPECT_GT(last.round_rmse_percent, 2 * 0.1);
  EXPECT_LE(last.estimated_rmse_percent, 0.1);
  EXPECT_TRUE(last.closest_points);
  // Every earlier round missed the target both ways, or was measured
  // densely and missed it there.
  for (size_t r = 0; r + 1 < s.rounds.size(); ++r) {
    const RoundDetails& d = fit->round_details[r];
    EXPECT_TRUE(d.closest_points ||
                std::min(d.round_rmse_percent, d.estimated_rmse_percent) > 0.1)
        << "round " << r;
  }
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_TRUE(fit->shortfall.empty());
  EXPECT_LE(s.final_result.rmse_percent, 0.1);
  EXPECT_LE(s.final_result.max_error_percent, 1.0);
  EXPECT_EQ(s.final_result.folded_area_percent, 0.0);
  ExpectHonestSurfaceErrors(mesh, *fit, 3000);
}

// fandisk_large at 0.05 % (no Hausdorff limit) in three rounds: the last
// round's own rms (0.062 %) and its estimate (0.057 %) both miss the target,
// so it is not measured densely and the fit stops at the round limit. The
// returned surface, measured densely as a reached one is (0.048 %), meets the
// target: the fit says it reached it, and brute force agrees with the report.
TEST(AdaptiveFitTest, AFitThatPassesTheFinalMeasurementHasReached) {
  const TriangleMesh mesh = Load("fandisk_large.off");
  FitOptions options;
  options.rmse_percent = 0.05;
  options.max_error_percent = -1;
  options.max_rounds = 3;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const FitStatistics& s = fit->model.statistics;
  ASSERT_EQ(s.rounds.size(), 3u);
  const RoundDetails& last = fit->round_details.back();
  EXPECT_FALSE(last.closest_points);
  EXPECT_GT(std::min(last.round_rmse_percent, last.estimated_rmse_percent),
            0.05);
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_TRUE(fit->shortfall.empty());
  EXPECT_LE(s.final_result.rmse_percent, 0.05);
  EXPECT_EQ(s.final_result.folded_area_percent, 0.0);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
}

// The bear (13,826 vertices) has far more vertices than its rounds have
// control points: every round's data term (more than eight vertices per
// control point) is thinned to the knots' density (about 12 rows per control
// point kept, well under half of the full quadrature), and the fit still
// reaches its target with errors that brute force confirms, the paper's vertex
// measure recomputed at every vertex.
TEST(AdaptiveFitTest, ADenseMeshIsFittedOnRowsTiedToItsKnots) {
  const TriangleMesh mesh = Load("bear.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  const FitStatistics& s = fit->model.statistics;
  for (size_t r = 0; r < s.rounds.size(); ++r) {
    const RoundDetails& d = fit->round_details[r];
    EXPECT_LT(d.data_samples, d.unthinned_samples / 2) << "round " << r;
    EXPECT_LE(d.data_samples, 16 * s.rounds[r].control_points) << "round " << r;
    EXPECT_GE(d.unthinned_samples, mesh.num_vertices()) << "round " << r;
  }
  EXPECT_EQ(s.options.thinned_cells_per_spacing, 4.0);
  EXPECT_LE(s.final_result.rmse_percent, 0.1);
  EXPECT_EQ(s.final_result.folded_area_percent, 0.0);
  ExpectHonestVertexErrors(mesh, *fit);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
}

// The cow at 0.3 % meets the rms in round 1 but folds over 0.55 % of its
// area; the rounds that place knots at the folds stop after two when the
// folded area has not halved (it was 0.45 % then), instead of running all
// five.
TEST(AdaptiveFitTest, FoldRoundsStopWhenTheFoldsDoNotShrink) {
  FitOptions options;
  options.rmse_percent = 0.3;
  auto fit = FitSphericalSpline(Load("cow.off"), options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const std::vector<RoundStatistics>& rounds = fit->model.statistics.rounds;
  // The first round within the target that folds starts the fold rounds.
  size_t began = 0;
  while (began < rounds.size() && !(rounds[began].rmse_percent <= 0.3 &&
                                    rounds[began].folded_area_percent > 0)) {
    ++began;
  }
  ASSERT_LT(began, rounds.size());
  const double start = rounds[began].folded_area_percent;
  // Each later round is a fold round; the fit ends at the first one from
  // the second on whose folds exceed half of `start` (or after five).
  size_t expected_end = began + 5;
  for (size_t r = began + 2; r < rounds.size(); ++r) {
    if (rounds[r].rmse_percent <= 0.3 &&
        rounds[r].folded_area_percent > 0.5 * start) {
      expected_end = r;
      break;
    }
  }
  EXPECT_EQ(rounds.size() - 1, expected_end);
  EXPECT_LT(rounds.size() - 1, began + 5);  // the rule, not the cap, ended it
  EXPECT_FALSE(fit->reached_target());
  EXPECT_NE(fit->shortfall.find("folds"), std::string::npos);
}

TEST(AdaptiveFitTest, WriteReadEvaluateIsBitIdentical) {
  const TriangleMesh mesh = Load("blobby.off");
  FitOptions options;
  options.max_rounds = 2;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const std::string path = testing::FreshTestDir() + "/blobby.sdcb";
  ASSERT_TRUE(WriteSdcbFile(fit->model, path).ok());
  auto read = ReadSdcbFile(path);
  ASSERT_TRUE(read.ok()) << read.status().message();
  auto before = SurfaceFromModel(fit->model);
  auto after = SurfaceFromModel(*read);
  ASSERT_TRUE(before.ok() && after.ok());
  const Eigen::MatrixX3d& u = fit->model.parameters;
  const Eigen::MatrixX3d a = before->EvaluateMany(u),
                         b = after->EvaluateMany(u);
  EXPECT_TRUE((a.array() == b.array()).all());
  const auto ja = before->EvaluateDifferentialMany(u.topRows(200));
  const auto jb = after->EvaluateDifferentialMany(u.topRows(200));
  for (size_t i = 0; i < ja.size(); ++i) {
    EXPECT_EQ(ja[i].normal, jb[i].normal);
    EXPECT_EQ(ja[i].mean_curvature, jb[i].mean_curvature);
  }
}

// tests/data/cow_round0_v1.sdcb was written by the first fitter (format
// version 1, `sdcb fit cow.off --max-rounds 1`, its errors measured at the
// vertices): it still reads, says what it measured, and its surface
// evaluated at its stored parameters reproduces the errors it reports.
TEST(AdaptiveFitTest, AVersionOneModelStillReadsAndKeepsItsWord) {
  auto model = ReadSdcbFile(testing::TestDataPath("cow_round0_v1.sdcb"));
  ASSERT_TRUE(model.ok()) << model.status().message();
  EXPECT_EQ(model->statistics.error_measure, ErrorMeasure::kVertices);
  EXPECT_EQ(model->basis_form, BasisForm::kNormalized);
  const TriangleMesh mesh = Load("cow.off");
  EXPECT_EQ(model->source.hash, HashTriangleMesh(mesh));
  FitResult as_fit;
  as_fit.model = *model;
  ExpectHonestVertexErrors(mesh, as_fit);
  // Options version 1 did not record read as "not recorded".
  EXPECT_EQ(model->statistics.options.regularization, 0.0);
  EXPECT_EQ(model->statistics.options.knots_growth, 0.0);
  EXPECT_EQ(model->statistics.options.degree, 4);
}

TEST(AdaptiveFitTest, RefusesHigherGenusAndBadOptions) {
  auto fit = FitSphericalSpline(Load("elephant.off"));
  ASSERT_FALSE(fit.ok());
  EXPECT_NE(fit.status().message().find("genus 3"), std::string::npos);
  FitOptions bad;
  bad.degree = 9;
  EXPECT_EQ(FitSphericalSpline(Load("blobby.off"), bad).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
