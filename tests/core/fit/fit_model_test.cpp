#include "sdcb/core/fit/fit_model.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "testing/finger_mesh.h"
#include "testing/honest_fit_errors.h"
#include "testing/open_sphere.h"

namespace sdcb {
namespace {

using testing::Hole;
using testing::OpenEllipsoid;

const Eigen::Vector3d kAxes(1.0, 0.8, 0.6);

ModelFitOptions CoarseOptions() {
  ModelFitOptions o;
  o.fit.rmse_percent = 0.3;
  o.fit.threads = 2;
  return o;
}

// The surface of an open part against its mesh by brute force, at random
// sphere points: inside the trims, every point of the spline is within the
// reported Hausdorff distance of the part (the fit measured what it kept);
// and the trims are where the part's boundary is: F at every trim point is
// its boundary vertex, within the reported distance.
void ExpectHonestTrimmedPart(const TriangleMesh& mesh, const ModelPart& part,
                             int points) {
  const SplineModel& model = part.spline;
  StatusOr<SphericalSpline> surface = SurfaceFromModel(model);
  ASSERT_TRUE(surface.ok());
  StatusOr<TrimRegion> region = TrimRegion::Create(part.trims);
  ASSERT_TRUE(region.ok()) << region.status().message();
  const double side = testing::BoundingBoxSide(mesh);
  const double reported = model.statistics.final_result.max_error_percent;
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss;
  int kept = 0;
  double worst = 0;
  for (int i = 0; i < points; ++i) {
    const Eigen::Vector3d p =
        Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    if (!region->Contains(p)) continue;
    ++kept;
    const Eigen::Vector3d x =
        model.transform.ToInput(surface->Evaluate(p).transpose()).row(0);
    worst = std::max(worst, 100 * testing::BruteForceDistance(mesh, x) / side);
  }
  EXPECT_GT(kept, points / 10);
  EXPECT_LE(worst, 1.02 * reported + 1e-9);

  // The boundary: F along the trims (50 points per arc) against the part's
  // boundary edges (one triangle each), by brute force, is within the
  // reported boundary distance; a reached fit's is within its target.
  const double boundary = model.statistics.final_result.boundary_error_percent;
  ASSERT_GE(boundary, 0);
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces(f, k), b = mesh.faces(f, (k + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  double boundary_worst = 0;
  for (const TrimLoop& trim : part.trims) {
    const Eigen::Index n = trim.points.rows();
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector3d a = trim.points.row(i);
      const Eigen::Vector3d b = trim.points.row((i + 1) % n);
      for (int k = 0; k < 50; ++k) {
        const Eigen::Vector3d p = (a + (b - a) * (k / 50.0)).normalized();
        const Eigen::Vector3d x =
            model.transform.ToInput(surface->Evaluate(p).transpose()).row(0);
        double best = 1e300;
        for (const auto& [edge, count] : uses) {
          if (count != 1) continue;
          const Eigen::Vector3d e0 = mesh.vertices.row(edge.first);
          const Eigen::Vector3d e1 = mesh.vertices.row(edge.second);
          const double t = std::clamp(
              (x - e0).dot(e1 - e0) / (e1 - e0).squaredNorm(), 0.0, 1.0);
          best = std::min(best, (e0 + t * (e1 - e0) - x).norm());
        }
        boundary_worst = std::max(boundary_worst, 100 * best / side);
      }
    }
  }
  EXPECT_LE(boundary_worst, 1.02 * boundary + 1e-9);
  // CoarseOptions: rms 0.3 %, the Hausdorff target 3 %, the boundary's 1.2 %.
  if (model.statistics.reached_target) {
    EXPECT_LE(boundary, 1.2);
  }
}

TEST(FitModel, ADiskIsOnePartTrimmedAtItsOneLoop) {
  const TriangleMesh disk =
      OpenEllipsoid(3, kAxes, {{Eigen::Vector3d::UnitZ(), 0.5}});
  ASSERT_EQ(AnalyzeMeshTopology(disk)->boundary_loops, 1);
  StatusOr<ModelFit> fit = FitModel(disk, CoarseOptions());
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  ASSERT_EQ(fit->model.parts.size(), 1u);
  const ModelPart& part = fit->model.parts[0];
  ASSERT_EQ(part.trims.size(), 1u);
  EXPECT_TRUE(fit->parts[0].fit.reached_target());
  EXPECT_FALSE(fit->parts[0].report.closed);
  EXPECT_GT(fit->parts[0].fill_faces, 0);
  // The model describes the part (not its fill): its source and frame.
  EXPECT_EQ(part.spline.source.num_faces, disk.num_faces());
  EXPECT_EQ(part.spline.source.hash, HashTriangleMesh(disk));
  ExpectHonestTrimmedPart(disk, part, 4000);
}

TEST(FitModel, AnOpenPartIsTheSameForAnyThreadCount) {
  // A flat square's hole folds back over it (its fill is lifted into a
  // dome) and its rounds repair small folds next to the trims.
  TriangleMesh square;
  const int n = 12;
  square.vertices.resize((n + 1) * (n + 1), 3);
  square.faces.resize(2 * n * n, 3);
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      square.vertices.row(i * (n + 1) + j) << i, j, 0.0;
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j, b = a + n + 1;
      square.faces.row(2 * (i * n + j)) << a, b, b + 1;
      square.faces.row(2 * (i * n + j) + 1) << a, b + 1, a + 1;
    }
  }
  ModelFitOptions one = CoarseOptions(), two = CoarseOptions();
  one.fit.threads = 1;
  two.fit.threads = 2;
  StatusOr<ModelFit> a = FitModel(square, one);
  StatusOr<ModelFit> b = FitModel(square, two);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->model.parts[0].spline.control_points,
            b->model.parts[0].spline.control_points);
  EXPECT_EQ(a->model.parts[0].trims[0].points,
            b->model.parts[0].trims[0].points);
}

