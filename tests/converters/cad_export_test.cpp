// Tests of converters/cad_patches and converters/cad_file on a real model
// (the cow's first round, tests/data). Oracles, none of them the patch
// fitter's own measurement:
// - the STEP / IGES file re-read by OpenCASCADE's readers: one valid solid,
//   closed shells, volume and area against a fine adaptive tessellation of
//   the spline (core/tessellate, its own certificate);
// - distances at >= 100K exact points of the re-read surfaces to the exact
//   spline (the fit's closest-point search, core/fit/surface_deviation), and
//   from the spline's points to the re-read surfaces (OpenCASCADE's
//   projection on the face the lattice names);
// - shared edges compared pole for pole; a brute-force normal comparison.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <map>

#include "sdcb/converters/cad_file.h"
#include "sdcb/converters/cad_patches.h"
#include "sdcb/core/fit/surface_deviation.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"
#include "sdcb/core/tessellate/surface_sampler.h"
#include "sdcb/io/sdcb_file.h"
#include "testing/occt_reread.h"
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

// Volume and area of a closed triangle mesh (divergence theorem).
void VolumeAndArea(const Eigen::MatrixX3d& v, const Eigen::MatrixX3i& f,
                   double* volume, double* area) {
  *volume = 0.0;
  *area = 0.0;
  for (Eigen::Index t = 0; t < f.rows(); ++t) {
    const Eigen::Vector3d a = v.row(f(t, 0)), b = v.row(f(t, 1)),
                          c = v.row(f(t, 2));
    *volume += a.dot(b.cross(c)) / 6.0;
    *area += 0.5 * (b - a).cross(c - a).norm();
  }
}

class CadExportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    spline_ = new SphericalSpline(CowSpline());
    CadPatchOptions options;
    options.tolerance_percent = kTolerance;
    auto fit = FitCadPatches(*spline_, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    patches_ = new CadPatchSet(std::move(*fit));
  }
  static void TearDownTestSuite() {
    delete patches_;
    delete spline_;
  }
  static constexpr double kTolerance = 0.05;
  static SphericalSpline* spline_;
  static CadPatchSet* patches_;
};
SphericalSpline* CadExportTest::spline_ = nullptr;
CadPatchSet* CadExportTest::patches_ = nullptr;

TEST_F(CadExportTest, ReachesTheToleranceAndSharesEdgesPoleForPole) {
  const CadPatchSet& p = *patches_;
  EXPECT_TRUE(p.within_tolerance);
  EXPECT_LE(p.max_deviation_percent, kTolerance);
  EXPECT_GE(p.measured_points, 100000);
  ASSERT_EQ(p.patches.size(), p.layout.faces.size());
  // Every edge of the layout: the two faces' boundary poles are the same
  // numbers, in opposite order.
  std::map<std::pair<int, int>, std::vector<Eigen::Vector3d>> seen;
  const int slots[4][4] = {
      {0, 1, 2, 3}, {3, 7, 11, 15}, {15, 14, 13, 12}, {12, 8, 4, 0}};
  int shared = 0;
  for (size_t f = 0; f < p.patches.size(); ++f) {
    for (int k = 0; k < 4; ++k) {
      const int a = p.layout.faces[f][k], b = p.layout.faces[f][(k + 1) % 4];
      std::vector<Eigen::Vector3d> poles;
      for (int q = 0; q < 4; ++q)
        poles.push_back(p.patches[f].poles[slots[k][q]]);
      auto it = seen.find({b, a});
      if (it == seen.end()) {
        seen[{a, b}] = poles;
        continue;
      }
      ++shared;
      for (int q = 0; q < 4; ++q) {
        EXPECT_EQ(poles[q], it->second[3 - q]) << "face " << f << " edge " << k;
      }
    }
  }
  EXPECT_EQ(shared * 2, static_cast<int>(p.patches.size()) * 4);
  // The largest normal jump, brute force at 65 points of every edge of the
  // first 60 faces: at most the reported figure (sampled at 33 points).
  double worst = 0.0;
  for (size_t f = 0; f < std::min<size_t>(60, p.patches.size()); ++f) {
    for (int k = 0; k < 4; ++k) {
      const int a = p.layout.faces[f][k], b = p.layout.faces[f][(k + 1) % 4];
      // The neighbour: the face with the edge b -> a.
      for (size_t g = 0; g < p.patches.size(); ++g) {
        for (int m = 0; m < 4; ++m) {
          if (p.layout.faces[g][m] != b || p.layout.faces[g][(m + 1) % 4] != a)
            continue;
          for (int s = 0; s <= 64; ++s) {
            const double t = s / 64.0;
            const Eigen::Vector2d x = QuadEdgeParameter(k, t);
            const Eigen::Vector2d y = QuadEdgeParameter(m, 1.0 - t);
            Eigen::Vector3d du, dv, eu, ev;
            const Eigen::Vector3d px =
                p.patches[f].Evaluate(x.x(), x.y(), &du, &dv);
            const Eigen::Vector3d py =
                p.patches[g].Evaluate(y.x(), y.y(), &eu, &ev);
            EXPECT_LT((px - py).norm(), 1e-12);
            const double c =
                du.cross(dv).normalized().dot(eu.cross(ev).normalized());
            worst = std::max(worst,
                             std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI);
          }
        }
      }
    }
  }
  EXPECT_LE(worst, p.max_normal_jump_degrees * 1.05 + 1e-9);
  EXPECT_GT(worst, 0.0);
}

