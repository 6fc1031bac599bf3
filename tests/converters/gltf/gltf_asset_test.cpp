// The shell of a hand-written glTF document (MakeGltfShell) against the
// document's own JSON: extension names nothing uses any more are dropped,
// and a primitive of kept and fitted parts is split, its kept triangles'
// indices the ones given.
#include "sdcb/converters/gltf/gltf_asset.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sdcb/converters/gltf/glb_container.h"

namespace sdcb {
namespace {

using Json = nlohmann::json;

// Two primitives of one triangle: 0 with material 0 (KHR_materials_
// pbrSpecularGlossiness), 1 with material 1 (KHR_materials_unlit).
// extensionsUsed also names FB_ngon_encoding, KHR_mesh_quantization and
// KHR_texture_transform, which only a node's extras name.
GltfDocument TwoPrimitiveDocument() {
  GltfDocument document;
  document.json = R"({
    "asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_materials_pbrSpecularGlossiness",
      "FB_ngon_encoding", "KHR_mesh_quantization", "KHR_texture_transform",
      "KHR_materials_unlit"],
    "extensionsRequired": ["KHR_materials_pbrSpecularGlossiness",
      "KHR_mesh_quantization"],
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0,
               "extras": {"extensions": {"KHR_texture_transform": {}}}}],
    "meshes": [{"primitives": [
      {"attributes": {"POSITION": 0}, "material": 0},
      {"attributes": {"POSITION": 0}, "material": 1}]}],
    "materials": [
      {"name": "glossy", "extensions": {"KHR_materials_pbrSpecularGlossiness":
        {"diffuseFactor": [1, 1, 1, 1]}}},
      {"name": "flat", "extensions": {"KHR_materials_unlit": {}}}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3,
                   "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"byteLength": 36}]})";
  document.buffers.push_back(std::string(36, '\0'));
  return document;
}

Json ShellJson(const std::string& shell) {
  StatusOr<GlbChunks> chunks = SplitGlb(shell);
  EXPECT_TRUE(chunks.ok());
  return chunks.ok() ? Json::parse(chunks->json) : Json();
}

TEST(GltfAssetTest, ExtensionNamesNothingUsesAreDropped) {
  const GltfDocument document = TwoPrimitiveDocument();
  // Primitive 0 fitted with an atlas: its material becomes a copy without
  // extensions, and the original, used by nothing else, goes.
  GltfFittedPrimitive f;
  f.parts = {0};
  f.atlas_png = "not decoded by the shell";
  f.atlas_layout.parts = 1;
  StatusOr<std::string> shell = MakeGltfShell(document, {f});
  ASSERT_TRUE(shell.ok()) << shell.status().message();
  Json j = ShellJson(*shell);
  EXPECT_EQ(j["extensionsUsed"],
            Json({"KHR_mesh_quantization", "KHR_materials_unlit"}));
  EXPECT_EQ(j["extensionsRequired"], Json({"KHR_mesh_quantization"}));
  ASSERT_EQ(j["materials"].size(), 2u);
  EXPECT_EQ(j["materials"][0]["name"], "flat");

  // Nothing fitted: the polygons of FB_ngon_encoding are still there, and
  // so is the glossy material; the name only extras hold still goes.
  shell = MakeGltfShell(document, {});
  ASSERT_TRUE(shell.ok()) << shell.status().message();
  j = ShellJson(*shell);
  EXPECT_EQ(j["extensionsUsed"],
            Json({"KHR_materials_pbrSpecularGlossiness", "FB_ngon_encoding",
                  "KHR_mesh_quantization", "KHR_materials_unlit"}));
  EXPECT_EQ(
      j["extensionsRequired"],
      Json({"KHR_materials_pbrSpecularGlossiness", "KHR_mesh_quantization"}));
}