TEST(FitModel, ATubeHasTwoTrimsAndThreeHolesThree) {
  const TriangleMesh tube = OpenEllipsoid(
      3, kAxes,
      {{Eigen::Vector3d::UnitZ(), 0.7}, {-Eigen::Vector3d::UnitZ(), 0.7}});
  const TriangleMesh holes =
      OpenEllipsoid(3, kAxes,
                    {{Eigen::Vector3d::UnitX(), 0.9},
                     {Eigen::Vector3d::UnitY(), 0.9},
                     {Eigen::Vector3d(-1, -1, 1).normalized(), 0.9}});
  for (const auto& [mesh, loops] :
       {std::pair<const TriangleMesh*, size_t>{&tube, 2},
        std::pair<const TriangleMesh*, size_t>{&holes, 3}}) {
    ASSERT_EQ(AnalyzeMeshTopology(*mesh)->boundary_loops,
              static_cast<int>(loops));
    StatusOr<ModelFit> fit = FitModel(*mesh, CoarseOptions());
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    ASSERT_EQ(fit->model.parts.size(), 1u);
    EXPECT_EQ(fit->model.parts[0].trims.size(), loops);
    EXPECT_TRUE(fit->parts[0].fit.reached_target());
    ExpectHonestTrimmedPart(*mesh, fit->model.parts[0], 3000);
  }
}

TEST(FitModel, TwoClosedPartsAreFittedEachInItsOwnFrame) {
  TriangleMesh far = MakeIcosphere(2);
  far.vertices = (far.vertices * 0.25).rowwise() + Eigen::RowVector3d(10, 0, 0);
  const TriangleMesh both =
      testing::Concatenated(OpenEllipsoid(2, kAxes, {}), far);
  StatusOr<ModelFit> fit = FitModel(both, CoarseOptions());
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  ASSERT_EQ(fit->model.parts.size(), 2u);
  EXPECT_EQ(fit->model.source.num_faces, both.num_faces());
  // Each part's frame is its own bounding box: the far sphere's side is
  // 0.5, centred at (10, 0, 0).
  const NormalizingTransform& t = fit->model.parts[1].spline.transform;
  EXPECT_NEAR(t.scale, 0.5, 1e-12);
  EXPECT_NEAR(t.translation.x(), 10, 1e-12);
  for (const PartFit& part : fit->parts) {
    EXPECT_TRUE(part.report.closed);
    EXPECT_TRUE(part.fit.reached_target());
  }
  EXPECT_TRUE(fit->model.parts[0].trims.empty());
}

