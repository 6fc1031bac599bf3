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
// parametric residual at the rows of the data term, which its corners keep
// above the target in round 4 (0.117 % rms, where the surface is within
// 0.060 %). The round's first-order estimate (the residuals along the
// mesh's normals, 0.076 %) meets the target, so that round is measured
// densely (and misses the Hausdorff target there: 1.37 %); the fit ends when
// a round passes, and brute force at random surface points agrees with what
// it reports.
TEST(AdaptiveFitTest, AFirstOrderEstimateSendsARoundToTheDenseMeasurement) {
  const TriangleMesh mesh = Load("beam.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const FitStatistics& s = fit->model.statistics;
  ASSERT_EQ(fit->round_details.size(), s.rounds.size());
  int sent_by_the_estimate = 0;
  for (size_t r = 0; r < s.rounds.size(); ++r) {
    const RoundDetails& d = fit->round_details[r];
    // Measured densely exactly when the bound or the estimate met the
    // target (no round of the beam folds).
    EXPECT_EQ(s.rounds[r].folded_area_percent, 0.0);
    EXPECT_EQ(d.closest_points,
              std::min(d.round_rmse_percent, d.estimated_rmse_percent) <= 0.1)
        << "round " << r;
    if (d.closest_points && d.round_rmse_percent > 0.1) {
      ++sent_by_the_estimate;
      EXPECT_LE(d.estimated_rmse_percent, 0.1);
      EXPECT_GT(d.mesh_samples, mesh.num_vertices());
      EXPECT_GE(d.mesh_to_surface_max_bound_percent, 0.0);
    }
  }
  EXPECT_GE(sent_by_the_estimate, 1);
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_TRUE(fit->shortfall.empty());
  EXPECT_LE(s.final_result.rmse_percent, 0.1);
  EXPECT_LE(s.final_result.max_error_percent, 1.0);
  EXPECT_EQ(s.final_result.folded_area_percent, 0.0);
  // The beam's error is at its edges and corners, few of the random points:
  // 3,000 of them estimate its rms 1.6 times too high (30,000: 1.05 times;
  // 3 million: 0.0242 % against the lattice's 0.0240 %).
  ExpectHonestSurfaceErrors(mesh, *fit, 30000);
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

// The cow at 0.3 % meets the rms in round 1 but folds (0.49 % of its area by
// the round's measurement). The rounds that place knots only at the folds
// (25 each) give way to an ordinary round (100) when two of them have not
// halved the folded area, and the fit ends once five of them have run and
// the surface still folds. Each round's kind is checked against the rule
// replayed over the rounds' statistics.
TEST(AdaptiveFitTest, FoldRoundsGiveWayWhenTheFoldsDoNotShrink) {
  FitOptions options;
  options.rmse_percent = 0.3;
  auto fit = FitSphericalSpline(Load("cow.off"), options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const std::vector<RoundStatistics>& rounds = fit->model.statistics.rounds;
  int fold_rounds = 0, in_a_row = 0, ordinary_after_folds = 0;
  double began = 0;
  size_t expected_end = rounds.size();
  for (size_t r = 0; r < rounds.size(); ++r) {
    const bool only_folds =
        rounds[r].rmse_percent <= 0.3 && rounds[r].folded_area_percent > 0;
    if (only_folds && in_a_row == 0) began = rounds[r].folded_area_percent;
    if (only_folds && fold_rounds >= options.max_fold_rounds) {
      expected_end = r;
      break;
    }
    const bool stay =
        in_a_row >= 2 && rounds[r].folded_area_percent > 0.5 * began;
    const bool next_folds = only_folds && !stay;
    if (r + 1 < rounds.size()) {
      EXPECT_EQ(rounds[r + 1].knots - rounds[r].knots, next_folds ? 25 : 100)
          << "round " << r + 1;
    }
    if (next_folds) {
      ++fold_rounds;
      ++in_a_row;
    } else {
      ordinary_after_folds += fold_rounds > 0 && r + 1 < rounds.size();
      in_a_row = 0;
    }
  }
  EXPECT_EQ(rounds.size() - 1, expected_end);
  EXPECT_EQ(fold_rounds, options.max_fold_rounds);
  EXPECT_GE(ordinary_after_folds, 1);
  EXPECT_FALSE(fit->reached_target());
  EXPECT_NE(fit->shortfall.find("folds"), std::string::npos);
}

// The hand at 0.1 %: every round from round 2 on folds a little (0.001 to
// 0.009 % of its area) at the narrow creases between its fingers, and round
// 1 (1,405 control points, rms 0.15 %) is the only one whose own
// measurement sees no fold. Measured densely it folds too (0.010 %), so it
// has no claim over the more accurate rounds: the fit returns the most
// accurate of all, not the coarse round.
TEST(AdaptiveFitTest,
     ARoundKeptForNotFoldingThatFoldsGivesWayToTheMostAccurate) {
  const TriangleMesh mesh = Load("hand.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  ASSERT_FALSE(fit->reached_target());
  const std::vector<RoundStatistics>& rounds = fit->model.statistics.rounds;
  const RoundStatistics& r = fit->model.statistics.final_result;
  // A round without folds in its own measurement existed, and is not it.
  const auto unfolded =
      std::find_if(rounds.begin(), rounds.end(),
                   [](const auto& x) { return x.folded_area_percent == 0; });
  ASSERT_NE(unfolded, rounds.end());
  EXPECT_NE(r.round, unfolded->round);
  // The returned round is the most accurate by the rounds' statistics, and
  // measured densely as the report says.
  for (const RoundStatistics& other : rounds) {
    EXPECT_LE(rounds[r.round].rmse_percent, other.rmse_percent) << other.round;
  }
  EXPECT_LT(r.rmse_percent, 0.1);
  EXPECT_GT(r.folded_area_percent, 0.0);
  EXPECT_NE(fit->shortfall.find("folds"), std::string::npos);
  ExpectHonestVertexErrors(mesh, *fit);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
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
  EXPECT_EQ(model->statistics.options.final_mesh_samples, 0);
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