// FB_ngon_encoding as its specification writes it, on each primitive
// (assimp's glTF 2 writer does so): it leaves the fitted primitive and
// both halves of a split one, and its name goes with the last of it.
TEST(GltfAssetTest, NgonEncodingLeavesTheTrianglesItNoLongerDescribes) {
  GltfDocument document;
  document.json = R"({
    "asset": {"version": "2.0"},
    "extensionsUsed": ["FB_ngon_encoding"],
    "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [
      {"attributes": {"POSITION": 0}, "extensions": {"FB_ngon_encoding": {}}},
      {"attributes": {"POSITION": 0}, "extensions": {"FB_ngon_encoding": {}}},
      {"attributes": {"POSITION": 0},
       "extensions": {"FB_ngon_encoding": {}}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3,
                   "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"byteLength": 36}]})";
  document.buffers.push_back(std::string(36, '\0'));
  GltfFittedPrimitive whole, split;
  whole.parts = {0};
  split.primitive = 1;
  split.parts = {1};
  split.kept_corners.resize(1, 3);
  split.kept_corners << 0, 1, 2;
  StatusOr<std::string> shell = MakeGltfShell(document, {whole, split});
  ASSERT_TRUE(shell.ok()) << shell.status().message();
  Json j = ShellJson(*shell);
  const Json& primitives = j["meshes"][0]["primitives"];
  ASSERT_EQ(primitives.size(), 4u);
  for (const int p : {0, 1, 3}) {
    EXPECT_FALSE(primitives[p].contains("extensions")) << p;
  }
  EXPECT_EQ(primitives[2]["extensions"],
            Json::parse(R"({"FB_ngon_encoding": {}})"));
  EXPECT_EQ(j["extensionsUsed"], Json({"FB_ngon_encoding"}));
  // The third primitive fitted too: nothing is encoded any more.
  GltfFittedPrimitive third;
  third.primitive = 2;
  third.parts = {2};
  shell = MakeGltfShell(document, {whole, split, third});
  ASSERT_TRUE(shell.ok()) << shell.status().message();
  j = ShellJson(*shell);
  EXPECT_FALSE(j.contains("extensionsUsed")) << j.dump();
}

TEST(GltfAssetTest, APrimitiveOfKeptAndFittedPartsIsSplit) {
  const GltfDocument document = TwoPrimitiveDocument();
  GltfFittedPrimitive f;
  f.primitive = 1;
  f.parts = {3, 4};
  for (const int largest : {2, 65535}) {
    f.kept_corners.resize(2, 3);
    f.kept_corners << 0, 1, 2, 2, 1, largest;
    StatusOr<std::string> shell = MakeGltfShell(document, {f});
    ASSERT_TRUE(shell.ok()) << shell.status().message();
    const Json j = ShellJson(*shell);
    const std::string bin(SplitGlb(*shell)->bin);
    const Json& primitives = j["meshes"][0]["primitives"];
    ASSERT_EQ(primitives.size(), 3u);
    // The kept primitive: its attributes and material, the kept triangles.
    const Json& kept = primitives[1];
    EXPECT_EQ(kept["material"], 1);
    ASSERT_TRUE(kept["attributes"].contains("POSITION"));
    EXPECT_FALSE(kept.contains("mode"));
    EXPECT_FALSE(kept.contains("extras"));
    const Json& accessor = j["accessors"][kept["indices"].get<int>()];
    EXPECT_EQ(accessor["count"], 6);
    // 65535 is the unsigned short's primitive restart: unsigned int then.
    const bool shorts = largest < 65535;
    EXPECT_EQ(accessor["componentType"], shorts ? 5123 : 5125);
    const Json& view = j["bufferViews"][accessor["bufferView"].get<int>()];
    EXPECT_EQ(view["target"], 34963);
    const size_t at = view.value("byteOffset", size_t{0}) +
                      accessor.value("byteOffset", size_t{0});
    for (int i = 0; i < 6; ++i) {
      uint32_t index = 0;
      std::memcpy(&index, bin.data() + at + i * (shorts ? 2 : 4),
                  shorts ? 2 : 4);
      EXPECT_EQ(static_cast<int>(index), f.kept_corners(i / 3, i % 3)) << i;
    }
    // The appended primitive holds the parts, with the same material.
    const Json& holding = primitives[2];
    EXPECT_EQ(holding["material"], 1);
    EXPECT_FALSE(holding.contains("attributes"));
    EXPECT_EQ(holding["extras"]["sdcb_parts"], Json({3, 4}));
    StatusOr<std::vector<GltfFittedPrimitive>> read =
        ShellFittedPrimitives(*shell);
    ASSERT_TRUE(read.ok());
    ASSERT_EQ(read->size(), 1u);
    EXPECT_EQ((*read)[0].primitive, 2);
    EXPECT_EQ((*read)[0].parts, f.parts);
    // Primitive 0 is not fitted: its glossy material stays, and so does
    // its extension; FB_ngon_encoding goes (a primitive is fitted).
    EXPECT_EQ(j["extensionsUsed"],
              Json({"KHR_materials_pbrSpecularGlossiness",
                    "KHR_mesh_quantization", "KHR_materials_unlit"}));
  }
}

}  // namespace
}  // namespace sdcb