TEST(FitModel, OneClosedPartIsTheFitOfTheMesh) {
  const TriangleMesh mesh = OpenEllipsoid(2, kAxes, {});
  const ModelFitOptions options = CoarseOptions();
  StatusOr<ModelFit> model = FitModel(mesh, options);
  StatusOr<FitResult> alone = FitSphericalSpline(mesh, options.fit);
  ASSERT_TRUE(model.ok() && alone.ok());
  const SplineModel& a = model->model.parts[0].spline;
  EXPECT_EQ(a.knots, alone->model.knots);
  EXPECT_EQ(a.control_points, alone->model.control_points);
}

TEST(FitModel, APartOfHigherGenusRefusesTheMeshBeforeAnyFit) {
  // A torus of 8 x 6 quads, beside a sphere: part 2 has genus 1.
  const TriangleMesh torus = testing::GridTorus(8, 6, 3.0, 0.0);
  const TriangleMesh both =
      testing::Concatenated(OpenEllipsoid(2, kAxes, {}), torus);
  StatusOr<ModelFit> fit = FitModel(both, CoarseOptions());
  ASSERT_FALSE(fit.ok());
  EXPECT_EQ(fit.status().code(), StatusCode::kUnsupported);
  EXPECT_EQ(fit.status().message(),
            "part 2 (96 triangles) has genus 1; sdcb fits genus-0 parts");
}

// Rows of `m`: the oracle of a part's input triangles (the
// mesh's own arrays, re-indexed by hand).
TriangleMesh Rows(const TriangleMesh& m, int first_vertex, int vertices,
                  int first_face, int faces) {
  TriangleMesh out;
  out.vertices = m.vertices.middleRows(first_vertex, vertices);
  out.faces = m.faces.middleRows(first_face, faces).array() - first_vertex;
  return out;
}

