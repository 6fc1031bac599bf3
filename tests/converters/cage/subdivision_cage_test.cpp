// Tests of converters/cage/subdivision_cage and converters/cage/cage_deviation
// on a real model (the cow's first round, tests/data): the measured deviation
// against independent searches (limit -> spline: derivative-free search over
// spline points; spline -> limit: a mesh through OpenSubdiv Far's exact limit
// points of a 6-level uniform refinement, not Bfr), convergence, budgets and
// determinism.
#include "sdcb/converters/cage/subdivision_cage.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/far_refinement.h"
#include "testing/kept_cube.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

SphericalSpline CowSpline() {
  auto model = ReadSdcbFile(testing::TestDataPath("cow_round0_v1.sdcb"));
  EXPECT_TRUE(model.ok());
  auto spline = SurfaceFromModel(*model);
  EXPECT_TRUE(spline.ok());
  return std::move(*spline);
}

// The distance from x to the spline by derivative-free search: the nearest
// of `starts` (spline points at known directions), then grids of 11 x 11
// directions around the best, each four times finer than the last.
double SplineDistanceBySearch(const SphericalSpline& spline,
                              const Eigen::Vector3d& x,
                              const Eigen::MatrixX3d& start_directions,
                              const Eigen::MatrixX3d& start_points,
                              double radius) {
  Eigen::Index nearest;
  (start_points.rowwise() - x.transpose())
      .rowwise()
      .squaredNorm()
      .minCoeff(&nearest);
  Eigen::Vector3d p = start_directions.row(nearest).transpose();
  double best = (spline.Evaluate(p) - x).norm();
  for (int level = 0; level < 7; ++level, radius /= 4) {
    Eigen::Vector3d e_u, e_v;
    TangentFrame(p, &e_u, &e_v);
    const Eigen::Vector3d centre = p;
    for (int i = -5; i <= 5; ++i) {
      for (int j = -5; j <= 5; ++j) {
        const Eigen::Vector3d q =
            (centre + radius / 5 * (i * e_u + j * e_v)).normalized();
        const double d = (spline.Evaluate(q) - x).norm();
        if (d < best) {
          best = d;
          p = q;
        }
      }
    }
  }
  return best;
}

struct FittedCage {
  SphereCage layout;
  Eigen::MatrixX3d positions;
};

FittedCage FitUniform(const SurfaceSampler& spline, CageCellShape shape,
                      int levels) {
  FittedCage c;
  c.layout = SphereCageTopology::Create(shape, levels).cage();
  const auto scheme = shape == CageCellShape::kTriangle
                          ? SubdivisionScheme::kLoop
                          : SubdivisionScheme::kCatmullClark;
  auto limit =
      LimitSurface::Create(scheme, c.layout.num_vertices(), c.layout.faces);
  EXPECT_TRUE(limit.ok());
  CageOptions options;
  options.scheme = scheme;
  auto positions = FitCagePositions(spline, c.layout, *limit, options);
  EXPECT_TRUE(positions.ok()) << positions.status().message();
  c.positions = *positions;
  return c;
}

