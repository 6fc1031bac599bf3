// The fitting driver on CGAL's meshes (in the io binary because it reads
// them): reaches the targets, errors are honest, output deterministic. The
// longer scenarios of the fit's rounds (the beam's first-order estimate,
// fandisk_large's final measurement, the bear's thinned rows, the cow's and
// the hand's fold rounds) run in tests/long/fit_scenarios_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/mesh_parts.h"
#include "sdcb/core/sphere/unit_vector_grid.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/cgal_test_mesh.h"
#include "testing/feature_normals.h"
#include "testing/finger_mesh.h"
#include "testing/honest_fit_errors.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::ExpectHonestSurfaceErrors;
using testing::ExpectHonestVertexErrors;
using testing::ReadCgalMesh;

TEST(AdaptiveFitTest, BlobbyReachesTheHonestTargetAtDegreesThreeToFive) {
  const TriangleMesh mesh = ReadCgalMesh("blobby.off");
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
  const TriangleMesh mesh = ReadCgalMesh("cow.off");
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

// armadillo.off folds in its narrow grooves in the rounds that meet the
// target (0.003-0.009 % of the area); the repair (core/fit/fold_repair.h)
// removes those folds, and the fit reaches the target with nothing folded,
// as the dense measurement and brute force at random points say. (Chosen
// because it does so in every nearby run, --lambda 0.998 to 1.002: the
// hand's and homer's folds, on thin fingers, are removed in some runs only.)
TEST(AdaptiveFitTest, SmallFoldsAreRepairedAndTheTargetReached) {
  const TriangleMesh mesh = ReadCgalMesh("armadillo.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  const RoundStatistics& final_round = fit->model.statistics.final_result;
  EXPECT_EQ(final_round.folded_area_percent, 0.0);
  const RoundDetails& last = fit->round_details.at(final_round.round);
  EXPECT_TRUE(last.fold_repaired);
  EXPECT_GT(last.folded_before_repair_percent, 0.0);
  EXPECT_GT(last.fold_repair_iterations, 0);
  testing::ExpectHonestSurfaceErrors(mesh, *fit, 2000);
  EXPECT_EQ(testing::BruteForceFoldedPoints(mesh, *fit, 1000), 0);
}

// CGAL's cactus (620 vertices): fitted on its own large triangles, the
// spline follows the map's jumps between them and folds in every round at
// the arms, and its folds do not shrink as knots are added: that fit stops
// at the first round with four times the knots of the round that folded
// least yet folding as much, and at least 0.5 % of its area (not at the
// 50,000 control-point cap, where it went without the rule: 12,944 control
// points), and says why. The fit then runs again on the input split to
// about 20,000 vertices (the same surface), which reaches the target with a
// quarter of the control points.
// What it reports is checked against the input itself: the vertex errors at
// the stored parameters of the input's vertices, the surface -> mesh errors
// and the fold test by brute force at random points.
TEST(AdaptiveFitTest, ACoarseInputThatFoldsIsFittedAgainSplit) {
  const TriangleMesh mesh = ReadCgalMesh("cactus.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  options.retry_map_vertices = 0;
  auto first = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(first.ok()) << first.status().message();
  EXPECT_FALSE(first->reached_target());
  EXPECT_GT(first->model.statistics.final_result.folded_area_percent, 0.1);
  EXPECT_EQ(first->map_vertices, mesh.num_vertices());
  EXPECT_FALSE(first->split_retry_run);
  EXPECT_NE(first->shortfall.find("its folds do not shrink as knots are added"),
            std::string::npos)
      << first->shortfall;
  const std::vector<RoundStatistics>& rounds = first->model.statistics.rounds;
  ASSERT_GE(rounds.size(), 3u);
  double least = 0.0;
  int least_knots = 0;
  for (size_t i = 0; i < rounds.size(); ++i) {
    const RoundStatistics& x = rounds[i];
    if (x.folded_area_percent <= 0) continue;
    const bool stops = least_knots > 0 && x.folded_area_percent >= least &&
                       x.knots >= 4 * least_knots &&
                       x.folded_area_percent >= 0.5;
    EXPECT_EQ(stops, i + 1 == rounds.size()) << "round " << i;
    if (least_knots == 0 || x.folded_area_percent < least) {
      least = x.folded_area_percent;
      least_knots = x.knots;
    }
  }
  EXPECT_LT(first->model.statistics.final_result.control_points, 10000);

  options.retry_map_vertices = 20000;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->split_retry_run);
  EXPECT_TRUE(fit->split_retry_returned);
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_GT(fit->map_vertices, 10000);
  EXPECT_EQ(fit->model.statistics.options.map_vertices, 20000);
  const RoundStatistics& r = fit->model.statistics.final_result;
  EXPECT_EQ(r.folded_area_percent, 0.0);
  EXPECT_LT(r.control_points,
            first->model.statistics.final_result.control_points / 2);
  EXPECT_EQ(fit->vertex_errors_percent.size(), mesh.num_vertices());
  ExpectHonestVertexErrors(mesh, *fit);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
  EXPECT_EQ(testing::BruteForceFoldedPoints(mesh, *fit, 1000), 0);
}

// A fit that reaches with more control points than the input has vertices
// is fitted again smooth on the input's split, and that fit returned when
// it reaches with fewer: CGAL's cross (40 vertices, a non-convex solid whose
// corners' clusters are tried and dropped, so its first fit is smooth on its
// own large triangles) and larger_sphere (812 vertices, a sphere).
TEST(AdaptiveFitTest, ACoarseInputWithDenseKnotsIsFittedAgainSplit) {
  for (const char* name : {"cross.off", "larger_sphere.off"}) {
    SCOPED_TRACE(name);
    const TriangleMesh mesh = ReadCgalMesh(name);
    FitOptions options;
    options.rmse_percent = 0.1;
    options.retry_map_vertices = 0;
    auto first = FitSphericalSpline(mesh, options);
    ASSERT_TRUE(first.ok()) << first.status().message();
    EXPECT_TRUE(first->reached_target()) << first->shortfall;
    EXPECT_FALSE(first->features_kept);
    EXPECT_FALSE(first->split_retry_run);
    const int first_points =
        first->model.statistics.final_result.control_points;
    EXPECT_GT(first_points, mesh.num_vertices());

    options.retry_map_vertices = 20000;
    auto fit = FitSphericalSpline(mesh, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
    EXPECT_TRUE(fit->split_retry_run);
    EXPECT_TRUE(fit->split_retry_returned);
    EXPECT_TRUE(fit->shortfall.empty());
    EXPECT_GT(fit->map_vertices, 10000);
    EXPECT_FALSE(fit->features_kept);
    const RoundStatistics& r = fit->model.statistics.final_result;
    EXPECT_EQ(r.folded_area_percent, 0.0);
    EXPECT_LT(r.control_points, first_points * 2 / 3);
    ExpectHonestVertexErrors(mesh, *fit);
    ExpectHonestSurfaceErrors(mesh, *fit, 2000);
    EXPECT_EQ(testing::BruteForceFoldedPoints(mesh, *fit, 1000), 0);
    if (std::string(name) != "cross.off") continue;
    // The cross's sharp features are still reported.
    EXPECT_GT(fit->features.edges.size(), 0u);
    // Its split fit, started early (before the first fit passed as many
    // control points as the input has vertices), is the split fit run after
    // the whole first one, capped at its control points.
    FitOptions split = options;
    split.map_vertices = 20000;
    split.keep_features = false;
    split.max_control_points = first_points;
    auto after = FitSphericalSpline(mesh, split);
    ASSERT_TRUE(after.ok()) << after.status().message();
    EXPECT_EQ(after->model.knots, fit->model.knots);
    EXPECT_EQ(after->model.control_points, fit->model.control_points);
  }
}

// An input with fewer vertices than the first fit's round 0 has control
// points: the first fit and the split fit take turns (spline_fitter.cpp,
// FitInTurns). The result is what running them one after the other gives:
// the first fit whole, then, as it reached with more control points than
// the input has vertices, the split fit capped at its control points,
// returned when it reaches with fewer.
TEST(AdaptiveFitTest, ATinyInputsTwoFitsInTurnsGiveTheFitsOneAfterTheOther) {
  // tripod.off (24 vertices) and bones.off's part 10 (69 vertices).
  auto bones = SplitIntoParts(ReadCgalMesh("bones.off"), kDefaultMaxParts);
  ASSERT_TRUE(bones.ok()) << bones.status().message();
  ASSERT_EQ(bones->size(), 26u);
  const std::pair<const char*, TriangleMesh> inputs[] = {
      {"tripod.off", ReadCgalMesh("tripod.off")},
      {"bones.off part 10", (*bones)[9].mesh}};
  int split_returned = 0;
  for (const auto& [name, mesh] : inputs) {
    SCOPED_TRACE(name);
    FitOptions options;
    options.rmse_percent = 0.1;
    auto fit = FitSphericalSpline(mesh, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
    EXPECT_TRUE(fit->split_retry_run);

    FitOptions alone = options;
    alone.retry_map_vertices = 0;
    auto first = FitSphericalSpline(mesh, alone);
    ASSERT_TRUE(first.ok()) << first.status().message();
    ASSERT_TRUE(first->reached_target()) << first->shortfall;
    const int first_points =
        first->model.statistics.final_result.control_points;
    ASSERT_GT(first->model.statistics.rounds[0].control_points,
              mesh.num_vertices());
    FitOptions split = alone;
    split.map_vertices = 20000;
    split.keep_features = false;
    split.max_control_points = first_points;
    auto second = FitSphericalSpline(mesh, split);
    ASSERT_TRUE(second.ok()) << second.status().message();
    const bool take_second =
        second->reached_target() &&
        second->model.statistics.final_result.control_points < first_points;
    const FitResult& expected = take_second ? *second : *first;
    EXPECT_EQ(fit->split_retry_returned, take_second);
    EXPECT_EQ(fit->model.knots, expected.model.knots);
    EXPECT_EQ(fit->model.control_points, expected.model.control_points);
    split_returned += take_second;
  }
  // Both outcomes are exercised: the tripod's split fit, the bone's first.
  EXPECT_EQ(split_returned, 1);
}

// A thin part that folds at lambda 1 reaches at a smaller lambda: a finger
// 20 radii long on a sphere (testing/finger_mesh.h: radius 0.15, edges
// 0.07, 3,119 vertices). At lambda 1 its map stretches the finger (median
// singular value ratio 7.9 on it) and the spline turns over in streaks
// along it (0.14 % of its area after four rounds); with lambda 0.5 the fit
// reaches in four. Four rounds at most, and no split (retry_map_vertices
// just above the input's vertices splits none of its edges), to keep the
// test short.
TEST(AdaptiveFitTest, AThinPartThatFoldsIsFittedAgainWithASmallerLambda) {
  const TriangleMesh mesh = testing::FingerMesh(0.15, 3.0, 0.07);
  FitOptions options;
  options.rmse_percent = 0.1;
  options.max_rounds = 4;
  options.retry_map_vertices = mesh.num_vertices() + 1;
  options.retry_lambda_factors = {};
  auto first = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(first.ok()) << first.status().message();
  EXPECT_FALSE(first->reached_target());
  EXPECT_FALSE(first->split_retry_run);
  EXPECT_GT(first->model.statistics.final_result.folded_area_percent, 0.0);
  EXPECT_GT(testing::BruteForceFoldedPoints(mesh, *first, 5000), 0);
  EXPECT_EQ(first->lambda_retries_run, 0);

  options.retry_lambda_factors = {0.5, 0.25, 0.15};
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_EQ(fit->lambda_retries_run, 1);  // 0.5 reached: no more run
  EXPECT_EQ(fit->model.statistics.options.lambda, 0.5);
  EXPECT_EQ(fit->map_vertices, mesh.num_vertices());
  EXPECT_EQ(fit->model.statistics.final_result.folded_area_percent, 0.0);
  EXPECT_EQ(testing::BruteForceFoldedPoints(mesh, *fit, 5000), 0);
  ExpectHonestVertexErrors(mesh, *fit);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
}

// FitOptions::map_vertices asked for directly: the sphere (162 vertices)
// parameterized and fitted split, its statistics still per input vertex.
TEST(AdaptiveFitTest, AnInputFittedSplitReportsPerInputVertex) {
  const TriangleMesh mesh = ReadCgalMesh("sphere.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  options.map_vertices = 3000;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_GT(fit->map_vertices, 1500);
  EXPECT_FALSE(fit->split_retry_run);
  EXPECT_EQ(fit->model.parameters.rows(), mesh.num_vertices());
  ExpectHonestVertexErrors(mesh, *fit);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
  // A missed target returns a kept round, measured again: split finer, its
  // rows thinned to the knots, at every vertex of the split mesh; its
  // errors are still the input vertices'.
  FitOptions missed = options;
  missed.map_vertices = 20000;
  missed.rmse_percent = 0.001;
  missed.max_rounds = 2;
  auto best = FitSphericalSpline(mesh, missed);
  ASSERT_TRUE(best.ok()) << best.status().message();
  EXPECT_FALSE(best->reached_target());
  EXPECT_LT(best->round_details.back().data_samples, best->map_vertices);
  EXPECT_EQ(best->vertex_errors_percent.size(), mesh.num_vertices());
  ExpectHonestVertexErrors(mesh, *best);
  // An input at least that fine is not split.
  options.map_vertices = mesh.num_vertices();
  auto unsplit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(unsplit.ok());
  EXPECT_EQ(unsplit->map_vertices, mesh.num_vertices());
}

// A density too peaked for the round's knots (hand.off's curvedness to the
// 16th power instead of the 4th) puts them all in a few places and the basis
// on them has a hole: the round is placed again with the density floored.
// At the 12th power the hole is a single knot outside every half-open
// support (I = 0 there, > 0 all around it), which only the coverage check
// at the knots finds (the round's dense measurement would meet it).
TEST(AdaptiveFitTest, ABasisWithAHoleIsPlacedAgain) {
  const TriangleMesh mesh = ReadCgalMesh("hand.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  options.max_rounds = 1;
  for (const auto& [alpha, retries] :
       std::vector<std::pair<double, int>>{{4, 0}, {16, 1}, {12, 1}}) {
    SCOPED_TRACE("alpha " + std::to_string(alpha));
    options.alpha = alpha;
    auto fit = FitSphericalSpline(mesh, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    EXPECT_EQ(fit->round_details[0].hole_retries, retries);
    EXPECT_TRUE(fit->model.control_points.allFinite());
  }
}

// CGAL's cube-meshed.off: 866 vertices, each of the cube's edges a straight
// chain of 16 mesh edges. Parameterized by the central projection from its
// centroid, every chain maps to one great-circle arc, so the corners'
// clusters keep it sharp, as they keep the 8-vertex cube.
TEST(AdaptiveFitTest, AFinelyMeshedCubeKeepsItsEdges) {
  const TriangleMesh mesh = ReadCgalMesh("cube-meshed.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto fit = FitSphericalSpline(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_TRUE(fit->features_kept);
  EXPECT_EQ(fit->features.curves.size(), 12u);
  EXPECT_EQ(fit->features.corners.size(), 8u);
  const RoundStatistics& r = fit->model.statistics.final_result;
  EXPECT_LE(r.control_points, 300);
  EXPECT_LE(r.max_error_percent, 0.2);
  EXPECT_EQ(r.folded_area_percent, 0.0);
  ExpectHonestSurfaceErrors(mesh, *fit, 3000);
  auto spline = SurfaceFromModel(fit->model);
  ASSERT_TRUE(spline.ok());
  const testing::FeatureNormals normals = testing::MeasureFeatureNormals(
      *spline, fit->model.transform.ToNormalized(mesh.vertices), mesh.faces,
      fit->features, 0.01, 150000);
  EXPECT_GT(normals.angles_degrees.size(), 12u * 16u);
  EXPECT_LT(normals.max_degrees, 2.0);
}

TEST(AdaptiveFitTest, SameInputSameBytesForAnyThreadCount) {
  const TriangleMesh mesh = ReadCgalMesh("blobby.off");
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
  auto fit = FitSphericalSpline(ReadCgalMesh("blobby.off"), options);
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
  EXPECT_EQ(
      FitSphericalSpline(ReadCgalMesh("blobby.off"), options).status().code(),
      StatusCode::kInvalidArgument);
}

// A fit that meets its rms but not its Hausdorff target goes on: blobby at
// 0.1 % stops in the first round whose rms is met; asked also for half that
// round's Hausdorff distance, it adds rounds until brute force, at random
// surface points, finds nothing farther from the mesh than the target (or it
// says why not). The default target, ten times the rms, is recorded.
TEST(AdaptiveFitTest, AHausdorffTargetKeepsTheRoundsGoing) {
  const TriangleMesh mesh = ReadCgalMesh("blobby.off");
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

TEST(AdaptiveFitTest, WriteReadEvaluateIsBitIdentical) {
  const TriangleMesh mesh = ReadCgalMesh("blobby.off");
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
  const TriangleMesh mesh = ReadCgalMesh("cow.off");
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
  auto fit = FitSphericalSpline(ReadCgalMesh("elephant.off"));
  ASSERT_FALSE(fit.ok());
  EXPECT_NE(fit.status().message().find("genus 3"), std::string::npos);
  FitOptions bad;
  bad.degree = 9;
  EXPECT_EQ(FitSphericalSpline(ReadCgalMesh("blobby.off"), bad).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb

namespace sdcb {
namespace {

// FitOptions::knot_grid_bits: every knot of every round is a grid point
// (checked bit for bit), the option is recorded, and the file stores the
// knots as grid codes (QKNT) and reads back to the fitted model.
TEST(AdaptiveFitTest, KnotsSnappedToTheGridAreStoredExactly) {
  FitOptions options;
  options.rmse_percent = 0.05;
  options.max_rounds = 3;
  options.knot_grid_bits = 12;
  auto fit = FitSphericalSpline(ReadCgalMesh("blobby.off"), options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const SplineModel& model = fit->model;
  for (Eigen::Index i = 0; i < model.knots.rows(); ++i) {
    ASSERT_TRUE(IsOnUnitVectorGrid(model.knots.row(i).transpose(), 12, nullptr))
        << i;
  }
  EXPECT_EQ(model.statistics.options.knot_grid_bits, 12);
  SdcbFileInfo info;
  auto bytes = SerializeSdcb(model, {false, 0}, &info);
  ASSERT_TRUE(bytes.ok()) << bytes.status().message();
  EXPECT_EQ(info.format_version, 3u);
  EXPECT_EQ(info.knot_grid_bits, 12);
  auto read = ParseSdcb(*bytes);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_TRUE((read->knots.array() == model.knots.array()).all());
  EXPECT_TRUE(
      (read->control_points.array() == model.control_points.array()).all());
  options.knot_grid_bits = 1;
  EXPECT_EQ(
      FitSphericalSpline(ReadCgalMesh("blobby.off"), options).status().code(),
      StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
