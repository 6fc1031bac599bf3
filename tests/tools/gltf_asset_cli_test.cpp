// `sdcb fit IN.gltf` then `sdcb export -o OUT.glb`: the asset comes back
// with its scene as the input had it (nodes with names, children and
// transforms, a mesh shared by two nodes, meshes with their primitives'
// materials, images embedded), the fitted primitives filled with surfaces
// close to the input's, and the Khronos validator finds no error.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "testing/gltf_assets.h"
#include "testing/gltf_validator.h"
#include "testing/run_sdcb.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;
using testing::WriteBytes;
using Json = nlohmann::json;

// The JSON and BIN chunks of a GLB.
struct Glb {
  Json json;
  std::string bin;
};

Glb ReadGlb(const std::string& path) {
  const std::string bytes = ReadBytes(path);
  Glb glb;
  uint32_t json_length = 0;
  std::memcpy(&json_length, bytes.data() + 12, 4);
  glb.json = Json::parse(bytes.substr(20, json_length));
  const size_t bin_at = 20 + json_length;
  if (bin_at + 8 <= bytes.size()) {
    uint32_t bin_length = 0;
    std::memcpy(&bin_length, bytes.data() + bin_at, 4);
    glb.bin = bytes.substr(bin_at + 8, bin_length);
  }
  return glb;
}

// The float VEC3 values of accessor `a` (tightly packed or strided).
std::vector<std::array<float, 3>> Vec3s(const Glb& glb, int a) {
  const Json& accessor = glb.json["accessors"][a];
  const Json& view = glb.json["bufferViews"][accessor["bufferView"].get<int>()];
  const size_t stride = view.value("byteStride", 12);
  const size_t at =
      view.value("byteOffset", size_t{0}) + accessor.value("byteOffset", 0);
  std::vector<std::array<float, 3>> out(accessor["count"].get<size_t>());
  for (size_t i = 0; i < out.size(); ++i) {
    std::memcpy(out[i].data(), glb.bin.data() + at + i * stride, 12);
  }
  return out;
}

// The `components` float values of each element of accessor `a`.
std::vector<std::vector<float>> Floats(const Glb& glb, int a, int components) {
  const Json& accessor = glb.json["accessors"][a];
  const Json& view = glb.json["bufferViews"][accessor["bufferView"].get<int>()];
  const size_t stride = view.value("byteStride", 4 * components);
  const size_t at =
      view.value("byteOffset", size_t{0}) + accessor.value("byteOffset", 0);
  std::vector<std::vector<float>> out(accessor["count"].get<size_t>(),
                                      std::vector<float>(components));
  for (size_t i = 0; i < out.size(); ++i) {
    std::memcpy(out[i].data(), glb.bin.data() + at + i * stride,
                4 * components);
  }
  return out;
}

// The values of index accessor `a` (unsigned byte, short or int).
std::vector<uint32_t> Indices(const Glb& glb, int a) {
  const Json& accessor = glb.json["accessors"][a];
  const Json& view = glb.json["bufferViews"][accessor["bufferView"].get<int>()];
  const int type = accessor["componentType"].get<int>();
  const size_t size = type == 5121 ? 1 : type == 5123 ? 2 : 4;
  const size_t at =
      view.value("byteOffset", size_t{0}) + accessor.value("byteOffset", 0);
  std::vector<uint32_t> out(accessor["count"].get<size_t>(), 0);
  for (size_t i = 0; i < out.size(); ++i) {
    std::memcpy(&out[i], glb.bin.data() + at + i * size, size);
  }
  return out;
}

// The Khronos validator's report of `file`.
Json Validate(const std::string& file, const std::string& dir) {
  const std::vector<Json> reports = testing::ValidateGltf({file}, dir);
  return reports.empty() ? Json{{"errors", -1}} : reports[0];
}

// An octahedron of "radius" r around c: 6 vertices, 8 faces outward.
void AppendOctahedron(float r, float cx, std::string* bin) {
  const float v[6][3] = {{cx + r, 0, 0}, {cx - r, 0, 0}, {cx, r, 0},
                         {cx, -r, 0},    {cx, 0, r},     {cx, 0, -r}};
  bin->append(reinterpret_cast<const char*>(v), sizeof v);
}

