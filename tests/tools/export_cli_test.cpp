// sdcb export end to end: files the Khronos glTF validator accepts without a
// warning, compressed files that glTF Transform decodes to the uncompressed
// geometry, meshes that `sdcb check` accepts within the tolerance, and bad
// input refused cleanly. Needs the npm tools scripts/setup.sh installs into
// scripts/gltf_tools/node_modules.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "testing/gltf_validator.h"
#include "testing/run_sdcb.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

namespace fs = std::filesystem;
using testing::RunSdcb;

const std::string kTools = std::string(SDCB_SOURCE_DIR) + "/scripts/gltf_tools";

// Runs a shell command; returns its exit code and what it printed (stdout
// and stderr). The capture file is named by the running test: ctest runs this
// suite's tests in parallel processes, which must not share it.
int Shell(const std::string& command, std::string* out) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string file = std::string(SDCB_TEST_TMP) + "/" +
                           info->test_suite_name() + "." + info->name() +
                           ".shell";
  const int status = std::system((command + " >" + file + " 2>&1").c_str());
  *out = testing::ReadBytes(file);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class ExportCliTest : public ::testing::Test {
 protected:
  // One small fitted model for the whole suite (blobby, 1.5 s).
  static void SetUpTestSuite() {
    // One folder per process: ctest runs the suite's tests in parallel.
    dir_ = new std::string(std::string(SDCB_TEST_TMP) +
                           "/ExportCliTest.model." + std::to_string(getpid()));
    fs::create_directories(*dir_);
    model_ = new std::string(*dir_ + "/blobby.sdcb");
    const auto r = RunSdcb({"fit", testing::MeshPath("blobby.off"), "-o",
                            *model_, "--rmse", "0.2", "--quiet"},
                           *dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(*dir_, ignored);
    delete dir_;
    delete model_;
  }
  void SetUp() override {
    ASSERT_TRUE(fs::exists(kTools + "/node_modules/gltf-validator"))
        << "run scripts/setup.sh: it installs the npm glTF tools";
  }
  // Exports and returns the JSON report.
  nlohmann::json Export(const std::string& dir, const std::string& out,
                        std::vector<std::string> flags) {
    std::vector<std::string> args = {
        "export",        *model_,  "-o",
        dir + "/" + out, "--json", dir + "/" + out + ".json",
        "--angle",       "180",    "--quiet"};
    args.insert(args.end(), flags.begin(), flags.end());
    const auto r = RunSdcb(args, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(testing::ReadBytes(dir + "/" + out + ".json"));
  }
  static std::string* dir_;
  static std::string* model_;
};
std::string* ExportCliTest::dir_ = nullptr;
std::string* ExportCliTest::model_ = nullptr;

TEST_F(ExportCliTest, EveryGltfPassesTheKhronosValidator) {
  const std::string dir = testing::FreshTestDir();
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"plain.glb", {}},
      {"plain.gltf", {}},
      {"curvature.glb", {"--colors", "curvature"}},
      {"error.gltf",
       {"--colors", "error", "--mesh", testing::MeshPath("blobby.off")}},
      {"draco.glb", {"--draco"}},
      {"draco_colors.gltf", {"--draco", "--colors", "gaussian"}},
      {"meshopt.glb", {"--meshopt"}},
      {"meshopt_colors.gltf", {"--meshopt", "--colors", "curvature"}},
      {"uniform.glb", {"--uniform", "2000"}},
  };
  std::vector<std::string> files;
  for (const auto& [name, flags] : cases) {
    std::vector<std::string> f = flags;
    f.insert(f.end(), {"--tolerance", "1"});
    Export(dir, name, f);
    files.push_back(dir + "/" + name);
  }
  const std::vector<nlohmann::json> reports = testing::ValidateGltf(files, dir);
  EXPECT_EQ(reports.size(), cases.size());
  for (const nlohmann::json& j : reports) {
    EXPECT_EQ(j["errors"], 0) << j.dump();
    EXPECT_EQ(j["warnings"], 0) << j.dump();
  }
}

