// Tests of converters/cad_patches and converters/cad_file on a real model
// (blobby.off, fitted). Oracles, none of them the patch
// fitter's own measurement:
// - the STEP / IGES file re-read by OpenCASCADE's readers: one valid solid,
//   closed shells, volume and area against the spline's fine uniform
//   tessellation and OpenCASCADE's own BRepGProp against the report's;
// - distances at >= 100K exact points of the re-read surfaces to the spline
//   (closest-point searches on the spline), and from >= 10K of the spline's
//   points to the re-read surfaces (OpenCASCADE's projection on the face
//   the lattice names);
// - shared edges compared pole for pole; a brute-force normal comparison;
// - the volume and area of patches whose exact values are known.
#include "sdcb/converters/cad_export.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <map>

#include "converters/cad_reread_oracle.h"
#include "sdcb/converters/cad_file.h"
#include "sdcb/converters/cad_patches.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"
#include "testing/occt_reread.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

// blobby.off fitted to rms 0.2 % (a few seconds): a smooth model without
// folds.
SphericalSpline BlobbySpline() {
  auto mesh = ReadMesh(testing::MeshPath("blobby.off"));
  EXPECT_TRUE(mesh.ok());
  FitOptions options;
  options.rmse_percent = 0.2;
  auto fit = FitSphericalSpline(*mesh, options);
  EXPECT_TRUE(fit.ok());
  auto spline = SurfaceFromModel(fit->model);
  EXPECT_TRUE(spline.ok());
  return std::move(*spline);
}

class CadExportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    spline_ = new SphericalSpline(BlobbySpline());
    CadPatchOptions options;
    options.tolerance_percent = kTolerance;
    options.angle_degrees = 20.0;  // fewer patches than the default 10
    auto fit = FitCadPatches(*spline_, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    patches_ = new CadPatchSet(std::move(*fit));
  }
  static void TearDownTestSuite() {
    delete patches_;
    delete spline_;
  }
  static constexpr double kTolerance = 0.2;
  static SphericalSpline* spline_;
  static CadPatchSet* patches_;
};
SphericalSpline* CadExportTest::spline_ = nullptr;
CadPatchSet* CadExportTest::patches_ = nullptr;

TEST_F(CadExportTest, ReachesTheToleranceAndSharesEdgesPoleForPole) {
  const CadPatchSet& p = *patches_;
  EXPECT_TRUE(p.within_tolerance);
  EXPECT_LE(p.max_distance_percent, kTolerance);
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
  options.max_faces = 200;
  auto fit = FitCadPatches(*spline_, options);
  ASSERT_TRUE(fit.ok());
  EXPECT_FALSE(fit->within_tolerance);
  EXPECT_EQ(fit->stop_reason, "patch budget");
  EXPECT_GT(fit->max_distance_percent, 1e-5);
  EXPECT_LE(static_cast<int>(fit->patches.size()), 200);
  options.max_faces = 10;
  EXPECT_FALSE(FitCadPatches(*spline_, options).ok());
}

