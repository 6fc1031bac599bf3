// `sdcb fit / check` on glTF input: the parts named after their primitives,
// malformed files refused in one line without output.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "testing/gltf_assets.h"
#include "testing/run_sdcb.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;
using testing::WriteBytes;

namespace fs = std::filesystem;

// The mesh names of a GLB, from its JSON chunk.
std::vector<std::string> GlbMeshNames(const std::string& path) {
  const std::string bytes = ReadBytes(path);
  uint32_t length;
  std::memcpy(&length, bytes.data() + 12, 4);
  const nlohmann::json json = nlohmann::json::parse(bytes.substr(20, length));
  std::vector<std::string> names;
  for (const auto& mesh : json["meshes"]) names.push_back(mesh["name"]);
  return names;
}

TEST(GltfCliTest, FitsTheDuckAndNamesItsPartsAfterThePrimitive) {
  const std::string dir = FreshTestDir();
  const std::string duck = testing::MakeDuckGlb(dir);
  if (duck.empty()) GTEST_SKIP() << "assimp or assimp-testmodels missing";
  const std::vector<std::string> meshes = GlbMeshNames(duck);
  ASSERT_EQ(meshes.size(), 1u);
  const std::string model = dir + "/duck.sdcb";
  const RunResult fit =
      RunSdcb({"fit", duck, "-o", model, "--rmse", "0.5", "--quiet"}, dir);
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  const RunResult info = RunSdcb({"info", model, "--json", "-"}, dir);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  ASSERT_FALSE(j["parts"].empty());
  for (const auto& part : j["parts"]) {
    const std::string name = part["name"];
    // The mesh's name, with " (k)" when its primitive has several parts.
    EXPECT_EQ(name.compare(0, meshes[0].size(), meshes[0]), 0) << name;
    if (j["parts"].size() > 1) {
      EXPECT_NE(name.find(" ("), std::string::npos) << name;
    } else {
      EXPECT_EQ(name, meshes[0]);
    }
  }
  const RunResult text = RunSdcb({"info", model}, dir);
  EXPECT_NE(text.out.find("\"" + meshes[0]), std::string::npos) << text.out;
}

TEST(GltfCliTest, CheckReadsBoxTexturedAsAClosedBoxOfEightVertices) {
  const std::string box = std::string(testing::kAssimpGltf2) +
                          "/BoxTextured-glTF-Binary/BoxTextured.glb";
  if (!fs::exists(box)) GTEST_SKIP() << "assimp-testmodels missing";
  const std::string dir = FreshTestDir();
  const RunResult r = RunSdcb({"check", box, "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["vertices"], 8);
  EXPECT_EQ(j["faces"], 12);
  EXPECT_EQ(j["boundary_edges"], 0);
}

// A GLB cut short, and one with an infinite position: exit 1, one line
// naming the file, no output file.
TEST(GltfCliTest, MalformedGlbExitsOneWithOneLineAndNoOutput) {
  const std::string dir = FreshTestDir();
  const std::string whole = ReadBytes(
      std::string(SDCB_SOURCE_DIR) + "/fuzz/corpus/gltf/icosahedron_plain.glb");
  ASSERT_GT(whole.size(), 200u);
  std::vector<std::string> inputs = {dir + "/cut.glb"};
  WriteBytes(inputs[0], whole.substr(0, whole.size() - 100));
  const std::string infinite = std::string(testing::kAssimpGltf2) +
                               "/BoxWithInfinites-glTF-Binary/"
                               "BoxWithInfinites.glb";
  if (fs::exists(infinite)) inputs.push_back(infinite);
  for (const std::string& input : inputs) {
    const std::string out = dir + "/out.sdcb";
    const RunResult r = RunSdcb({"fit", input, "-o", out}, dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    testing::ExpectOneSentenceNaming(r, input);
    EXPECT_FALSE(fs::exists(out));
    const RunResult check = RunSdcb({"check", input}, dir);
    EXPECT_EQ(check.exit_code, 1);
    testing::ExpectOneSentenceNaming(check, input);
  }
}

}  // namespace
}  // namespace sdcb