void AppendOctahedronIndices(std::string* bin) {
  const uint16_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                            {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  bin->append(reinterpret_cast<const char*>(f), sizeof f);
}

// A scene with a root, two children that share mesh 0 (translation; TRS),
// a grandchild without a mesh, and mesh 0 of two primitives (two
// octahedra, materials 1 and 0), its buffer an external .bin.
std::string WriteSharedMeshScene(const std::string& dir) {
  std::string bin;
  AppendOctahedron(1.0f, 0.0f, &bin);  // 72 bytes at 0
  AppendOctahedron(0.5f, 3.0f, &bin);  // 72 bytes at 72
  AppendOctahedronIndices(&bin);       // 48 bytes at 144
  WriteBytes(dir + "/scene.bin", bin);
  Json j = Json::parse(R"({
    "asset": {"version": "2.0", "generator": "hand"},
    "scene": 0,
    "scenes": [{"name": "S", "nodes": [0]}],
    "nodes": [
      {"name": "Root", "children": [1, 2]},
      {"name": "Left", "mesh": 0, "translation": [-4, 0, 0]},
      {"name": "Right", "mesh": 0, "children": [3],
       "rotation": [0, 0.7071068, 0, 0.7071068], "scale": [2, 2, 2]},
      {"name": "Marker", "translation": [0, 1, 0]}
    ],
    "meshes": [{"name": "Pair", "primitives": [
      {"attributes": {"POSITION": 0}, "indices": 2, "material": 1},
      {"attributes": {"POSITION": 1}, "indices": 2, "material": 0}]}],
    "materials": [
      {"name": "Red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}},
      {"name": "Blue", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 1, 1]}}
    ],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
       "min": [-1, -1, -1], "max": [1, 1, 1]},
      {"bufferView": 0, "byteOffset": 72, "componentType": 5126, "count": 6,
       "type": "VEC3", "min": [2.5, -0.5, -0.5], "max": [3.5, 0.5, 0.5]},
      {"bufferView": 1, "componentType": 5123, "count": 24, "type": "SCALAR"}
    ],
    "bufferViews": [
      {"buffer": 0, "byteLength": 144, "target": 34962},
      {"buffer": 0, "byteOffset": 144, "byteLength": 48, "target": 34963}
    ],
    "buffers": [{"uri": "scene.bin", "byteLength": 192}]
  })");
  const std::string path = dir + "/scene.gltf";
  WriteBytes(path, j.dump(1));
  return path;
}

// A 2 by 2 RGB PNG (red, green; blue, yellow), written by hand.
constexpr const char* kTinyPng =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAFElEQVR4nGP4z8DAAMIM////"
    "ZwAAHu8E/KPItPcAAAAASUVORK5CYII=";

// One textured primitive of two components: an octahedron (vertices 0-5,
// fitted) and three triangles on one edge (not manifold: kept), each with
// vertices of its own (6-14: the edge's ends repeated, with other texture
// coordinates), their triangles among the octahedron's in the index list.
struct MixedScene {
  std::string path;
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 2>> texcoords;
  std::vector<std::array<uint16_t, 3>> kept;  // the kept triangles, in order
};

