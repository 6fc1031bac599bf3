// Tests of converters/mesh/surface_mesh_export: the library call makes the
// bytes and the report `sdcb export` writes (the command line is a wrapper of
// it), the file writer writes them, options that do not go together are
// refused, progress reaches 1, and the bytes do not depend on the thread
// count. A small fitted model (blobby, rms 0.2 %) at a coarse tolerance.
#include "sdcb/converters/mesh/surface_mesh_export.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/kept_cube.h"
#include "testing/run_sdcb.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

namespace fs = std::filesystem;

class SurfaceMeshExportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per process: ctest runs the suite's tests in parallel.
    dir_ = new std::string(std::string(SDCB_TEST_TMP) +
                           "/SurfaceMeshExportTest.model." +
                           std::to_string(getpid()));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    auto mesh = ReadMesh(testing::MeshPath("blobby.off"));
    ASSERT_TRUE(mesh.ok());
    FitOptions options;
    options.rmse_percent = 0.2;
    auto fit = FitSphericalSpline(*mesh, options);
    ASSERT_TRUE(fit.ok());
    model_ = new SplineModel(fit->model);
    ASSERT_TRUE(WriteSdcbFile(*model_, *dir_ + "/blobby.sdcb").ok());
  }
  static void TearDownTestSuite() {
    delete model_;
    std::error_code ignored;
    fs::remove_all(*dir_, ignored);
    delete dir_;
  }
  static std::string* dir_;
  static SplineModel* model_;
};
std::string* SurfaceMeshExportTest::dir_ = nullptr;
SplineModel* SurfaceMeshExportTest::model_ = nullptr;

// The report's JSON without what differs between two runs (times) and what
// only the command line knows (file names).
nlohmann::json Comparable(nlohmann::json j) {
  j.erase("seconds");
  j.erase("model");
  j.erase("output");
  return j;
}