TEST(CageDeviationTest, AgreesWithBruteForceBothWays) {
  const SphericalSpline spline = CowSpline();
  const PiecewiseSurface pieces(spline);
  const PiecewiseSplineSampler sampler(spline, pieces);
  const FittedCage c = FitUniform(sampler, CageCellShape::kQuad, 2);
  auto limit = LimitSurface::Create(SubdivisionScheme::kCatmullClark,
                                    c.layout.num_vertices(), c.layout.faces);
  ASSERT_TRUE(limit.ok());
  CageDeviationOptions options;
  options.min_samples = 20000;
  auto d =
      MeasureCageDeviation(sampler, *limit, c.positions, c.layout, options);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_GE(d->limit_samples, 20000);
  EXPECT_GE(d->spline_samples, 20000);

  // Limit -> spline at every 150th limit sample, by derivative-free
  // search from the nearest of 163842 spline points.
  const TriangleMesh sphere = MakeIcosphere(7);
  const Eigen::MatrixX3d spline_points = spline.EvaluateMany(sphere.vertices);
  double sum_ours = 0, sum_oracle = 0;
  int compared = 0;
  for (Eigen::Index i = 0; i < d->limit_samples; i += 150, ++compared) {
    const double oracle =
        100 * SplineDistanceBySearch(spline,
                                     d->limit_sample_points.row(i).transpose(),
                                     sphere.vertices, spline_points, 0.03);
    const double ours = d->limit_sample_distance_percent[i];
    sum_ours += ours * ours;
    sum_oracle += oracle * oracle;
    // Both are distances to points of the spline (upper bounds of the true
    // distance); ours is at most slightly farther than what the search finds
    // (core/measure/surface_deviation stops refining once within 1 % of its
    // lattice image: pessimistic by design, by up to ~0.02 % here).
    EXPECT_LE(ours, 1.05 * oracle + 0.02) << "sample " << i;
  }
  const double rms_ours = std::sqrt(sum_ours / compared);
  const double rms_oracle = std::sqrt(sum_oracle / compared);
  EXPECT_NEAR(rms_ours, rms_oracle, 0.01 * rms_oracle);

  // Spline -> limit at every 20th spline sample: the closest point of the
  // mesh through Far's exact limit points of the cage refined 6 times
  // (393216 quads, chords within ~1e-6 of the limit surface), found by
  // CGAL's AABB tree.
  std::vector<std::vector<int>> faces;
  for (const auto& f : c.layout.faces) faces.emplace_back(f.begin(), f.end());
  const testing::FarRefined far =
      testing::RefineWithFar(false, c.positions, faces, 6);
  TriangleMesh far_mesh;
  far_mesh.vertices = far.limit;
  far_mesh.faces.resize(2 * far.faces.size(), 3);
  for (size_t f = 0; f < far.faces.size(); ++f) {
    const auto& q = far.faces[f];
    far_mesh.faces.row(2 * f) << q[0], q[1], q[2];
    far_mesh.faces.row(2 * f + 1) << q[0], q[2], q[3];
  }
  auto to_limit = MeshDistance::Create(far_mesh);
  ASSERT_TRUE(to_limit.ok());
  double sum_back = 0, sum_back_oracle = 0;
  int compared_back = 0;
  for (Eigen::Index i = 0; i < d->spline_samples; i += 20, ++compared_back) {
    const double ours = d->spline_sample_distance_percent[i];
    const double oracle =
        100 *
        to_limit->Find(d->spline_sample_points.row(i).transpose()).distance;
    sum_back += ours * ours;
    sum_back_oracle += oracle * oracle;
    // Never flattering (the chords are within ~0.01 % of the limit); at
    // most slightly pessimistic (the foot point searched in one face).
    EXPECT_GE(ours, oracle - 0.01) << "spline sample " << i;
    EXPECT_LE(ours, 1.03 * oracle + 3e-3) << "spline sample " << i;
  }
  const double oracle = std::sqrt(sum_back_oracle / compared_back);
  const double ours_back = std::sqrt(sum_back / compared_back);
  EXPECT_NEAR(ours_back, oracle, 0.01 * oracle);
  std::printf(
      "[ cow, 96 quads ] limit->spline rms %.4f%% (brute force "
      "%.4f%%), spline->limit rms %.4f%% (brute force %.4f%%)\n",
      rms_ours, rms_oracle, ours_back, oracle);
}

