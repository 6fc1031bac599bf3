// STEP of a Model (converters/cad/cad_export.h WriteCadExport(const Model&)):
// one solid per closed part, checked by reading the file back with
// OpenCASCADE; an open part refused in one sentence with no file.
#include <gtest/gtest.h>

#include <filesystem>

#include "sdcb/converters/cad/cad_export.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/occt_reread.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

Model CowParts(int parts) {
  auto cow = ReadSdcbFile(testing::TestDataPath("cow_round0_v1.sdcb"));
  EXPECT_TRUE(cow.ok());
  Model model;
  model.source = cow->source;
  for (int i = 0; i < parts; ++i) {
    model.parts.emplace_back();
    model.parts.back().spline = *cow;
    // Side by side, apart: each part 1.5 of its size to the right.
    model.parts.back().spline.transform.translation.x() +=
        1.5 * i * cow->transform.scale;
  }
  return model;
}

CadExportOptions Options() {
  CadExportOptions options;
  options.network.tolerance_percent = 0.5;
  options.network.smoothness_degrees = 1.0;
  return options;
}

TEST(CadModelExportTest, TwoClosedPartsAreTwoSolids) {
  const std::string dir = testing::FreshTestDir();
  auto one = WriteCadExport(CowParts(1), Options(), dir + "/one.step");
  ASSERT_TRUE(one.ok()) << one.status().message();
  auto two = WriteCadExport(CowParts(2), Options(), dir + "/two.step");
  ASSERT_TRUE(two.ok()) << two.status().message();
  EXPECT_EQ(two->solids, 2);
  EXPECT_EQ(two->faces, 2 * one->faces);
  EXPECT_EQ(CadExportReportToJson(*two)["solids"], 2);
  EXPECT_FALSE(CadExportReportToJson(*one).contains("solids"));
  const testing::RereadShape a = testing::Reread(dir + "/one.step", false);
  const testing::RereadShape b = testing::Reread(dir + "/two.step", false);
  ASSERT_TRUE(a.read && b.read);
  EXPECT_EQ(a.solids, 1);
  EXPECT_EQ(b.solids, 2);
  EXPECT_EQ(b.faces, 2 * a.faces);
  EXPECT_EQ(b.free_edges, 0);
  EXPECT_TRUE(b.valid);
  // The same solid twice, moved: twice the volume and area.
  EXPECT_NEAR(b.volume, 2.0 * a.volume, 1e-6 * a.volume);
  EXPECT_NEAR(b.area, 2.0 * a.area, 1e-6 * a.area);
}

TEST(CadModelExportTest, OpenPartIsRefusedByNameAndNothingIsWritten) {
  const std::string dir = testing::FreshTestDir();
  Model model = CowParts(2);
  TrimLoop loop;
  loop.points.resize(3, 3);
  loop.points << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  model.parts[1].trims = {loop};
  for (const auto& [format, name] : {std::pair{CadFormat::kStep, "STEP"},
                                     std::pair{CadFormat::kIges, "IGES"}}) {
    CadExportOptions options = Options();
    options.format = format;
    const std::string path = dir + "/open." + name;
    auto report = WriteCadExport(model, options, path);
    ASSERT_FALSE(report.ok());
    EXPECT_EQ(report.status().code(), StatusCode::kInvalidInput);
    EXPECT_EQ(report.status().message(),
              std::string("part 2 is open (1 trim loop); ") + name +
                  " of open parts is not supported yet");
    EXPECT_FALSE(std::filesystem::exists(path));
  }
}

}  // namespace
}  // namespace sdcb