TEST_F(SurfaceMeshExportTest, LibraryMakesWhatTheCommandLineWrites) {
  struct Case {
    std::string file;
    std::vector<std::string> flags;
    SurfaceMeshExportOptions options;
  };
  std::vector<Case> cases(4);
  cases[0].file = "plain.glb";
  cases[1].file = "draco.glb";
  cases[1].flags = {"--draco"};
  cases[1].options.compression = GltfCompression::kDraco;
  cases[2].file = "curvature.ply";
  cases[2].flags = {"--colors", "curvature", "--angle", "30"};
  cases[2].options.colors = VertexColoring::kMeanCurvature;
  cases[2].options.angle_degrees = 30.0;
  cases[3].file = "meshopt.gltf";
  cases[3].flags = {"--meshopt", "--qp", "12"};
  cases[3].options.compression = GltfCompression::kMeshopt;
  cases[3].options.position_bits = 12;
  for (Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string out = *dir_ + "/" + c.file;
    std::vector<std::string> args = {
        "export",      *dir_ + "/blobby.sdcb", "-o", out,      "--json",
        out + ".json", "--tolerance",          "1",  "--quiet"};
    args.insert(args.end(), c.flags.begin(), c.flags.end());
    const auto r = testing::RunSdcb(args, *dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;

    c.options.tolerance_percent = 1.0;
    ASSERT_TRUE(ExportFormatOfExtension(fs::path(c.file).extension().string(),
                                        &c.options.format));
    const auto exported = ExportSurfaceMesh(*model_, c.options);
    ASSERT_TRUE(exported.ok()) << exported.status().message();
    EXPECT_TRUE(exported->bytes == testing::ReadBytes(out));
    EXPECT_EQ(
        Comparable(SurfaceMeshExportReportToJson(exported->report)),
        Comparable(nlohmann::json::parse(testing::ReadBytes(out + ".json"))));
    EXPECT_EQ(exported->report.bytes,
              static_cast<int64_t>(exported->bytes.size()));
    EXPECT_EQ(exported->mesh.faces.rows(), exported->report.triangles);
    EXPECT_LE(exported->report.total_error_bound_percent, 1.0);
  }
}

// The tolerance holds both ways, measured as `sdcb compare` measures
// (core/measure/surface_deviation.h: CGAL's AABB tree over a lattice of the
// surface, closest points on the exact spline), 40 points per triangle on
// each side, not by the tessellator's certificate: the mesh's side too
// (the flat triangles' points to the surface), which the certificate's
// surface side does not bound.
TEST_F(SurfaceMeshExportTest, ToleranceHoldsBothWaysMeasuredByCompare) {
  auto surface = SurfaceFromModel(*model_);
  ASSERT_TRUE(surface.ok());
  for (double tolerance : {0.3, 0.05}) {
    SCOPED_TRACE(tolerance);
    SurfaceMeshExportOptions options;
    options.format = ExportFormat::kObj;
    options.tolerance_percent = tolerance;
    const auto exported = ExportSurfaceMesh(*model_, options);
    ASSERT_TRUE(exported.ok()) << exported.status().message();
    TriangleMesh mesh;
    mesh.vertices = model_->transform.ToNormalized(exported->mesh.positions);
    mesh.faces = exported->mesh.faces;
    DeviationOptions measure;
    measure.min_surface_samples = 40 * mesh.num_faces();
    measure.mesh_samples = 40 * mesh.num_faces();
    const auto d = MeasureSurfaceDeviation(*surface, mesh, measure);
    ASSERT_TRUE(d.ok()) << d.status().message();
    EXPECT_LE(d->surface_to_mesh_max_percent, tolerance);
    EXPECT_LE(d->mesh_to_surface_max_percent, tolerance);
    // Not trivially within: the mesh uses its tolerance.
    EXPECT_GE(d->hausdorff_percent, 0.7 * tolerance);
  }
}

// A model whose fit measured folds is refused at once with one sentence
// (no tolerance holds across a fold, and refining one would not end); its
// uniform mesh is still made.
TEST_F(SurfaceMeshExportTest, FoldedModelIsRefusedUnlessUniform) {
  SplineModel folded = *model_;
  folded.statistics.final_result.folded_area_percent = 0.25;
  SurfaceMeshExportOptions options;
  options.format = ExportFormat::kObj;
  options.tolerance_percent = 0.05;
  const auto refused = ExportSurfaceMesh(folded, options);
  ASSERT_EQ(refused.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(refused.status().message().find("folds over 0.25 %"),
            std::string::npos)
      << refused.status().message();
  EXPECT_EQ(refused.status().message().find('\n'), std::string::npos);
  options.uniform_vertices = 2000;
  const auto uniform = ExportSurfaceMesh(folded, options);
  ASSERT_TRUE(uniform.ok()) << uniform.status().message();
  EXPECT_GT(uniform->report.triangles, 2000);
}

TEST_F(SurfaceMeshExportTest, FileWriterWritesTheSameBytes) {
  SurfaceMeshExportOptions options;
  options.tolerance_percent = 1.0;
  options.format = ExportFormat::kObj;
  const auto exported = ExportSurfaceMesh(*model_, options);
  ASSERT_TRUE(exported.ok());
  const std::string path = *dir_ + "/written.obj";
  options.format = ExportFormat::kGlb;  // the path's extension decides
  const auto report = WriteSurfaceMeshExport(*model_, options, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(testing::ReadBytes(path) == exported->bytes);
  EXPECT_EQ(report->format, "obj");
  EXPECT_EQ(report->triangles, exported->report.triangles);

  const auto refused =
      WriteSurfaceMeshExport(*model_, options, *dir_ + "/x.step");
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(*dir_ + "/x.step"));
}

TEST_F(SurfaceMeshExportTest, OptionsThatDoNotGoTogetherAreRefused) {
  std::vector<SurfaceMeshExportOptions> bad(6);
  bad[0].format = ExportFormat::kObj;
  bad[0].compression = GltfCompression::kDraco;
  bad[1].format = ExportFormat::kStl;
  bad[1].colors = VertexColoring::kGaussianCurvature;
  bad[2].colors = VertexColoring::kDistanceToMesh;  // no mesh
  bad[3].compression = GltfCompression::kMeshopt;
  bad[3].position_bits = 17;
  bad[4].tolerance_percent = 0.0;
  // 16-bit positions alone are off by more than half of 0.002 %.
  bad[5].compression = GltfCompression::kMeshopt;
  bad[5].tolerance_percent = 0.002;
  for (size_t i = 0; i < bad.size(); ++i) {
    const auto r = ExportSurfaceMesh(*model_, bad[i]);
    EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument) << i;
  }
}

TEST_F(SurfaceMeshExportTest, ProgressRisesToOneAndBytesIgnoreThreads) {
  SurfaceMeshExportOptions options;
  options.tolerance_percent = 1.0;
  options.compression = GltfCompression::kDraco;
  std::vector<std::pair<std::string, double>> calls;
  options.progress = [&](const std::string& stage, double fraction) {
    calls.emplace_back(stage, fraction);
  };
  const auto many = ExportSurfaceMesh(*model_, options);
  ASSERT_TRUE(many.ok());
  ASSERT_GE(calls.size(), 3u);
  for (size_t i = 1; i < calls.size(); ++i) {
    EXPECT_GE(calls[i].second, calls[i - 1].second) << calls[i].first;
  }
  EXPECT_EQ(calls.back().second, 1.0);

  options.progress = nullptr;
  StatusOr<SurfaceMeshExport> one = InvalidArgumentError("not run");
  tbb::task_arena single(1);
  single.execute([&] { one = ExportSurfaceMesh(*model_, options); });
  ASSERT_TRUE(one.ok());
  EXPECT_TRUE(one->bytes == many->bytes);
}

// A cube that kept its edges follows its creases: glTF gets each corner once
// per side (24 vertices, the faces' normals: hard edges), a mesh file one
// closed mesh of the cube's 8 corners (every edge in exactly two triangles), as
// `sdcb check` needs to read it back.
TEST(SurfaceMeshExportCreases, GltfSplitsTheCornersAndMeshFilesWeldThem) {
  auto fit = testing::FitKeptCube();
  ASSERT_TRUE(fit.ok() && fit->features_kept);
  SurfaceMeshExportOptions options;
  options.format = ExportFormat::kGlb;
  auto glb = ExportSurfaceMesh(fit->model, options);
  ASSERT_TRUE(glb.ok()) << glb.status().message();
  EXPECT_EQ(glb->report.feature_arcs, 12);
  EXPECT_EQ(glb->mesh.faces.rows(), 12);
  EXPECT_EQ(glb->mesh.positions.rows(), 24);
  options.format = ExportFormat::kPly;
  auto ply = ExportSurfaceMesh(fit->model, options);
  ASSERT_TRUE(ply.ok()) << ply.status().message();
  ASSERT_EQ(ply->mesh.positions.rows(), 8);
  EXPECT_EQ(ply->report.vertices, 8);
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index f = 0; f < ply->mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = ply->mesh.faces(f, k), b = ply->mesh.faces(f, (k + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  EXPECT_EQ(uses.size(), 18u);  // 12 edges + 6 diagonals
  for (const auto& [edge, count] : uses) EXPECT_EQ(count, 2);
  for (Eigen::Index v = 0; v < 8; ++v) {
    // The input's corners (side 2), each normal the mean of three faces'.
    EXPECT_NEAR(ply->mesh.positions.row(v).cwiseAbs().minCoeff(), 1.0, 1e-3);
    EXPECT_NEAR(ply->mesh.normals.row(v).cwiseAbs().minCoeff(),
                1.0 / std::sqrt(3.0), 1e-3);
  }
}

// A model fitted to a cube stored inward (faces reversed) exports outward, as
// glTF (counter-clockwise front faces) and the mesh formats expect: the
// enclosed volume is +8 (the cube of side 2; summed here face by face, the
// divergence theorem), and every vertex normal points out of the face it
// belongs to.
TEST(SurfaceMeshExportCreases, InwardStoredCubeExportsOutward) {
  auto fit = testing::FitKeptCube(/*inward=*/true);
  ASSERT_TRUE(fit.ok() && fit->features_kept);
  for (const ExportFormat format : {ExportFormat::kGlb, ExportFormat::kObj}) {
    SurfaceMeshExportOptions options;
    options.format = format;
    auto out = ExportSurfaceMesh(fit->model, options);
    ASSERT_TRUE(out.ok()) << out.status().message();
    const SurfaceMesh& m = out->mesh;
    double six_volume = 0;
    for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
      const Eigen::Vector3d a = m.positions.row(m.faces(f, 0));
      const Eigen::Vector3d b = m.positions.row(m.faces(f, 1));
      const Eigen::Vector3d c = m.positions.row(m.faces(f, 2));
      six_volume += a.x() * (b.y() * c.z() - b.z() * c.y()) -
                    a.y() * (b.x() * c.z() - b.z() * c.x()) +
                    a.z() * (b.x() * c.y() - b.y() * c.x());
      const Eigen::Vector3d n = (b - a).cross(c - a);
      for (int k = 0; k < 3; ++k) {
        EXPECT_GT(m.normals.row(m.faces(f, k)).dot(n), 0) << "face " << f;
      }
    }
    EXPECT_NEAR(six_volume / 6, 8.0, 0.01);
  }
}

}  // namespace
}  // namespace sdcb
