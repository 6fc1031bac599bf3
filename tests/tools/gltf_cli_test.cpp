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

// Octahedra as unindexed triangles (24 corners each, float32): one
// primitive of two separate ones centred at x = 0 and 3 (mesh "pair"), one
// of one at x = 0 (mesh "single", moved by its node): in their local frames
// "single" and the first of "pair" coincide.
std::string TwoMeshesThreeOctahedra() {
  std::string bytes;
  for (const float cx : {0.0f, 3.0f, 0.0f}) {
    const float v[6][3] = {{cx + 1, 0, 0}, {cx - 1, 0, 0}, {cx, 1, 0},
                           {cx, -1, 0},    {cx, 0, 1},     {cx, 0, -1}};
    const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                             {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (const auto& f : faces) {
      for (const int k : f) {
        bytes.append(reinterpret_cast<const char*>(v[k]), 12);
      }
    }
  }
  return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [0, 5, 0]}],
    "meshes": [{"name": "pair", "primitives": [{"attributes": {"POSITION": 0}}]},
               {"name": "single", "primitives": [{"attributes": {"POSITION": 1}}]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 48, "type": "VEC3"},
      {"bufferView": 0, "byteOffset": 576, "componentType": 5126, "count": 24,
       "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteLength": 864}],
    "buffers": [{"byteLength": 864,
      "uri": "data:application/octet-stream;base64,)" +
         testing::Base64(bytes) + R"("}]})";
}

TEST(GltfCliTest, APrimitiveOfSeveralPartsNumbersThem) {
  const std::string dir = FreshTestDir();
  const std::string input = dir + "/octahedra.gltf";
  WriteBytes(input, TwoMeshesThreeOctahedra());
  const std::string model = dir + "/octahedra.sdcb";
  const RunResult fit = RunSdcb({"fit", input, "-o", model, "--rmse", "5",
                                 "--max-rounds", "1", "--quiet"},
                                dir);
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  // Parts are searched for self-intersections one by one: the coincident
  // octahedra of two primitives are no intersection.
  EXPECT_EQ(fit.err.find("intersect"), std::string::npos) << fit.err;
  const RunResult info = RunSdcb({"info", model, "--json", "-"}, dir);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  ASSERT_EQ(j["parts"].size(), 3u);
  EXPECT_EQ(j["parts"][0]["name"], "pair (1)");
  EXPECT_EQ(j["parts"][1]["name"], "pair (2)");
  EXPECT_EQ(j["parts"][2]["name"], "single");
  // Merged by position: 6 vertices, 8 faces per octahedron.
  const RunResult check = RunSdcb({"check", input, "--json", "-"}, dir);
  ASSERT_EQ(check.exit_code, 0) << check.err;
  const auto c = nlohmann::json::parse(check.out);
  EXPECT_EQ(c["vertices"], 18);
  EXPECT_EQ(c["faces"], 24);
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