TEST_F(ExportCliTest, CompressedFilesDecodeToTheUncompressedGeometry) {
  const std::string dir = testing::FreshTestDir();
  Export(dir, "plain.glb", {"--tolerance", "0.5"});
  std::string out;
  ASSERT_EQ(Shell("node " + kTools + "/decode.mjs " + dir + "/plain.glb", &out),
            0)
      << out;
  const auto plain = nlohmann::json::parse(out);
  for (const std::string codec : {"draco", "meshopt"}) {
    SCOPED_TRACE(codec);
    // --qp keeps the whole tolerance for the surface: the same
    // tessellation as the plain export.
    const auto report =
        Export(dir, codec + ".glb",
               {"--tolerance", "0.5", "--" + codec, "--qp", "14"});
    const std::string file = dir + "/" + codec + ".glb";
    ASSERT_EQ(
        Shell(kTools + "/node_modules/.bin/gltf-transform inspect " + file,
              &out),
        0)
        << out;
    ASSERT_EQ(Shell("node " + kTools + "/decode.mjs " + file, &out), 0) << out;
    const auto decoded = nlohmann::json::parse(out);
    EXPECT_EQ(decoded["triangles"], plain["triangles"]);
    EXPECT_EQ(decoded["triangles"], report["triangles"]);
    // Each decoded vertex lies within the quantization error of a vertex of
    // the uncompressed export (vertices are reordered by the codecs), and
    // every uncompressed vertex has such a decoded vertex.
    const double step = report["quantization"]["step"];
    ASSERT_GT(step, 0.0);
    const double bound = std::sqrt(3.0) / 2.0 * step * 1.001 + 1e-6;
    auto nearest = [](const nlohmann::json& from, const nlohmann::json& to) {
      double worst = 0.0;
      for (const auto& p : from) {
        double best = 1e300;
        for (const auto& q : to) {
          double d2 = 0;
          for (int k = 0; k < 3; ++k) {
            const double d = p[k].get<double>() - q[k].get<double>();
            d2 += d * d;
          }
          best = std::min(best, d2);
        }
        worst = std::max(worst, std::sqrt(best));
      }
      return worst;
    };
    EXPECT_LE(nearest(decoded["positions"], plain["positions"]), bound);
    EXPECT_LE(nearest(plain["positions"], decoded["positions"]), bound);
    EXPECT_EQ(report["quantization"]["bits"], 14);
    // Without --qp the quantization share keeps the total within the
    // tolerance.
    const auto derived = Export(dir, codec + "_derived.glb",
                                {"--tolerance", "0.5", "--" + codec});
    EXPECT_LE(derived["total_error_bound_percent"].get<double>(), 0.5);
    EXPECT_LE(derived["quantization"]["error_percent"].get<double>(),
              0.05 + 1e-12);
  }
}

TEST_F(ExportCliTest, MeshoptKeepsTheToleranceWhereSixteenBitsAreCoarse) {
  // meshopt's positions have at most 16 bits: over a largest side of about
  // 1 (the normalized frame) they are off by up to sqrt(3) / 2 / 65535 =
  // 0.00132 %, more than the usual 10 % share of a 0.013 % tolerance. The
  // surface must then get less than 90 % of it, so that the measured
  // distance plus the quantization error stays within the tolerance.
  const std::string dir = testing::FreshTestDir();
  const double tolerance = 0.013;
  const auto report =
      Export(dir, "m.glb", {"--tolerance", "0.013", "--meshopt"});
  const double quantization =
      report["quantization"]["error_percent"].get<double>();
  const double surface = report["surface_tolerance_percent"].get<double>();
  EXPECT_EQ(report["quantization"]["bits"], 16);
  EXPECT_GT(quantization, 0.1 * tolerance);  // the case this is about
  EXPECT_LE(surface + quantization, tolerance);
  EXPECT_LE(report["max_distance_percent"].get<double>(), surface);
  EXPECT_LE(report["total_error_bound_percent"].get<double>(), tolerance);
}

TEST_F(ExportCliTest, MeshesPassCheckWithinTheTolerance) {
  const std::string dir = testing::FreshTestDir();
  for (const char* name : {"m.obj", "m.ply", "m.stl"}) {
    SCOPED_TRACE(name);
    const auto report = Export(dir, name, {"--tolerance", "0.5"});
    EXPECT_LE(report["max_distance_percent"].get<double>(), 0.5);
    EXPECT_GT(report["max_distance_percent"].get<double>(), 0.1);
    EXPECT_LE(report["certified_distance_percent"].get<double>(), 0.5);
    const auto r = RunSdcb({"check", dir + "/" + name}, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
}

TEST_F(ExportCliTest, BadInputExitsCleanlyLeavingNothing) {
  const std::string dir = testing::FreshTestDir();
  testing::WriteBytes(dir + "/corrupt.sdcb", "\x89SDCB\r\n\x1a garbage");
  struct Case {
    std::vector<std::string> args;
    int code;
    std::string output;
  };
  const std::vector<Case> cases = {
      {{"export", dir + "/corrupt.sdcb", "-o", dir + "/a.glb"},
       1,
       dir + "/a.glb"},
      {{"export", *model_, "-o", dir + "/b.xyz"}, 2, dir + "/b.xyz"},
      {{"export", *model_, "-o", dir + "/c.ply", "--colors", "error"},
       2,
       dir + "/c.ply"},
      {{"export", *model_, "-o", dir + "/missing/d.glb", "--tolerance", "2"},
       1,
       dir + "/missing/d.glb"},
      {{"export", *model_, "-o", dir + "/e.obj", "--draco"}, 2, dir + "/e.obj"},
      {{"export", dir + "/absent.sdcb", "-o", dir + "/f.glb"},
       1,
       dir + "/f.glb"},
      // 16-bit positions alone are off by more than half of 0.002 %.
      {{"export", *model_, "-o", dir + "/g.glb", "--meshopt", "--tolerance",
        "0.002"},
       2,
       dir + "/g.glb"},
  };
  for (const Case& c : cases) {
    const auto r = RunSdcb(c.args, dir);
    EXPECT_FALSE(r.crashed);
    EXPECT_EQ(r.exit_code, c.code) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(c.output)) << c.output;
  }
  // Nothing but the inputs and the captured streams is left in dir.
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == "corrupt.sdcb" || name[0] == '.') << name;
  }
}

}  // namespace
}  // namespace sdcb