MixedScene WriteMixedPrimitiveScene(const std::string& dir) {
  MixedScene scene;
  scene.positions = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                     {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  for (const auto& v : scene.positions) {
    scene.texcoords.push_back({0.25f * (v[0] + 1), 0.5f * (v[1] + 1)});
  }
  const std::array<float, 3> ends[2] = {{3, 0, 0}, {3, 1, 0}};
  const std::array<float, 3> tips[3] = {
      {4, 0.5f, 0}, {3.5f, 0.5f, 0.8f}, {2.5f, 0.5f, 0.5f}};
  for (int k = 0; k < 3; ++k) {
    const uint16_t first = static_cast<uint16_t>(scene.positions.size());
    scene.positions.push_back(ends[0]);
    scene.positions.push_back(ends[1]);
    scene.positions.push_back(tips[k]);
    const float u = 0.6f + 0.1f * k;
    scene.texcoords.push_back({u, 0.1f});
    scene.texcoords.push_back({u, 0.9f});
    scene.texcoords.push_back({u + 0.05f, 0.5f});
    scene.kept.push_back({first, static_cast<uint16_t>(first + 1),
                          static_cast<uint16_t>(first + 2)});
  }
  const std::vector<std::array<uint16_t, 3>> octahedron = {
      {0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
      {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const std::vector<std::array<uint16_t, 3>> triangles = {
      octahedron[0], octahedron[1], scene.kept[0], octahedron[2],
      octahedron[3], octahedron[4], scene.kept[1], octahedron[5],
      octahedron[6], scene.kept[2], octahedron[7]};
  std::string bin;
  for (const auto& v : scene.positions) {
    bin.append(reinterpret_cast<const char*>(v.data()), 12);
  }
  for (const auto& t : scene.texcoords) {
    bin.append(reinterpret_cast<const char*>(t.data()), 8);
  }
  for (const auto& t : triangles) {
    bin.append(reinterpret_cast<const char*>(t.data()), 6);
  }
  WriteBytes(dir + "/mixed.bin", bin);
  const size_t n = scene.positions.size();
  Json j = Json::parse(R"({
    "asset": {"version": "2.0", "generator": "hand"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"name": "Both", "mesh": 0}],
    "meshes": [{"name": "Mixed", "primitives": [{"attributes":
      {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"name": "Painted", "pbrMetallicRoughness":
      {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
    "textures": [{"source": 0}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "type": "VEC3",
       "min": [-1, -1, -1], "max": [4, 1, 1]},
      {"bufferView": 1, "componentType": 5126, "type": "VEC2"},
      {"bufferView": 2, "componentType": 5123, "count": 33, "type": "SCALAR"}
    ]
  })");
  j["images"] = {{{"uri", std::string("data:image/png;base64,") + kTinyPng}}};
  j["accessors"][0]["count"] = n;
  j["accessors"][1]["count"] = n;
  j["bufferViews"] = {
      {{"buffer", 0}, {"byteLength", 12 * n}},
      {{"buffer", 0}, {"byteOffset", 12 * n}, {"byteLength", 8 * n}},
      {{"buffer", 0}, {"byteOffset", 20 * n}, {"byteLength", 66}}};
  j["buffers"] = {{{"uri", "mixed.bin"}, {"byteLength", bin.size()}}};
  scene.path = dir + "/mixed.gltf";
  WriteBytes(scene.path, j.dump(1));
  return scene;
}

// The mixed primitive becomes two: the kept triangles as the file had them
// (its vertices, texture coordinates and material), and the fitted
// octahedron textured through an atlas in a primitive of its own.
TEST(GltfAssetCliTest, APrimitiveOfFittedAndKeptPartsIsSplitInTwo) {
  const std::string dir = FreshTestDir();
  const MixedScene scene = WriteMixedPrimitiveScene(dir);
  const std::string model = dir + "/mixed.sdcb";
  RunResult r = RunSdcb(
      {"fit", scene.path, "-o", model, "--rmse", "0.5", "--quiet"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json in = Json::parse(ReadBytes(scene.path));
  for (const bool draco : {false, true}) {
    const std::string out = dir + (draco ? "/draco.glb" : "/plain.glb");
    std::vector<std::string> args = {"export",      model, "-o",     out,
                                     "--tolerance", "0.5", "--quiet"};
    if (draco) args.push_back("--draco");
    r = RunSdcb(args, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Json report = Validate(out, dir);
    EXPECT_EQ(report["errors"], 0) << report.dump();
    EXPECT_EQ(report["warnings"], 0) << report.dump();
    const Glb glb = ReadGlb(out);
    EXPECT_EQ(glb.json["nodes"], in["nodes"]);
    ASSERT_EQ(glb.json["meshes"].size(), 1u);
    EXPECT_EQ(glb.json["meshes"][0]["name"], "Mixed");
    const Json& primitives = glb.json["meshes"][0]["primitives"];
    ASSERT_EQ(primitives.size(), 2u) << primitives.dump();

    // The kept triangles, corner by corner: the input's positions and
    // texture coordinates, bit for bit, with the input's material.
    const Json& kept = primitives[0];
    EXPECT_EQ(glb.json["materials"][kept["material"].get<int>()],
              in["materials"][0]);
    const auto positions =
        Floats(glb, kept["attributes"]["POSITION"].get<int>(), 3);
    const auto texcoords =
        Floats(glb, kept["attributes"]["TEXCOORD_0"].get<int>(), 2);
    const std::vector<uint32_t> corners =
        Indices(glb, kept["indices"].get<int>());
    ASSERT_EQ(corners.size(), 3 * scene.kept.size());
    for (size_t t = 0; t < scene.kept.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = corners[3 * t + k];
        ASSERT_LT(v, positions.size());
        const uint16_t w = scene.kept[t][k];
        EXPECT_EQ(positions[v], std::vector<float>(scene.positions[w].begin(),
                                                   scene.positions[w].end()))
            << "triangle " << t << " corner " << k;
        EXPECT_EQ(texcoords[v], std::vector<float>(scene.texcoords[w].begin(),
                                                   scene.texcoords[w].end()))
            << "triangle " << t << " corner " << k;
      }
    }
    // The fitted octahedron: its own texture coordinates and a copy of the
    // material whose base colour texture is the atlas.
    const Json& fitted = primitives[1];
    EXPECT_TRUE(fitted["attributes"].contains("TEXCOORD_0")) << fitted.dump();
    EXPECT_EQ(draco, fitted.contains("extensions"));
    ASSERT_TRUE(fitted.contains("material"));
    EXPECT_NE(fitted["material"], kept["material"]);
    const Json& material = glb.json["materials"][fitted["material"].get<int>()];
    EXPECT_EQ(material["name"], "Painted");
    EXPECT_TRUE(material["pbrMetallicRoughness"].contains("baseColorTexture"))
        << material.dump();
    // The input's image, which the kept triangles still use, and the atlas.
    EXPECT_EQ(glb.json["images"].size(), 2u);
  }
}

// WriteSharedMeshScene's scene written into `dir` and fitted to
// `dir`/scene.sdcb: that path, or "" (a test failure) when the fit fails.
std::string FitSharedMeshScene(const std::string& dir) {
  const std::string model = dir + "/scene.sdcb";
  const RunResult fit = RunSdcb({"fit", WriteSharedMeshScene(dir), "-o", model,
                                 "--rmse", "0.5", "--quiet"},
                                dir);
  if (fit.exit_code != 0) {
    ADD_FAILURE() << fit.err;
    return "";
  }
  return model;
}

// `out`, an export of the scene, keeps the nodes, scenes and materials of
// `in` (the input) and its one mesh "Pair" of two primitives with their
// materials.
void ExpectSharedMeshSceneKept(const Json& out, const Json& in) {
  EXPECT_EQ(out["nodes"], in["nodes"]);
  EXPECT_EQ(out["scenes"], in["scenes"]);
  EXPECT_EQ(out["scene"], in["scene"]);
  EXPECT_EQ(out["materials"], in["materials"]);
  ASSERT_EQ(out["meshes"].size(), 1u);
  EXPECT_EQ(out["meshes"][0]["name"], "Pair");
  const Json& primitives = out["meshes"][0]["primitives"];
  ASSERT_EQ(primitives.size(), 2u);
  EXPECT_EQ(primitives[0]["material"], 1);
  EXPECT_EQ(primitives[1]["material"], 0);
}

TEST(GltfAssetCliTest, SceneOfASharedMeshComesBackWithItsNodesAndMaterials) {
  const std::string dir = FreshTestDir();
  const std::string model = FitSharedMeshScene(dir);
  ASSERT_FALSE(model.empty());
  // The shared mesh is fitted once: one part per primitive.
  const RunResult info = RunSdcb({"info", model, "--json", "-"}, dir);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const Json parts = Json::parse(info.out)["parts"];
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0]["name"], "Pair#0");
  EXPECT_EQ(parts[1]["name"], "Pair#1");

  const Json in = Json::parse(ReadBytes(dir + "/scene.gltf"));
  for (const bool draco : {false, true}) {
    const std::string out = dir + (draco ? "/draco.glb" : "/plain.glb");
    std::vector<std::string> args = {"export",      model, "-o",     out,
                                     "--tolerance", "0.5", "--quiet"};
    if (draco) args.push_back("--draco");
    const RunResult exported = RunSdcb(args, dir);
    ASSERT_EQ(exported.exit_code, 0) << exported.err;
    const Json report = Validate(out, dir);
    EXPECT_EQ(report["errors"], 0) << report.dump();
    EXPECT_EQ(report["warnings"], 0) << report.dump();
    const Glb glb = ReadGlb(out);
    ASSERT_NO_FATAL_FAILURE(ExpectSharedMeshSceneKept(glb.json, in));
    const Json& primitives = glb.json["meshes"][0]["primitives"];
    if (draco) {
      EXPECT_TRUE(
          primitives[0]["extensions"].contains("KHR_draco_mesh_compression"));
      continue;
    }
    // Each primitive's surface lies around its own octahedron: every
    // vertex within 5 % of the octahedron's size of its surface |x|+|y|+|z|
    // = r (the fit's rms target is 0.5 %, a corner's rounding more).
    const float radius[2] = {1.0f, 0.5f}, centre[2] = {0.0f, 3.0f};
    for (int p = 0; p < 2; ++p) {
      const int a = primitives[p]["attributes"]["POSITION"].get<int>();
      const auto points = Vec3s(glb, a);
      ASSERT_GT(points.size(), 8u);
      double worst = 0.0;
      for (const auto& v : points) {
        const double l1 =
            std::abs(v[0] - centre[p]) + std::abs(v[1]) + std::abs(v[2]);
        // Distance to the plane of the nearest face: |l1 - r| / sqrt(3).
        worst = std::max(worst, std::abs(l1 - radius[p]) / std::sqrt(3.0));
      }
      EXPECT_LT(worst, 0.05 * 2 * radius[p]) << "primitive " << p;
    }
  }
}

// The world positions glTF Transform decodes from `file`
// (scripts/gltf_tools/decode.mjs: meshopt and Draco decoded, node
// transforms applied), node by node in document order.
Json DecodeWithGltfTransform(const std::string& file, const std::string& dir) {
  const std::string out = dir + "/decoded.json";
  const std::string command =
      "node " +
      testing::ShellQuote(std::string(SDCB_SOURCE_DIR) +
                          "/scripts/gltf_tools/decode.mjs") +
      " " + testing::ShellQuote(file) + " > " + testing::ShellQuote(out) +
      " 2>&1";
  (void)std::system(command.c_str());
  return Json::parse(ReadBytes(out), nullptr, false);
}

// The largest distance from a point of `from` to its nearest point of `to`
// (rows of 3 numbers; `from` rows [from_begin, from_end), `to` rows
// [to_begin, to_end)).
double Farthest(const Json& from, size_t from_begin, size_t from_end,
                const Json& to, size_t to_begin, size_t to_end) {
  double worst = 0.0;
  for (size_t i = from_begin; i < from_end; ++i) {
    double best = HUGE_VAL;
    for (size_t j = to_begin; j < to_end; ++j) {
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double d = from[i][k].get<double>() - to[j][k].get<double>();
        d2 += d * d;
      }
      best = std::min(best, d2);
    }
    worst = std::max(worst, std::sqrt(best));
  }
  return worst;
}

// `export --meshopt` of an asset: its nodes keep their transforms (the
// positions are floats through the exponential filter, no dequantizing
// node), the file is valid, and the positions glTF Transform decodes lie
// within the reported quantization error of the plain export's.
TEST(GltfAssetCliTest, SceneOfASharedMeshComesBackWithMeshopt) {
  const std::string dir = FreshTestDir();
  const std::string model = FitSharedMeshScene(dir);
  ASSERT_FALSE(model.empty());
  const Json in = Json::parse(ReadBytes(dir + "/scene.gltf"));
  // A uniform mesh (its vertices off the octahedra's round corners, which
  // the adaptive one keeps) is the same for every encoding, so the two
  // files hold the same vertices; the quantization gets its share of the
  // tolerance as always.
  const std::vector<std::string> common = {"export", model, "--tolerance",
                                           "0.5", "--quiet"};
  const auto run = [&](const std::string& name,
                       const std::vector<std::string>& flags) {
    std::vector<std::string> args = common;
    args.insert(args.end(),
                {"-o", dir + "/" + name, "--json", dir + "/" + name + ".json"});
    args.insert(args.end(), flags.begin(), flags.end());
    const RunResult r = RunSdcb(args, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return Json::parse(ReadBytes(dir + "/" + name + ".json"));
  };
  const Json plain_report = run("plain.glb", {"--uniform", "600"});
  const Json report = run("meshopt.glb", {"--uniform", "600", "--meshopt"});
  const std::string out = dir + "/meshopt.glb";
  const Json validated = Validate(out, dir);
  EXPECT_EQ(validated["errors"], 0) << validated.dump();
  const Glb glb = ReadGlb(out);
  const Json& j = glb.json;
  ASSERT_NO_FATAL_FAILURE(ExpectSharedMeshSceneKept(j, in));
  EXPECT_NE(std::find(j["extensionsRequired"].begin(),
                      j["extensionsRequired"].end(), "EXT_meshopt_compression"),
            j["extensionsRequired"].end());
  for (const Json& p : j["meshes"][0]["primitives"]) {
    const Json& position =
        j["accessors"][p["attributes"]["POSITION"].get<int>()];
    EXPECT_EQ(position["componentType"], 5126);
    const Json& view = j["bufferViews"][position["bufferView"].get<int>()];
    EXPECT_EQ(view["extensions"]["EXT_meshopt_compression"]["filter"],
              "EXPONENTIAL");
  }

  // The parts' largest sides are 2 and 1 (the octahedra of radius 1 and
  // 0.5): the report's percent are of 1, the smaller.
  const double error =
      report["quantization"]["error_percent"].get<double>() / 100.0;
  const double plain_rounding =
      plain_report["quantization"]["float32_error_percent"].get<double>() /
      100.0;
  ASSERT_GT(error, 0.0);
  // Within the quantization's share of the tolerance, 10 % of 0.5 % of the
  // larger part's side.
  EXPECT_LE(error, 0.1 * 0.005 * 2.0);
  const Json decoded = DecodeWithGltfTransform(out, dir);
  const Json plain = DecodeWithGltfTransform(dir + "/plain.glb", dir);
  ASSERT_TRUE(decoded.contains("positions")) << decoded.dump();
  ASSERT_TRUE(plain.contains("positions")) << plain.dump();
  EXPECT_EQ(decoded["triangles"], plain["triangles"]);
  // Both lists hold the nodes Left (scale 1) then Right (scale 2), each
  // with primitive 0 then 1: compared group by group, each group's error
  // scaled by its node's scale (float32 node transforms: 1e-5 more).
  const Glb plain_glb = ReadGlb(dir + "/plain.glb");
  std::vector<size_t> groups_plain = {0}, groups_meshopt = {0};
  for (int node = 0; node < 2; ++node) {
    for (int p = 0; p < 2; ++p) {
      const auto count = [&](const Json& doc) {
        const int a =
            doc["meshes"][0]["primitives"][p]["attributes"]["POSITION"];
        return doc["accessors"][a]["count"].get<size_t>();
      };
      groups_plain.push_back(groups_plain.back() + count(plain_glb.json));
      groups_meshopt.push_back(groups_meshopt.back() + count(j));
    }
  }
  ASSERT_EQ(groups_plain.back(), plain["positions"].size());
  ASSERT_EQ(groups_meshopt.back(), decoded["positions"].size());
  for (int g = 0; g < 4; ++g) {
    SCOPED_TRACE(g);
    const double scale = g < 2 ? 1.0 : 2.0;
    const double bound = scale * (error + plain_rounding) * 1.001 + 1e-5;
    EXPECT_LE(
        Farthest(decoded["positions"], groups_meshopt[g], groups_meshopt[g + 1],
                 plain["positions"], groups_plain[g], groups_plain[g + 1]),
        bound);
    EXPECT_LE(Farthest(plain["positions"], groups_plain[g], groups_plain[g + 1],
                       decoded["positions"], groups_meshopt[g],
                       groups_meshopt[g + 1]),
              bound);
  }

  // The adaptive mesh: the total stays within the tolerance.
  const Json derived = run("derived.glb", {"--meshopt"});
  EXPECT_LE(derived["total_error_bound_percent"].get<double>(), 0.5);
  EXPECT_LE(derived["quantization"]["error_percent"].get<double>(),
            0.05 + 1e-12);
  const Json derived_validated = Validate(dir + "/derived.glb", dir);
  EXPECT_EQ(derived_validated["errors"], 0) << derived_validated.dump();
}

// `sdcb batch` with a glTF row whose output is a .glb: the row's fit and
// export give the asset back as `fit` then `export` do (nodes, materials,
// both primitives), valid, with the row's JSON line saying ok.
TEST(GltfAssetCliTest, BatchRowOfAGltfAssetWritesTheAssetBack) {
  const std::string dir = FreshTestDir();
  const std::string input = WriteSharedMeshScene(dir);
  const std::string manifest = dir + "/rows.txt";
  WriteBytes(manifest,
             input + " " + dir + "/batch.glb --rmse 0.5 --tolerance 0.5\n");
  const RunResult batch = RunSdcb(
      {"batch", manifest, "--json-lines", dir + "/rows.jsonl", "--quiet"}, dir);
  ASSERT_EQ(batch.exit_code, 0) << batch.err;
  const Json row = Json::parse(ReadBytes(dir + "/rows.jsonl"));
  EXPECT_EQ(row["status"], "ok") << row.dump();
  EXPECT_EQ(row["steps"], Json::array({"fit", "export"}));
  const Json report = Validate(dir + "/batch.glb", dir);
  EXPECT_EQ(report["errors"], 0) << report.dump();
  const Json in = Json::parse(ReadBytes(input));
  const Glb glb = ReadGlb(dir + "/batch.glb");
  EXPECT_EQ(glb.json["nodes"], in["nodes"]);
  EXPECT_EQ(glb.json["materials"], in["materials"]);
  ASSERT_EQ(glb.json["meshes"].size(), 1u);
  EXPECT_EQ(glb.json["meshes"][0]["primitives"].size(), 2u);
}

TEST(GltfAssetCliTest, BoxTexturedKeepsItsSceneAndComesOutTextured) {
  const std::string gltf =
      std::string(testing::kAssimpGltf2) + "/BoxTextured-glTF/BoxTextured.gltf";
  if (!std::filesystem::exists(gltf)) GTEST_SKIP() << "no assimp-testmodels";
  const std::string dir = FreshTestDir();
  const std::string model = dir + "/box.sdcb";
  RunResult r =
      RunSdcb({"fit", gltf, "-o", model, "--rmse", "0.5", "--quiet"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json in = Json::parse(ReadBytes(gltf));
  for (const char* compression : {"", "--draco", "--meshopt"}) {
    const std::string out = dir + "/box" + compression + ".glb";
    std::vector<std::string> args = {"export",      model, "-o",     out,
                                     "--tolerance", "0.5", "--quiet"};
    if (*compression != '\0') args.push_back(compression);
    r = RunSdcb(args, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Json report = Validate(out, dir);
    EXPECT_EQ(report["errors"], 0) << report.dump();
    const Glb glb = ReadGlb(out);
    EXPECT_EQ(glb.json["nodes"], in["nodes"]);
    EXPECT_EQ(glb.json["meshes"][0]["name"], in["meshes"][0]["name"]);
    // The fitted primitive samples a texture through TEXCOORD_0: its
    // material's base colour texture is an embedded PNG (the atlas; the
    // input's image, which nothing uses any more, is gone).
    const Json& primitive = glb.json["meshes"][0]["primitives"][0];
    EXPECT_TRUE(primitive["attributes"].contains("TEXCOORD_0"))
        << primitive.dump();
    const Json& material =
        glb.json["materials"][primitive["material"].get<int>()];
    ASSERT_TRUE(material["pbrMetallicRoughness"].contains("baseColorTexture"))
        << material.dump();
    const int texture =
        material["pbrMetallicRoughness"]["baseColorTexture"]["index"]
            .get<int>();
    const Json& image =
        glb.json["images"][glb.json["textures"][texture]["source"].get<int>()];
    ASSERT_TRUE(image.contains("bufferView"));
    EXPECT_EQ(image["mimeType"], "image/png");
    EXPECT_EQ(glb.json["images"].size(), 1u);
    const Json& view = glb.json["bufferViews"][image["bufferView"].get<int>()];
    EXPECT_EQ(glb.bin.substr(view.value("byteOffset", size_t{0}), 8),
              std::string("\x89PNG\r\n\x1a\n", 8));
  }
}

}  // namespace
}  // namespace sdcb
