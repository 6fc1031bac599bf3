// Cages of a Model (converters/cage/subdivision_cage.h FitModelCages,
// CageObjText of parts): one object per part in one OBJ, indices file-wide;
// an open part refused in one sentence.
#include <gtest/gtest.h>

#include <sstream>

#include "sdcb/converters/cage/subdivision_cage.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

Model CowParts() {
  auto cow = ReadSdcbFile(testing::TestDataPath("cow_round0_v1.sdcb"));
  EXPECT_TRUE(cow.ok());
  Model model;
  model.source = cow->source;
  for (int i = 0; i < 2; ++i) {
    model.parts.emplace_back();
    model.parts.back().spline = *cow;
    model.parts.back().spline.transform.translation.x() +=
        1.5 * i * cow->transform.scale;
  }
  model.parts[1].name = "calf";
  return model;
}

TEST(ModelCageTest, OneObjectPerPartWithFileWideIndices) {
  CageOptions options;
  options.tolerance_percent = 2.0;
  options.max_faces = 300;
  auto cages = FitModelCages(CowParts(), options);
  ASSERT_TRUE(cages.ok()) << cages.status().message();
  ASSERT_EQ(cages->size(), 2u);
  EXPECT_EQ((*cages)[0].name, "part1");
  EXPECT_EQ((*cages)[1].name, "calf");
  const Eigen::Index n0 = (*cages)[0].positions.rows();
  const Eigen::Index n1 = (*cages)[1].positions.rows();
  // The same spline moved: the same cage, moved.
  EXPECT_EQ(n0, n1);
  const std::string text = CageObjText(*cages);
  std::istringstream lines(text);
  std::string line;
  std::vector<std::string> objects;
  Eigen::Index vertices = 0, faces[2] = {0, 0};
  while (std::getline(lines, line)) {
    if (line.rfind("o ", 0) == 0) {
      objects.push_back(line.substr(2));
      // Each object's vertices come after the previous objects'.
      EXPECT_EQ(vertices, objects.size() == 1 ? 0 : n0);
    } else if (line.rfind("v ", 0) == 0) {
      ++vertices;
    } else if (line.rfind("f ", 0) == 0) {
      ASSERT_FALSE(objects.empty());
      const int part = static_cast<int>(objects.size()) - 1;
      ++faces[part];
      std::istringstream corners(line.substr(2));
      for (Eigen::Index c; corners >> c;) {
        // 1-based, within the part's own vertices.
        EXPECT_GT(c, part == 0 ? 0 : n0);
        EXPECT_LE(c, part == 0 ? n0 : n0 + n1);
      }
    }
  }
  EXPECT_EQ(objects, (std::vector<std::string>{"part1", "calf"}));
  EXPECT_EQ(vertices, n0 + n1);
  EXPECT_EQ(faces[0], (*cages)[0].fit.cage.layout.num_faces());
  EXPECT_EQ(faces[1], (*cages)[1].fit.cage.layout.num_faces());
  // One cage is CageObjText's own text.
  EXPECT_EQ(CageObjText({(*cages)[0]}),
            CageObjText((*cages)[0].fit.cage, (*cages)[0].positions));
}

TEST(ModelCageTest, OpenPartIsRefusedByName) {
  Model model = CowParts();
  TrimLoop loop;
  loop.points.resize(3, 3);
  loop.points << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  model.parts[1].trims = {loop, loop};
  auto cages = FitModelCages(model);
  ASSERT_FALSE(cages.ok());
  EXPECT_EQ(cages.status().code(), StatusCode::kInvalidInput);
  EXPECT_EQ(cages.status().message(),
            "part 2 is open (2 trim loops); cages of open parts are not "
            "supported yet");
}

}  // namespace
}  // namespace sdcb