TEST(FitModel, KeepUnfittableKeepsTheTorusAndTheFanAsTheyWere) {
  const TriangleMesh mesh = testing::SphereTorusFan();
  const TriangleMesh sphere = OpenEllipsoid(2, kAxes, {});
  ModelFitOptions options = CoarseOptions();
  options.keep_unfittable = true;
  StatusOr<ModelFit> fit = FitModel(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  ASSERT_EQ(fit->model.parts.size(), 3u);
  const ModelPart& fitted = fit->model.parts[0];
  EXPECT_TRUE(fitted.fitted());
  EXPECT_TRUE(fit->parts[0].fit.reached_target());
  EXPECT_FALSE(fit->parts[0].kept());
  EXPECT_TRUE(fit->reached_target());  // every fitted part
  // The sentences `sdcb check` gives those parts (docs/CLI.md).
  ASSERT_TRUE(fit->model.parts[1].kept.has_value());
  ASSERT_TRUE(fit->model.parts[2].kept.has_value());
  EXPECT_EQ(fit->model.parts[1].kept->reason,
            "part 2 (96 triangles) has genus 1; sdcb fits genus-0 parts");
  EXPECT_EQ(fit->parts[1].kept_reason, fit->model.parts[1].kept->reason);
  EXPECT_EQ(fit->model.parts[2].kept->reason.rfind("part 3 (3 triangles) is "
                                                   "not manifold",
                                                   0),
            0u)
      << fit->model.parts[2].kept->reason;
  // The kept triangles are the input's rows, exactly.
  const int nv = sphere.num_vertices(), nf = sphere.num_faces();
  const TriangleMesh torus = Rows(mesh, nv, 48, nf, 96);
  const TriangleMesh fan = Rows(mesh, nv + 48, 5, nf + 96, 3);
  EXPECT_EQ(fit->model.parts[1].kept->mesh.vertices, torus.vertices);
  EXPECT_EQ(fit->model.parts[1].kept->mesh.faces, torus.faces);
  EXPECT_EQ(fit->model.parts[2].kept->mesh.vertices, fan.vertices);
  EXPECT_EQ(fit->model.parts[2].kept->mesh.faces, fan.faces);
  EXPECT_TRUE(fit->model.parts[1].spline.control_points.rows() == 0);
  EXPECT_TRUE(ValidateModel(fit->model).ok());
}

// A part whose fit misses with a folded surface is kept as its mesh with
// keep_unfittable, the reason naming the part, the folds and the fit's
// shortfall. The finger of the thin-part test
// (testing/finger_mesh.h: it folds at lambda 1 in four rounds, no further
// fits; the same vertex order as there, as part 1) beside a sphere that
// reaches.
TEST(FitModel, KeepUnfittableKeepsAPartWhoseFitMissesFolded) {
  TriangleMesh sphere = OpenEllipsoid(2, kAxes, {});
  sphere.vertices.col(0).array() += 10.0;
  const TriangleMesh finger = testing::FingerMesh(0.15, 3.0, 0.07);
  const TriangleMesh mesh = testing::Concatenated(finger, sphere);
  ModelFitOptions options;
  options.fit.rmse_percent = 0.1;
  options.fit.max_rounds = 4;
  options.fit.retry_map_vertices = finger.num_vertices() + 1;
  options.fit.retry_lambda_factors = {};
  options.fit.threads = 2;
  options.keep_unfittable = true;
  StatusOr<ModelFit> fit = FitModel(mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  ASSERT_EQ(fit->model.parts.size(), 2u);
  EXPECT_TRUE(fit->model.parts[1].fitted());
  EXPECT_TRUE(fit->parts[1].fit.reached_target());
  const ModelPart& thin = fit->model.parts[0];
  ASSERT_TRUE(thin.kept.has_value()) << fit->parts[0].fit.shortfall;
  // The missed fit is still reported beside the kept mesh.
  EXPECT_FALSE(fit->parts[0].fit.reached_target());
  EXPECT_GT(fit->parts[0].fit.model.statistics.final_result.folded_area_percent,
            0.0);
  EXPECT_EQ(thin.kept->reason.rfind("part 1: the fit missed its targets "
                                    "with a surface folded over ",
                                    0),
            0u)
      << thin.kept->reason;
  EXPECT_NE(thin.kept->reason.find(fit->parts[0].fit.shortfall),
            std::string::npos);
  EXPECT_EQ(thin.kept->mesh.vertices, finger.vertices);
  EXPECT_EQ(thin.kept->mesh.faces, finger.faces);
  EXPECT_TRUE(fit->reached_target());  // every fitted part
  EXPECT_TRUE(ValidateModel(fit->model).ok());
}

TEST(FitModel, KeepUnfittableIsTheSameForAnyThreadCount) {
  const TriangleMesh mesh = testing::SphereTorusFan();
  ModelFitOptions one = CoarseOptions(), two = CoarseOptions();
  one.keep_unfittable = two.keep_unfittable = true;
  one.fit.threads = 1;
  two.fit.threads = 2;
  StatusOr<ModelFit> a = FitModel(mesh, one);
  StatusOr<ModelFit> b = FitModel(mesh, two);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a->model.parts.size(), b->model.parts.size());
  for (size_t i = 0; i < a->model.parts.size(); ++i) {
    const ModelPart &p = a->model.parts[i], &q = b->model.parts[i];
    EXPECT_EQ(p.kept.has_value(), q.kept.has_value());
    EXPECT_EQ(p.spline.knots, q.spline.knots);
    EXPECT_EQ(p.spline.control_points, q.spline.control_points);
    if (p.kept && q.kept) {
      EXPECT_EQ(p.kept->reason, q.kept->reason);
      EXPECT_EQ(p.kept->mesh.vertices, q.kept->mesh.vertices);
    }
  }
}

TEST(FitModel, AModelOfKeptPartsOnlyIsStillAModel) {
  ModelFitOptions options = CoarseOptions();
  options.keep_unfittable = true;
  StatusOr<ModelFit> fit =
      FitModel(testing::GridTorus(8, 6, 3.0, 0.0), options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  ASSERT_EQ(fit->model.parts.size(), 1u);
  EXPECT_TRUE(fit->model.parts[0].kept.has_value());
  EXPECT_TRUE(ValidateModel(fit->model).ok());
}

TEST(FitModel, KeepUnfittableKeepsNoPartForOptionsOutOfRange) {
  ModelFitOptions options = CoarseOptions();
  options.keep_unfittable = true;
  options.fit.rmse_percent = -1;
  StatusOr<ModelFit> fit = FitModel(testing::SphereTorusFan(), options);
  ASSERT_FALSE(fit.ok());
  EXPECT_EQ(fit.status().code(), StatusCode::kInvalidArgument);
}

TEST(FitModel, WithoutKeepUnfittableTheSameMeshIsRefused) {
  StatusOr<ModelFit> fit = FitModel(testing::SphereTorusFan(), CoarseOptions());
  ASSERT_FALSE(fit.ok());
  EXPECT_EQ(fit.status().message(),
            "part 2 (96 triangles) has genus 1; sdcb fits genus-0 parts");
}

}  // namespace
}  // namespace sdcb