// Finer uniform cages fit better (the rows, the solver and the parameter
// corrections work together): the error falls by a factor per level.
TEST(SubdivisionCageTest, UniformRefinementConverges) {
  const SphericalSpline spline = CowSpline();
  const PiecewiseSurface pieces(spline);
  const PiecewiseSplineSampler sampler(spline, pieces);
  auto image = SplineImage::Create(sampler);
  ASSERT_TRUE(image.ok());
  for (CageCellShape shape : {CageCellShape::kQuad, CageCellShape::kTriangle}) {
    double previous = 0;
    for (int levels = 1; levels <= 3; ++levels) {
      const FittedCage c = FitUniform(sampler, shape, levels);
      auto limit = LimitSurface::Create(
          shape == CageCellShape::kQuad ? SubdivisionScheme::kCatmullClark
                                        : SubdivisionScheme::kLoop,
          c.layout.num_vertices(), c.layout.faces);
      CageDeviationOptions options;
      options.min_samples = 20000;
      auto d = MeasureCageDeviation(sampler, *limit, c.positions, c.layout,
                                    options, &*image);
      ASSERT_TRUE(d.ok());
      if (levels > 1) {
        EXPECT_LT(d->rms_percent, 0.7 * previous) << "levels " << levels;
      }
      previous = d->rms_percent;
    }
  }
}

TEST(SubdivisionCageTest, StopsAtTheToleranceOrTheBudget) {
  const SphericalSpline spline = CowSpline();
  CageOptions options;
  options.measure_samples = 20000;
  options.tolerance_percent = 1.0;
  auto fit = FitSubdivisionCage(spline, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_EQ(fit->stop_reason, "tolerance reached");
  EXPECT_LE(fit->rounds.back().limit_rmse_percent, 1.0);
  EXPECT_GT(fit->rounds.front().limit_rmse_percent, 1.0);
  EXPECT_NEAR(fit->deviation.rms_percent, fit->rounds.back().limit_rmse_percent,
              0.05);
  for (size_t r = 1; r < fit->rounds.size(); ++r) {
    EXPECT_LT(fit->rounds[r].limit_rmse_percent,
              fit->rounds[r - 1].limit_rmse_percent * 1.05);
  }

  options.tolerance_percent = 1e-4;
  options.max_faces = 150;
  options.scheme = SubdivisionScheme::kLoop;
  fit = FitSubdivisionCage(spline, options);
  ASSERT_TRUE(fit.ok());
  EXPECT_EQ(fit->stop_reason, "face budget reached");
  EXPECT_LE(fit->cage.layout.num_faces(), 150);
  EXPECT_EQ(fit->cage.layout.face_size, 3);

  options.max_faces = 10;  // below the icosahedron
  EXPECT_FALSE(FitSubdivisionCage(spline, options).ok());
}

TEST(SubdivisionCageTest, SameCageForAnyThreadCount) {
  const SphericalSpline spline = CowSpline();
  CageOptions options;
  options.measure_samples = 10000;
  options.max_faces = 120;
  options.tolerance_percent = 1e-3;
  StatusOr<CageFit> one = InvalidArgumentError("not run");
  tbb::task_arena single(1);
  single.execute([&] { one = FitSubdivisionCage(spline, options); });
  auto many = FitSubdivisionCage(spline, options);
  ASSERT_TRUE(one.ok() && many.ok());
  EXPECT_EQ(CageObjText(one->cage, one->cage.vertices),
            CageObjText(many->cage, many->cage.vertices));
  EXPECT_EQ(one->deviation.rms_percent, many->deviation.rms_percent);
}

// The cube fitted with its corners' knot clusters (FitOptions::keep_features):
// its Catmull-Clark cage is the cube's 8 corners, 6 quads and 12 infinitely
// sharp edges, and OpenSubdiv's Far refinement of that cage with those
// creases (the oracle, no code shared with the converter) reaches the
// closed-form cube within 0.1 % of its side; without the creases it rounds
// into a blob.
TEST(SubdivisionCageTest, TheKeptCubesCageIsItsCornersWithSharpEdges) {
  auto fit = testing::FitKeptCube();
  ASSERT_TRUE(fit.ok() && fit->features_kept);
  auto spline = SurfaceFromModel(fit->model);
  ASSERT_TRUE(spline.ok());
  CageOptions options;
  options.tolerance_percent = 0.1;
  auto cage = FitSubdivisionCage(*spline, options);
  ASSERT_TRUE(cage.ok()) << cage.status().message();
  EXPECT_EQ(cage->cage.layout.num_vertices(), 8);
  EXPECT_EQ(cage->cage.layout.num_faces(), 6);
  ASSERT_EQ(cage->cage.creases.size(), 12u);
  EXPECT_LE(cage->deviation.rms_percent, 0.1);
  std::vector<std::vector<int>> faces;
  for (const auto& f : cage->cage.layout.faces) {
    faces.push_back({f[0], f[1], f[2], f[3]});
  }
  const auto off_cube = [](const Eigen::MatrixX3d& points) {
    double worst = 0.0;
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      worst =
          std::max(worst, std::abs(points.row(i).cwiseAbs().maxCoeff() - 0.5));
    }
    return worst;
  };
  const testing::FarRefined sharp = testing::RefineWithFar(
      false, cage->cage.vertices, faces, 4, cage->cage.creases);
  ASSERT_GT(sharp.limit.rows(), 0);
  EXPECT_LT(off_cube(sharp.limit), 1e-3);  // 0.1 % of the side
  const testing::FarRefined smooth =
      testing::RefineWithFar(false, cage->cage.vertices, faces, 4);
  EXPECT_GT(off_cube(smooth.limit), 0.05);
  const std::string obj = CageObjText(cage->cage, cage->cage.vertices);
  EXPECT_NE(obj.find("t crease 2/1/0 "), std::string::npos);
}