TEST_F(CadExportTest, BudgetTooSmallReportsWhatItReached) {
  CadPatchOptions options;
  options.tolerance_percent = 1e-5;
  options.max_patches = 200;
  auto fit = FitCadPatches(*spline_, options);
  ASSERT_TRUE(fit.ok());
  EXPECT_FALSE(fit->within_tolerance);
  EXPECT_EQ(fit->stop_reason, "patch budget");
  EXPECT_GT(fit->max_deviation_percent, 1e-5);
  EXPECT_LE(static_cast<int>(fit->patches.size()), 200);
  options.max_patches = 10;
  EXPECT_FALSE(FitCadPatches(*spline_, options).ok());
}

// The STEP and IGES files re-read by OpenCASCADE against the spline.
void CheckReread(const SphericalSpline& spline, const CadPatchSet& patches,
                 const std::string& path, bool iges, double tolerance) {
  const testing::RereadShape r = testing::Reread(path, iges);
  ASSERT_TRUE(r.read) << path;
  EXPECT_EQ(r.solids, 1);
  EXPECT_EQ(r.shells, 1);
  EXPECT_EQ(r.free_edges, 0);
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.faces, static_cast<int>(patches.patches.size()));

  // The spline's volume and area from a fine adaptive tessellation.
  const PiecewiseSurface pieces(spline);
  const PiecewiseSplineSampler sampler(spline, pieces);
  TessellationOptions options;
  options.tolerance = 2e-5;
  auto t = TessellateAdaptively(sampler, options);
  ASSERT_TRUE(t.ok());
  double volume, area;
  VolumeAndArea(t->positions, t->faces, &volume, &area);
  EXPECT_NEAR(r.volume / volume, 1.0, 1e-3) << r.volume << " vs " << volume;
  EXPECT_NEAR(r.area / area, 1.0, 1e-3) << r.area << " vs " << area;

  // Re-read surfaces -> spline, at >= 100K exact surface points: the
  // mesh -> surface side of MeasureSurfaceDeviation is, at every vertex, the
  // distance to a point of the exact spline.
  const int n = static_cast<int>(std::ceil(std::sqrt(100000.0 / r.faces)));
  const testing::SurfaceLattice lattice = testing::SampleSurfaces(r, n);
  ASSERT_GE(lattice.mesh.vertices.rows(), 100000);
  DeviationOptions deviation_options;
  deviation_options.min_surface_samples = 100000;
  auto d = MeasureSurfaceDeviation(spline, lattice.mesh, deviation_options);
  ASSERT_TRUE(d.ok());
  const double to_spline = d->vertex_distance_percent.maxCoeff();
  EXPECT_LE(to_spline, tolerance);

  // Spline -> re-read surfaces: each spline sample's closest lattice point
  // names a face; OpenCASCADE projects the sample onto that face's surface
  // (or the nearest lattice vertex of the face, an exact surface point,
  // when the projection is farther).
  double to_surfaces = 0.0;
  for (Eigen::Index s = 0; s < d->surface_sample_positions.rows(); ++s) {
    const Eigen::Vector3d x = d->surface_sample_positions.row(s);
    const int triangle = d->surface_sample_mesh_face[s];
    double best =
        testing::DistanceToFace(r, lattice.triangle_face[triangle], x);
    for (int c = 0; c < 3; ++c) {
      best = std::min(
          best, (lattice.mesh.vertices.row(lattice.mesh.faces(triangle, c))
                     .transpose() -
                 x)
                    .norm());
    }
    to_surfaces = std::max(to_surfaces, 100.0 * best);
  }
  EXPECT_GE(d->surface_sample_positions.rows(), 100000);
  EXPECT_LE(to_surfaces, tolerance);
  // The fitter's parametric figure bounds both (it is the distance to the
  // spline point of the same sphere point).
  EXPECT_LE(to_spline, patches.max_deviation_percent * 1.01);
  std::printf(
      "%s: %d faces, volume %.6f (spline %.6f), area %.6f (%.6f), "
      "to spline %.5f%%, from spline %.5f%%\n",
      iges ? "IGES" : "STEP", r.faces, r.volume, volume, r.area, area,
      to_spline, to_surfaces);
}

TEST_F(CadExportTest, StepRereadIsOneValidSolidWithinTheTolerance) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/cow.step";
  auto report = WriteCadSolid(patches_->patches, patches_->layout.faces,
                              CadFormat::kStep, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(report->valid);
  EXPECT_EQ(report->free_edges, 0);
  const std::string text = testing::ReadBytes(path);
  EXPECT_NE(text.find("AUTOMOTIVE_DESIGN"), std::string::npos);  // AP214
  EXPECT_NE(text.find("B_SPLINE_SURFACE_WITH_KNOTS"), std::string::npos);
  EXPECT_NE(text.find("MANIFOLD_SOLID_BREP"), std::string::npos);
  CheckReread(*spline_, *patches_, path, false, kTolerance);
}

TEST_F(CadExportTest, IgesRereadIsOneValidSolidWithinTheTolerance) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/cow.igs";
  auto report = WriteCadSolid(patches_->patches, patches_->layout.faces,
                              CadFormat::kIges, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  CheckReread(*spline_, *patches_, path, true, kTolerance);
}

TEST_F(CadExportTest, PatchesThatDoNotCloseWriteNothing) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/open.step";
  std::vector<BicubicPatch> open(patches_->patches.begin(),
                                 patches_->patches.end() - 1);
  std::vector<std::array<int, 4>> corners(patches_->layout.faces.begin(),
                                          patches_->layout.faces.end() - 1);
  auto report = WriteCadSolid(open, corners, CadFormat::kStep, path);
  EXPECT_FALSE(report.ok());
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

}  // namespace
}  // namespace sdcb
