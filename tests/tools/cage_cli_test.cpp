// `sdcb cage` as pipelines use it. The written OBJ is re-read by a test-side
// parser and refined by OpenSubdiv's Far (not the Bfr stencils the converter
// fits and measures with); the distances of Far's level-4 limit points to
// the spline must agree with what the report says.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/far_refinement.h"
#include "testing/fbx_binary_reader.h"
#include "testing/run_sdcb.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::MeshPath;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;
using testing::TestDataPath;
using testing::WriteBytes;

namespace fs = std::filesystem;

// The model: the cow's first round (100 knots), kept in tests/data.
const std::string kModel = "cow_round0_v1.sdcb";

struct Obj {
  Eigen::MatrixX3d vertices;
  std::vector<std::vector<int>> faces;  // 0-based
};

// A minimal OBJ reader for "v x y z" and "f a b c ..." lines.
Obj ParseObj(const std::string& text) {
  Obj obj;
  std::vector<Eigen::RowVector3d> v;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      Eigen::RowVector3d p;
      s >> p[0] >> p[1] >> p[2];
      v.push_back(p);
    } else if (tag == "f") {
      std::vector<int> f;
      int i;
      while (s >> i) f.push_back(i - 1);
      obj.faces.push_back(f);
    }
  }
  obj.vertices.resize(v.size(), 3);
  for (size_t i = 0; i < v.size(); ++i) obj.vertices.row(i) = v[i];
  return obj;
}

class CageCliTest : public ::testing::TestWithParam<const char*> {};