// The STEP and IGES files re-read by OpenCASCADE against the spline.
void CheckReread(const SphericalSpline& spline, const CadPatchSet& patches,
                 const std::string& path, bool iges, double tolerance,
                 bool distances) {
  const testing::RereadShape r = testing::Reread(path, iges);
  ASSERT_TRUE(r.read) << path;
  EXPECT_EQ(r.solids, 1);
  EXPECT_EQ(r.shells, 1);
  EXPECT_EQ(r.free_edges, 0);
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.faces, static_cast<int>(patches.patches.size()));

  const testing::RereadComparison c = testing::CompareRereadWithSpline(
      r, spline, distances ? 100000 : 1000, distances ? 10000 : 100);
  ASSERT_TRUE(c.ok);
  EXPECT_NEAR(r.volume / c.spline_volume, 1.0, 1e-3)
      << r.volume << " vs " << c.spline_volume;
  EXPECT_NEAR(r.area / c.spline_area, 1.0, 1e-3)
      << r.area << " vs " << c.spline_area;
  // The report's volume and area (from the patches) are OpenCASCADE's.
  const PatchSetMeasures measures = MeasurePatchSet(patches.patches);
  EXPECT_NEAR(measures.volume / r.volume, 1.0, 1e-9);
  EXPECT_NEAR(measures.area / r.area, 1.0, 1e-7);
  std::printf("%s: %d faces, volume %.6f (spline %.6f), area %.6f (%.6f)\n",
              iges ? "IGES" : "STEP", r.faces, r.volume, c.spline_volume,
              r.area, c.spline_area);
  if (!distances) return;  // the same surfaces as the STEP file's
  EXPECT_GE(c.surface_points, 100000);
  EXPECT_GE(c.spline_points, 10000);
  EXPECT_LE(c.to_spline_percent, tolerance);
  EXPECT_LE(c.from_spline_percent, tolerance);
  // The fitter's parametric figure bounds both (it is the distance to the
  // spline point of the same sphere point), up to the spacing of its
  // lattice.
  EXPECT_LE(c.to_spline_percent, patches.max_distance_percent * 1.05);
  EXPECT_LE(c.from_spline_percent, patches.max_distance_percent * 1.05);
  std::printf("to spline %.5f%%, from spline %.5f%% (reported %.5f%%)\n",
              c.to_spline_percent, c.from_spline_percent,
              patches.max_distance_percent);
}

TEST_F(CadExportTest, StepRereadIsOneValidSolidWithinTheTolerance) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/blobby.step";
  auto report = WriteCadSolid(patches_->patches, patches_->layout.faces,
                              CadFormat::kStep, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(report->valid);
  EXPECT_EQ(report->free_edges, 0);
  const std::string text = testing::ReadBytes(path);
  EXPECT_NE(text.find("AUTOMOTIVE_DESIGN"), std::string::npos);  // AP214
  EXPECT_NE(text.find("B_SPLINE_SURFACE_WITH_KNOTS"), std::string::npos);
  EXPECT_NE(text.find("MANIFOLD_SOLID_BREP"), std::string::npos);
  CheckReread(*spline_, *patches_, path, false, kTolerance, true);
}

TEST_F(CadExportTest, IgesRereadIsOneValidSolidWithinTheTolerance) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/blobby.igs";
  auto report = WriteCadSolid(patches_->patches, patches_->layout.faces,
                              CadFormat::kIges, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  CheckReread(*spline_, *patches_, path, true, kTolerance, false);
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

// The library call behind `sdcb export OUT.step`: the file and its report,
// or, when the budget cannot reach the tolerance, a status naming what it
// reached and no file.
TEST(CadExportCallTest, WritesTheFileItReportsOrNothing) {
  const std::string dir = testing::FreshTestDir();
  auto model = ReadSdcbFile(testing::TestDataPath("cow_round0_v1.sdcb"));
  ASSERT_TRUE(model.ok());
  CadExportOptions options;
  options.patches.tolerance_percent = 0.5;
  options.patches.angle_degrees = 180.0;
  double last = -1.0;
  options.progress = [&](const std::string& stage, double fraction) {
    EXPECT_GE(fraction, last) << stage;
    last = fraction;
  };
  const std::string path = dir + "/cow.step";
  auto report = WriteCadExport(*model, options, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(last, 1.0);
  EXPECT_EQ(report->bytes,
            static_cast<int64_t>(std::filesystem::file_size(path)));
  EXPECT_TRUE(report->valid);
  EXPECT_LE(report->max_distance_percent, 0.5);
  EXPECT_EQ(static_cast<int>(report->face_max_distance_percent.size()),
            report->faces);
  const auto j = CadExportReportToJson(*report);
  EXPECT_EQ(j["faces"], report->faces);
  EXPECT_EQ(j["format"], "step");

  options.patches.tolerance_percent = 1e-5;
  options.patches.max_faces = 300;
  options.progress = nullptr;
  const std::string refused = dir + "/refused.step";
  report = WriteCadExport(*model, options, refused);
  EXPECT_EQ(report.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(report.status().message().find("max distance of"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(refused));
}

}  // namespace
}  // namespace sdcb
