// sdcb export to STEP / IGES end to end: the files OpenCASCADE's readers
// re-read as one valid closed solid whose volume is the report's, in the
// input's coordinates (millimetres); a tolerance the control point budget
// cannot meet is exit 1 naming the achieved distance with nothing written;
// bad usage is exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/occt_reread.h"
#include "testing/run_sdcb.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

namespace fs = std::filesystem;
using testing::RunSdcb;

const std::string kModel = testing::TestDataPath("cow_round0_v1.sdcb");

TEST(CadExportCliTest, StepAndIgesAreOneValidSolidInInputCoordinates) {
  const std::string dir = testing::FreshTestDir();
  // The cow's own frame has scale 1: the model is moved to millimetres of a
  // 250 mm cow away from the origin, so input coordinates are not the
  // normalized ones.
  auto model = ReadSdcbFile(kModel);
  ASSERT_TRUE(model.ok());
  model->transform.scale = 250.0;
  model->transform.translation = Eigen::Vector3d(1000.0, -500.0, 20.0);
  const std::string moved = dir + "/cow_mm.sdcb";
  ASSERT_TRUE(WriteSdcbFile(*model, moved).ok());
  const double scale = model->transform.scale;
  // The faces fitted to the distance alone (no tangent rows: the fit's
  // smoothness is the library tests' subject; here the files are).
  for (const std::string name : {"cow.step", "cow.stp", "cow.igs"}) {
    const std::string out = dir + "/" + name;
    const auto r = RunSdcb(
        {"export", moved, "-o", out, "--tolerance", "0.5",
         "--smoothness-degrees", "180", "--json", out + ".json", "--quiet"},
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.out.empty());
    const auto j = nlohmann::json::parse(testing::ReadBytes(out + ".json"));
    EXPECT_EQ(j["format"], name == "cow.igs" ? "iges" : "step");
    EXPECT_EQ(j["unit"], "mm");
    EXPECT_LE(j["max_distance_percent"].get<double>(), 0.5);
    EXPECT_GE(j["measured_points"].get<int64_t>(), 100000);
    EXPECT_TRUE(j["valid"].get<bool>());
    EXPECT_EQ(j["bytes"].get<int64_t>(),
              static_cast<int64_t>(fs::file_size(out)));
    EXPECT_EQ(j["face_max_distance_percent"].size(), j["faces"].get<size_t>());
    const testing::RereadShape s = testing::Reread(out, name == "cow.igs");
    ASSERT_TRUE(s.read);
    EXPECT_EQ(s.solids, 1);
    EXPECT_EQ(s.free_edges, 0);
    EXPECT_TRUE(s.valid);
    EXPECT_EQ(s.faces, j["faces"].get<int>());
    EXPECT_NEAR(s.volume / j["volume"].get<double>(), 1.0, 1e-6);
    // Input coordinates: the surfaces' bounding box is the input mesh's
    // (largest side `scale`, centred at `translation`) up to the fit error
    // (this first-round model is up to 3.6 % from the mesh).
    const testing::SurfaceLattice lattice = testing::SampleSurfaces(s, 4);
    const Eigen::Vector3d lo = lattice.mesh.vertices.colwise().minCoeff();
    const Eigen::Vector3d hi = lattice.mesh.vertices.colwise().maxCoeff();
    EXPECT_NEAR((hi - lo).maxCoeff() / scale, 1.0, 0.036);
    EXPECT_LT(((hi + lo) / 2 - model->transform.translation).norm(),
              0.036 * scale);
  }
  // Two runs, the same bytes (the STEP header's time stamp is fixed).
  EXPECT_TRUE(testing::ReadBytes(dir + "/cow.step") ==
              testing::ReadBytes(dir + "/cow.stp"));
}

TEST(CadExportCliTest, UnreachableToleranceWritesNothing) {
  const std::string dir = testing::FreshTestDir();
  const std::string out = dir + "/cow.step";
  const auto r =
      RunSdcb({"export", kModel, "-o", out, "--tolerance", "0.00001",
               "--max-control-points", "3000", "--json", out + ".json"},
              dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  testing::ExpectOneSentenceNaming(r, kModel);
  EXPECT_NE(r.err.find("max distance of"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nothing written"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".json"));
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == ".stdout" || name == ".stderr") << name;
  }
}

TEST(CadExportCliTest, BadUsageAndBadInput) {
  const std::string dir = testing::FreshTestDir();
  auto r = RunSdcb({"export", kModel, "-o", dir + "/a.step", "--draco"}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  r = RunSdcb({"export", kModel, "-o", dir + "/a.obj", "--max-faces", "500"},
              dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  r = RunSdcb({"export", kModel, "-o", dir + "/a.step", "--angle", "5"}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  r = RunSdcb({"export", kModel, "-o", dir + "/a.step", "--tolerance", "0"},
              dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const std::string missing = dir + "/missing.sdcb";
  r = RunSdcb({"export", missing, "-o", dir + "/a.step"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  testing::ExpectOneSentenceNaming(r, missing);
  r = RunSdcb({"export", kModel, "-o", dir + "/no/such/folder/a.step"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_FALSE(fs::exists(dir + "/a.step"));
}

}  // namespace
}  // namespace sdcb