TEST_P(CageCliTest, FarRefinementOfTheWrittenCageAgreesWithTheReport) {
  const std::string scheme = GetParam();
  const bool loop = scheme == "loop";
  const std::string dir = FreshTestDir();
  const std::string model_path = TestDataPath(kModel);
  const RunResult r =
      RunSdcb({"cage", model_path, "-o", dir + "/cage.obj", "--scheme", scheme,
               "--faces", "300", "--tolerance", "0.01", "--json",
               dir + "/cage.json", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/cage.json"));
  for (const char* key : {"scheme", "faces", "vertices", "limit_rmse_percent",
                          "limit_max_error_percent", "seconds"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["scheme"], scheme);
  EXPECT_LE(j["faces"].get<int>(), 300);

  const Obj obj = ParseObj(ReadBytes(dir + "/cage.obj"));
  EXPECT_EQ(obj.vertices.rows(), j["vertices"].get<int>());
  ASSERT_EQ(static_cast<int>(obj.faces.size()), j["faces"].get<int>());
  for (const auto& f : obj.faces) {
    ASSERT_EQ(f.size(), loop ? 3u : 4u);
    for (int i : f) ASSERT_TRUE(i >= 0 && i < obj.vertices.rows());
  }

  // Far: four uniform levels, then the limit positions of those vertices;
  // in the model's normalized frame, where 1 is 100 %.
  auto model = ReadSdcbFile(model_path);
  ASSERT_TRUE(model.ok());
  auto spline = SurfaceFromModel(*model);
  ASSERT_TRUE(spline.ok());
  const testing::FarRefined far = testing::RefineWithFar(
      loop, model->transform.ToNormalized(obj.vertices), obj.faces, 4);
  ASSERT_GT(far.limit.rows(), 30000);
  TriangleMesh mesh;
  mesh.vertices = far.limit;
  std::vector<Eigen::RowVector3i> triangles;
  for (const auto& f : far.faces) {
    triangles.emplace_back(f[0], f[1], f[2]);
    if (f.size() == 4) triangles.emplace_back(f[0], f[2], f[3]);
  }
  mesh.faces.resize(triangles.size(), 3);
  for (size_t t = 0; t < triangles.size(); ++t)
    mesh.faces.row(t) = triangles[t];
  DeviationOptions deviation;
  deviation.min_surface_samples = 30000;
  auto d = MeasureSurfaceDeviation(*spline, mesh, deviation);
  ASSERT_TRUE(d.ok()) << d.status().message();

  // Limit -> spline at Far's limit points, against the report's.
  const double reported_rms = j["limit_to_spline_rms_percent"];
  const double reported_max = j["limit_to_spline_max_percent"];
  EXPECT_NEAR(d->mesh_to_surface_rms_percent, reported_rms,
              0.05 * reported_rms);
  EXPECT_NEAR(d->mesh_to_surface_max_percent, reported_max,
              0.15 * reported_max);
  // Both ways (the far side on the level-4 mesh, a chord of the limit).
  const double reported = j["limit_rmse_percent"];
  EXPECT_NEAR(d->rms_percent, reported, 0.05 * reported);
  // The refined vertices themselves are within a small fraction of that of
  // their limit positions.
  const double drift =
      100 * (far.points - far.limit).rowwise().norm().maxCoeff();
  EXPECT_LT(drift, 0.5 * reported_max);
  std::printf(
      "[ %s ] faces %d: report rms %.5f%% (limit->spline %.5f%%, "
      "max %.4f%%); Far level 4: rms %.5f%% (limit->spline %.5f%%, "
      "max %.4f%%), level-4 vertices within %.5f%% of the limit\n",
      scheme.c_str(), j["faces"].get<int>(), reported, reported_rms,
      reported_max, d->rms_percent, d->mesh_to_surface_rms_percent,
      d->mesh_to_surface_max_percent, drift);
}

INSTANTIATE_TEST_SUITE_P(Schemes, CageCliTest,
                         ::testing::Values("catmark", "loop"));

// -o CAGE.fbx: the kept cube's cage as binary FBX (converters/cage/cage_fbx.h),
// read back with the test-side reader: the OBJ's vertices, 6 quads, 12 of
// its edges with crease 1.0 (the report's `creases`), the same report.
TEST(CageCliTest, FbxOutputCarriesTheKeptCubesCreases) {
  const std::string dir = FreshTestDir();
  RunResult r = RunSdcb({"fit", MeshPath("cube.off"), "-o", dir + "/cube.sdcb",
                         "--rmse", "0.1", "--quiet"},
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* ext : {"obj", "fbx"}) {
    r = RunSdcb({"cage", dir + "/cube.sdcb", "-o", dir + "/cage." + ext,
                 "--json", dir + "/" + ext + ".json", "--quiet"},
                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  auto obj_report = nlohmann::json::parse(ReadBytes(dir + "/obj.json"));
  auto fbx_report = nlohmann::json::parse(ReadBytes(dir + "/fbx.json"));
  EXPECT_EQ(fbx_report["output"], dir + "/cage.fbx");
  EXPECT_EQ(fbx_report["creases"], 12);
  for (auto* report : {&obj_report, &fbx_report}) {
    report->erase("output");
    report->erase("seconds");
    for (auto& round : (*report)["rounds"]) round.erase("seconds");
  }
  EXPECT_EQ(fbx_report, obj_report);

  const testing::FbxDocument doc =
      testing::ParseFbxBinary(ReadBytes(dir + "/cage.fbx"));
  const testing::FbxNode* geometry = doc.root.Find("Objects")->Find("Geometry");
  ASSERT_NE(geometry, nullptr);
  const Obj obj = ParseObj(ReadBytes(dir + "/cage.obj"));
  const std::vector<double>& xyz =
      geometry->Find("Vertices")->properties.at(0).numbers;
  ASSERT_EQ(xyz.size(), 3u * obj.vertices.rows());
  for (Eigen::Index i = 0; i < obj.vertices.rows(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(xyz[3 * i + c], obj.vertices(i, c));
  }
  const auto& corners =
      geometry->Find("PolygonVertexIndex")->properties.at(0).integers;
  EXPECT_EQ(corners.size(), 24u);
  EXPECT_EQ(std::count_if(corners.begin(), corners.end(),
                          [](int64_t c) { return c < 0; }),
            6);
  const testing::FbxNode* layer = geometry->Find("LayerElementEdgeCrease");
  ASSERT_NE(layer, nullptr);
  const auto& crease = layer->Find("EdgeCrease")->properties.at(0).numbers;
  EXPECT_EQ(std::count(crease.begin(), crease.end(), 1.0), 12);
}

TEST(CageCliBadInputTest, ExitOneWithOneSentenceAndNothingWritten) {
  const std::string dir = FreshTestDir();
  // A truncated model.
  const std::string bytes = ReadBytes(TestDataPath(kModel));
  WriteBytes(dir + "/truncated.sdcb", bytes.substr(0, bytes.size() / 2));
  WriteBytes(dir + "/garbage.sdcb", "not a model at all\n");
  const std::vector<std::vector<std::string>> cases = {
      {"cage", dir + "/missing.sdcb", "-o", dir + "/out.obj"},
      {"cage", dir + "/truncated.sdcb", "-o", dir + "/out.obj"},
      {"cage", dir + "/garbage.sdcb", "-o", dir + "/out.obj"},
      {"cage", TestDataPath(kModel), "-o", dir + "/no/such/dir/out.obj",
       "--faces", "50"},
      {"cage", dir + "/garbage.sdcb", "-o", dir + "/out.fbx"},
      {"cage", TestDataPath(kModel), "-o", dir + "/no/such/dir/out.fbx",
       "--faces", "50"},
  };
  for (const auto& args : cases) {
    const RunResult r = RunSdcb(args, dir);
    EXPECT_FALSE(r.crashed);
    EXPECT_EQ(r.exit_code, 1) << args[1] << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("sdcb: ", 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/out.obj"));
    EXPECT_FALSE(fs::exists(dir + "/out.fbx"));
  }
  // A report that cannot be written (a folder in its way) is refused before
  // the fit, and no cage is written either.
  fs::create_directories(dir + "/report.json");
  const RunResult r =
      RunSdcb({"cage", TestDataPath(kModel), "-o", dir + "/out.obj", "--faces",
               "30", "--json", dir + "/report.json"},
              dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/out.obj"));
  fs::remove(dir + "/report.json");
  // Nothing else left in the directory (no temporary files).
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name != "truncated.sdcb" && name != "garbage.sdcb" &&
        name != ".stdout" && name != ".stderr") {
      ++files;
      ADD_FAILURE() << "left behind: " << name;
    }
  }
  EXPECT_EQ(files, 0);
}

TEST(CageCliBadInputTest, UsageErrorsExitTwo) {
  const std::string dir = FreshTestDir();
  const std::string model = TestDataPath(kModel);
  const std::vector<std::vector<std::string>> cases = {
      {"cage", model},
      {"cage", model, "-o", dir + "/cage.ply"},
      {"cage", model, "-o", dir + "/cage.obj", "--scheme", "quads"},
      {"cage", model, "-o", dir + "/cage.obj", "--faces", "0"},
      {"cage", model, "-o", dir + "/cage.obj", "--tolerance", "-1"},
      {"cage", model, "-o", dir + "/cage.obj", "--bogus"},
      {"cage", model, "-o", dir + "/cage.abc"},
      // FBX has no Loop scheme.
      {"cage", model, "-o", dir + "/cage.fbx", "--scheme", "loop"},
  };
  for (const auto& args : cases) {
    const RunResult r = RunSdcb(args, dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/cage.obj"));
    EXPECT_FALSE(fs::exists(dir + "/cage.ply"));
    EXPECT_FALSE(fs::exists(dir + "/cage.abc"));
    EXPECT_FALSE(fs::exists(dir + "/cage.fbx"));
  }
}

}  // namespace
}  // namespace sdcb
