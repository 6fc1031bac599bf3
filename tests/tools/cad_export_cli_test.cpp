// sdcb export to STEP / IGES end to end: the files OpenCASCADE's readers
// re-read as one valid closed solid whose volume is the report's, in the
// input's coordinates (millimetres); a tolerance the patch budget cannot
// meet is exit 1 naming the achieved distance with nothing written; bad
// usage is exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "sdcb/io/sdcb_file.h"
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
  auto model = ReadSdcbFile(kModel);
  ASSERT_TRUE(model.ok());
  const double scale = model->transform.scale;
  for (const std::string name : {"cow.step", "cow.stp", "cow.igs"}) {
    const std::string out = dir + "/" + name;
    const auto r =
        RunSdcb({"export", kModel, "-o", out, "--tolerance", "0.2", "--angle",
                 "180", "--json", out + ".json", "--quiet"},
                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.out.empty());
    const auto j = nlohmann::json::parse(testing::ReadBytes(out + ".json"));
    EXPECT_EQ(j["format"], name == "cow.igs" ? "iges" : "step");
    EXPECT_EQ(j["unit"], "mm");
    EXPECT_LE(j["max_deviation_percent"].get<double>(), 0.2);
    EXPECT_GE(j["measured_points"].get<int64_t>(), 100000);
    EXPECT_TRUE(j["valid"].get<bool>());
    EXPECT_EQ(j["patch_max_deviation_percent"].size(),
              j["patches"].get<size_t>());
    const testing::RereadShape s = testing::Reread(out, name == "cow.igs");
    ASSERT_TRUE(s.read);
    EXPECT_EQ(s.solids, 1);
    EXPECT_EQ(s.free_edges, 0);
    EXPECT_TRUE(s.valid);
    EXPECT_EQ(s.faces, j["patches"].get<int>());
    EXPECT_NEAR(s.volume / j["volume"].get<double>(), 1.0, 1e-6);
    // Input coordinates: the normalized model's volume times scale^3 (the
    // cow's normalized volume is of order 0.01 .. 1, far from scale^0).
    EXPECT_GT(s.volume, 1e-3 * scale * scale * scale);
    EXPECT_LT(s.volume, scale * scale * scale);
  }
}

TEST(CadExportCliTest, UnreachableToleranceWritesNothing) {
  const std::string dir = testing::FreshTestDir();
  const std::string out = dir + "/cow.step";
  const auto r = RunSdcb({"export", kModel, "-o", out, "--tolerance", "0.00001",
                          "--max-patches", "300", "--json", out + ".json"},
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
  r = RunSdcb({"export", kModel, "-o", dir + "/a.obj", "--max-patches", "500"},
              dir);
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