// The volume enclosed by an OBJ's faces (fans), summed from the text alone.
double ObjVolume(const std::string& text) {
  std::istringstream in(text);
  std::vector<Eigen::Vector3d> v;
  double six_volume = 0;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string tag;
    fields >> tag;
    if (tag == "v") {
      Eigen::Vector3d p;
      fields >> p.x() >> p.y() >> p.z();
      v.push_back(p);
    } else if (tag == "f") {
      std::vector<int> f;
      int i;
      while (fields >> i) f.push_back(i - 1);
      for (size_t k = 1; k + 1 < f.size(); ++k) {
        six_volume += v[f[0]].dot(v[f[k]].cross(v[f[k + 1]]));
      }
    }
  }
  return six_volume / 6;
}

// A cage whose positions turn its layout inside out (a spline fitted to a
// mesh stored inward) is written with its faces reversed: outward.
TEST(SubdivisionCageTest, ObjFacesTurnOutward) {
  SubdivisionCage cage;
  cage.layout = SphereCageTopology::Create(CageCellShape::kQuad, 1).cage();
  const Eigen::MatrixX3d outward = cage.layout.sphere_points;
  Eigen::MatrixX3d mirrored = outward;
  mirrored.col(0) *= -1;
  const double out_volume = ObjVolume(CageObjText(cage, outward));
  const double mirrored_volume = ObjVolume(CageObjText(cage, mirrored));
  EXPECT_GT(out_volume, 3.0);  // inscribed in the unit sphere (4.19)
  EXPECT_NEAR(mirrored_volume, out_volume, 1e-12);
  EXPECT_TRUE(OutwardCageFaces(cage, outward) == cage.layout.faces);
  const auto reversed = OutwardCageFaces(cage, mirrored);
  ASSERT_EQ(reversed.size(), cage.layout.faces.size());
  EXPECT_EQ(reversed[0][0], cage.layout.faces[0][3]);
  EXPECT_EQ(reversed[0][3], cage.layout.faces[0][0]);
}

TEST(SubdivisionCageTest, ObjTextListsVerticesAndFaces) {
  SubdivisionCage cage;
  cage.layout = SphereCageTopology::Create(CageCellShape::kQuad, 0).cage();
  cage.vertices = cage.layout.sphere_points;
  const std::string text = CageObjText(cage, cage.vertices);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 8 + 6);
  EXPECT_NE(text.find("\nf 1 "), std::string::npos);  // 1-based
  EXPECT_EQ(text.find("f 0 "), std::string::npos);
}

}  // namespace
}  // namespace sdcb
