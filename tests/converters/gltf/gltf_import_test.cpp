// The glTF reader against oracles of its own: the glTF JSON's accessor
// counts and positions read here with nlohmann_json and plain byte copies,
// closed-form transforms, the exporter's reported quantization error, and
// the sentences the malformed assimp-testmodels files must give.
#include "sdcb/converters/gltf/gltf_import.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <utility>

#include "sdcb/converters/gltf/glb_container.h"
#include "sdcb/converters/gltf/gltf_export.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "testing/gltf_assets.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::Base64;
using testing::FreshTestDir;
using testing::kAssimpGltf2;
using testing::ReadBytes;
using testing::WriteBytes;

uint32_t U32(const std::string& s, size_t at) {
  uint32_t v;
  std::memcpy(&v, s.data() + at, 4);
  return v;
}

TEST(GltfImport, DuckCountsAndPositionsMatchTheJson) {
  const std::string glb = testing::MakeDuckGlb(FreshTestDir());
  if (glb.empty()) GTEST_SKIP() << "assimp or assimp-testmodels missing";
  // The oracle: the JSON chunk and the BIN chunk read directly.
  const std::string bytes = ReadBytes(glb);
  const uint32_t json_length = U32(bytes, 12);
  const nlohmann::json json =
      nlohmann::json::parse(bytes.substr(20, json_length));
  const std::string bin = bytes.substr(20 + json_length + 8);
  ASSERT_EQ(json["meshes"].size(), 1u);
  const nlohmann::json& primitive = json["meshes"][0]["primitives"][0];
  const nlohmann::json& position =
      json["accessors"][primitive["attributes"]["POSITION"].get<int>()];
  const nlohmann::json& indices =
      json["accessors"][primitive["indices"].get<int>()];
  ASSERT_EQ(position["componentType"], 5126);
  ASSERT_EQ(indices["componentType"], 5125);
  auto view_start = [&](const nlohmann::json& accessor) {
    const nlohmann::json& view =
        json["bufferViews"][accessor["bufferView"].get<int>()];
    EXPECT_FALSE(view.contains("byteStride"));
    return view.value("byteOffset", 0) + accessor.value("byteOffset", 0);
  };
  const int n = position["count"];
  const int corners = indices["count"];
  std::vector<std::array<float, 3>> points(n);
  std::memcpy(points.data(), bin.data() + view_start(position), 12 * n);
  std::vector<uint32_t> index(corners);
  std::memcpy(index.data(), bin.data() + view_start(indices), 4 * corners);
  std::set<std::array<float, 3>> distinct;
  int degenerate = 0;
  for (int f = 0; f < corners / 3; ++f) {
    const auto& a = points[index[3 * f]];
    const auto& b = points[index[3 * f + 1]];
    const auto& c = points[index[3 * f + 2]];
    if (a == b || b == c || a == c) ++degenerate;
    distinct.insert({a, b, c});
  }

  StatusOr<GltfAsset> asset = ReadGltf(glb);
  ASSERT_TRUE(asset.ok()) << asset.status().message();
  ASSERT_EQ(asset->primitives.size(), 1u);
  const GltfPrimitive& p = asset->primitives[0];
  EXPECT_EQ(p.name, json["meshes"][0]["name"].get<std::string>());
  EXPECT_EQ(p.source_vertices, n);
  EXPECT_EQ(p.dropped_degenerate, degenerate);
  EXPECT_EQ(p.triangles.num_faces(), corners / 3 - degenerate);
  EXPECT_EQ(p.triangles.num_vertices(), static_cast<int>(distinct.size()));
  EXPECT_LT(p.triangles.num_vertices(), n);  // UV seams merged
  EXPECT_EQ(p.texcoords.rows(), 3 * p.triangles.num_faces());
  EXPECT_EQ(p.colors.rows(), 0);
  EXPECT_EQ(p.material, primitive["material"].get<int>());
  // Every read vertex is one of the file's positions, bit for bit.
  for (int v = 0; v < p.triangles.num_vertices(); ++v) {
    const std::array<float, 3> q = {
        static_cast<float>(p.triangles.vertices(v, 0)),
        static_cast<float>(p.triangles.vertices(v, 1)),
        static_cast<float>(p.triangles.vertices(v, 2))};
    EXPECT_EQ(distinct.count(q), 1u);
  }
  // Nodes: names and the scale-0.01 matrix of the root.
  ASSERT_EQ(asset->nodes.size(), json["nodes"].size());
  for (size_t i = 0; i < asset->nodes.size(); ++i) {
    EXPECT_EQ(asset->nodes[i].name, json["nodes"][i].value("name", ""));
  }
  EXPECT_NEAR(asset->nodes[0].local(0, 0),
              json["nodes"][0]["matrix"][0].get<double>(), 0);
}

TEST(GltfImport, BoxTexturedMergesItsSplitVerticesIntoAClosedBox) {
  const std::string path =
      std::string(kAssimpGltf2) + "/BoxTextured-glTF-Binary/BoxTextured.glb";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "assimp-testmodels";
  StatusOr<GltfAsset> asset = ReadGltf(path);
  ASSERT_TRUE(asset.ok()) << asset.status().message();
  ASSERT_EQ(asset->primitives.size(), 1u);
  const GltfPrimitive& p = asset->primitives[0];
  EXPECT_EQ(p.source_vertices, 24);
  EXPECT_EQ(p.triangles.num_vertices(), 8);
  EXPECT_EQ(p.triangles.num_faces(), 12);
  EXPECT_EQ(p.texcoords.rows(), 36);
  StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(p.triangles);
  ASSERT_TRUE(topology.ok());
  EXPECT_EQ(topology->boundary_edges, 0);
  EXPECT_EQ(topology->non_manifold_edges, 0);
  EXPECT_EQ(topology->components, 1);
  // The same box from the .gltf with its external .bin and embedded as a
  // data URI.
  for (const char* other : {"/BoxTextured-glTF/BoxTextured.gltf",
                            "/BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
    StatusOr<GltfAsset> same = ReadGltf(std::string(kAssimpGltf2) + other);
    ASSERT_TRUE(same.ok()) << same.status().message();
    EXPECT_EQ(same->primitives[0].triangles.vertices, p.triangles.vertices);
    EXPECT_EQ(same->primitives[0].triangles.faces, p.triangles.faces);
    // The image's bytes, from its file or its data URI: a PNG.
    ASSERT_EQ(same->document.images.size(), 1u);
    EXPECT_EQ(same->document.images[0].substr(0, 8),
              std::string("\x89PNG\r\n\x1a\n", 8))
        << other;
  }
  // The GLB's image is in a buffer view: no bytes of its own.
  ASSERT_EQ(asset->document.images.size(), 1u);
  EXPECT_EQ(asset->document.images[0], "");
}

// The exporter's Draco and meshopt (quantized and exponential) GLBs of an
// icosphere read back to the original positions within the quantization
// error it reports.
TEST(GltfImport, DracoAndMeshoptGlbsReadBackWithinTheQuantizationError) {
  const TriangleMesh sphere = MakeIcosphere(3);
  SurfaceMesh mesh;
  mesh.positions = sphere.vertices * 2.5;
  mesh.normals = sphere.vertices.rowwise().normalized();
  mesh.faces = sphere.faces;
  // The fourth case: meshopt with exponential positions.
  for (const int c : {0, 1, 2, 3}) {
    const GltfCompression compression = c == 0   ? GltfCompression::kNone
                                        : c == 1 ? GltfCompression::kDraco
                                                 : GltfCompression::kMeshopt;
    GltfExportOptions options;
    options.compression = compression;
    if (c == 3) options.meshopt_positions = GltfMeshoptPositions::kExponential;
    options.position_bits = 12;
    StatusOr<EncodedGltf> encoded = EncodeGltf(mesh, options, true);
    ASSERT_TRUE(encoded.ok()) << encoded.status().message();
    StatusOr<GltfAsset> asset = ReadGltfFromBuffer(encoded->bytes);
    ASSERT_TRUE(asset.ok()) << asset.status().message();
    ASSERT_EQ(asset->primitives.size(), 1u);
    const TriangleMesh& read = asset->primitives[0].triangles;
    EXPECT_EQ(read.num_vertices(), sphere.num_vertices());
    EXPECT_EQ(read.num_faces(), sphere.num_faces());
    // Compressed vertices have no indices in the file's numbering.
    EXPECT_EQ(asset->primitives[0].source_corners.rows(),
              compression == GltfCompression::kNone ? read.num_faces() : 0);
    // The scene's node transform undoes meshopt's quantization: the
    // positions in the world are node.local * p.
    Eigen::Matrix4d world = Eigen::Matrix4d::Identity();
    for (const int root : asset->roots) {
      if (asset->nodes[root].mesh == 0) world = asset->nodes[root].local;
    }
    const double bound = encoded->result.quantization_error +
                         encoded->result.float32_error + 1e-6;
    for (int v = 0; v < read.num_vertices(); ++v) {
      const Eigen::Vector3d p =
          world.topLeftCorner<3, 3>() * read.vertices.row(v).transpose() +
          world.topRightCorner<3, 1>();
      double nearest = HUGE_VAL;
      for (int w = 0; w < mesh.positions.rows(); ++w) {
        nearest =
            std::min(nearest, (mesh.positions.row(w).transpose() - p).norm());
      }
      EXPECT_LE(nearest, bound) << "case " << c;
    }
  }
}

// A unit square's four corners (float32) in one data-URI buffer.
std::string SquareBufferJson() {
  const float corners[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const std::string bytes(reinterpret_cast<const char*>(corners), 48);
  return R"("buffers": [{"byteLength": 48, "uri": "data:application/octet-stream;base64,)" +
         Base64(bytes) + R"("}],
    "bufferViews": [{"buffer": 0, "byteLength": 48}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4,
                   "type": "VEC3"}])";
}

// Nodes, names and transforms of a small hand-written file; a strip and a
// fan of the same four corners.
TEST(GltfImport, ReadsTheNodeHierarchyAndTrsOfAHandWrittenFile) {
  const std::string text = R"({"asset": {"version": "2.0"}, "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [
      {"name": "root", "children": [1, 2]},
      {"name": "child", "mesh": 0, "translation": [1, 2, 3],
       "rotation": [0, 0, 0.7071067811865476, 0.7071067811865476],
       "scale": [2, 2, 2]},
      {"name": "matrix", "mesh": 0,
       "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 6, 7, 1]}],
    "meshes": [{"name": "quad", "primitives": [
      {"attributes": {"POSITION": 0}, "mode": 5},
      {"attributes": {"POSITION": 0}, "mode": 6},
      {"attributes": {"POSITION": 0}, "mode": 1}]}],
    )" + SquareBufferJson() +
                           "}";
  StatusOr<GltfAsset> asset = ReadGltfFromBuffer(text);
  ASSERT_TRUE(asset.ok()) << asset.status().message();
  ASSERT_EQ(asset->nodes.size(), 3u);
  EXPECT_EQ(asset->roots, std::vector<int>{0});
  EXPECT_EQ(asset->nodes[0].name, "root");
  EXPECT_EQ(asset->nodes[0].children, (std::vector<int>{1, 2}));
  EXPECT_EQ(asset->nodes[0].mesh, -1);
  EXPECT_EQ(asset->nodes[1].mesh, 0);
  // T * R(z, 90 degrees) * S(2), by hand.
  Eigen::Matrix4d expected;
  expected << 0, -2, 0, 1,  //
      2, 0, 0, 2,           //
      0, 0, 2, 3,           //
      0, 0, 0, 1;
  EXPECT_LT((asset->nodes[1].local - expected).norm(), 1e-12);
  Eigen::Matrix4d moved = Eigen::Matrix4d::Identity();
  moved.col(3).head<3>() << 5, 6, 7;
  EXPECT_EQ(asset->nodes[2].local, moved);
  // The mesh used by two nodes is read once; the lines primitive skipped.
  ASSERT_EQ(asset->primitives.size(), 2u);
  EXPECT_EQ(asset->line_primitives, 1);
  EXPECT_EQ(asset->primitives[0].name, "quad#0");
  EXPECT_EQ(asset->primitives[1].name, "quad#1");
  // Strip (v0 v1 v2), (v1 v3 v2) by the spec's p_i = (v_i, v_{i+1+i%2},
  // v_{i+2-i%2}), both counter-clockwise seen from +z; fan (v1 v2 v0),
  // (v2 v3 v0): two triangles each over the four corners, numbered in order
  // of first use.
  const TriangleMesh& strip = asset->primitives[0].triangles;
  Eigen::MatrixX3i strip_faces(2, 3);
  strip_faces << 0, 1, 2, 1, 3, 2;
  EXPECT_EQ(strip.faces, strip_faces);
  const TriangleMesh& fan = asset->primitives[1].triangles;
  ASSERT_EQ(fan.num_faces(), 2);
  EXPECT_EQ(fan.vertices.row(fan.faces(0, 0)), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(fan.vertices.row(fan.faces(1, 2)), Eigen::RowVector3d(0, 0, 0));
  // Mesh-local coordinates: no node transform applied.
  EXPECT_EQ(strip.vertices.row(3), Eigen::RowVector3d(1, 1, 0));
}

// The file's vertex of each corner: vertex 4 is at vertex 1's position
// (merged), and a triangle with two corners at one position is dropped;
// a strip's triangles take the spec's corners.
TEST(GltfImport, SourceCornersAreTheFilesVerticesOfTheTrianglesRead) {
  const float corners[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 1, 0, 0};
  const uint8_t indices[13] = {0, 4, 2, 1, 1, 3, 4, 3, 2,  // TRIANGLES
                               0, 4, 2, 3};                // strip
  const std::string bytes =
      std::string(reinterpret_cast<const char*>(corners), 60) +
      std::string(reinterpret_cast<const char*>(indices), 13);
  const std::string text =
      R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [
      {"attributes": {"POSITION": 0}, "indices": 1},
      {"attributes": {"POSITION": 0}, "indices": 2, "mode": 5}]}],
    "buffers": [{"byteLength": 73, "uri": "data:application/octet-stream;base64,)" +
      Base64(bytes) + R"("}],
    "bufferViews": [{"buffer": 0, "byteLength": 60},
                    {"buffer": 0, "byteOffset": 60, "byteLength": 13}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3"},
      {"bufferView": 1, "componentType": 5121, "count": 9, "type": "SCALAR"},
      {"bufferView": 1, "byteOffset": 9, "componentType": 5121, "count": 4,
       "type": "SCALAR"}]})";
  StatusOr<GltfAsset> asset = ReadGltfFromBuffer(text);
  ASSERT_TRUE(asset.ok()) << asset.status().message();
  ASSERT_EQ(asset->primitives.size(), 2u);
  Eigen::MatrixX3i expected(2, 3);
  expected << 0, 4, 2, 4, 3, 2;
  Eigen::MatrixX3i merged(2, 3);
  merged << 0, 1, 2, 1, 3, 2;
  for (const GltfPrimitive& p : asset->primitives) {
    EXPECT_EQ(p.source_corners, expected) << p.name;
    EXPECT_EQ(p.triangles.faces, merged) << p.name;
  }
  EXPECT_EQ(asset->primitives[0].dropped_degenerate, 1);
}

// A sparse POSITION without a buffer view: zeros, with corners 1..3
// replaced by the square's (indices 1 2 3 as unsigned bytes, values from
// byte 12 of the square's view); a strip over them is the square's.
TEST(GltfImport, ReadsSparseAccessors) {
  const float corners[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const std::string text =
      R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 5}]}],
    "buffers": [{"byteLength": 48, "uri": "data:application/octet-stream;base64,)" +
      Base64(std::string(reinterpret_cast<const char*>(corners), 48)) +
      R"("}, {"byteLength": 3, "uri": "data:application/octet-stream;base64,AQID"}],
    "bufferViews": [{"buffer": 0, "byteLength": 48},
                    {"buffer": 1, "byteLength": 3}],
    "accessors": [{"componentType": 5126, "count": 4, "type": "VEC3",
      "sparse": {"count": 3,
                 "indices": {"bufferView": 1, "componentType": 5121},
                 "values": {"bufferView": 0, "byteOffset": 12}}}]})";
  StatusOr<GltfAsset> asset = ReadGltfFromBuffer(text);
  ASSERT_TRUE(asset.ok()) << asset.status().message();
  Eigen::MatrixX3d square(4, 3);
  square << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  EXPECT_EQ(asset->primitives[0].triangles.vertices, square);
  // Indices out of order are named.
  std::string swapped = text;
  swapped.replace(swapped.find("AQID"), 4, "AwIB");  // 3 2 1
  const Status s = ReadGltfFromBuffer(swapped).status();
  EXPECT_EQ(s.message(),
            "primitive 0 of mesh 0: POSITION (accessor 0) (sparse): index 2 "
            "is out of order or past the 4 elements");
}

// The square as a strip, with the given scene and nodes.
std::string SquareText(const std::string& nodes_and_scene) {
  return R"({"asset": {"version": "2.0"}, )" + nodes_and_scene + ", " +
         SquareBufferJson() + R"(, "meshes": [{"primitives": [
      {"attributes": {"POSITION": 0}, "mode": 5}]}]})";
}

Status ReadText(const std::string& nodes_and_scene) {
  return ReadGltfFromBuffer(SquareText(nodes_and_scene)).status();
}

TEST(GltfImport, NodeCyclesAndSharedChildrenAreOneSentence) {
  Status s = ReadText(R"("scene": 0, "scenes": [{"nodes": [0]}], "nodes": [
      {"children": [1]}, {"children": [2]}, {"children": [0], "mesh": 0}])");
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_EQ(s.message(), "node 0 is its own ancestor");
  s = ReadText(R"("scenes": [{"nodes": [0]}], "nodes": [
      {"children": [2]}, {"children": [2]}, {"mesh": 0}])");
  EXPECT_EQ(s.message(), "node 2 is a child of both node 0 and node 1");
  s = ReadText(R"("scenes": [{"nodes": [0]}], "nodes": [{"children": [0]}])");
  EXPECT_EQ(s.message(), "node 0 is its own ancestor");
  s = ReadText(R"("nodes": [{"mesh": 0}])");
  EXPECT_EQ(s.message(), "the file has no scene");
  // Without `scene`, scene 0; a scene whose nodes have no mesh.
  s = ReadText(R"("scenes": [{"nodes": [0]}], "nodes": [{}])");
  EXPECT_EQ(s.message(), "scene 0 has no triangles");
  EXPECT_TRUE(
      ReadText(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}])").ok());
}

TEST(GltfImport, ABufferReadOpensNoExternalFile) {
  const std::string text = R"({"asset": {"version": "2.0"},
    "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "buffers": [{"byteLength": 48, "uri": "square.bin"}],
    "bufferViews": [{"buffer": 0, "byteLength": 48}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4,
                   "type": "VEC3"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]})";
  const Status s = ReadGltfFromBuffer(text).status();
  EXPECT_EQ(s.code(), StatusCode::kCorruptFile);
  EXPECT_EQ(s.message(),
            "the buffer file 'square.bin' is external (a buffer read opens no "
            "files)");
}

TEST(GltfImport, AccessorsPastTheirViewAndWrongTypesAreNamed) {
  // 4 corners claimed as 5; as unsigned shorts; as VEC2.
  const std::string square = SquareBufferJson();
  auto with_accessor = [&](const std::string& from, const std::string& to) {
    std::string text = R"({"asset": {"version": "2.0"},
      "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], )" +
                       square + R"(, "meshes": [{"primitives": [
        {"attributes": {"POSITION": 0}, "mode": 5}]}]})";
    text.replace(text.find(from), from.size(), to);
    return ReadGltfFromBuffer(text).status();
  };
  Status s = with_accessor(R"("count": 4)", R"("count": 5)");
  EXPECT_EQ(s.code(), StatusCode::kCorruptFile);
  EXPECT_EQ(s.message(),
            "primitive 0 of mesh 0: POSITION (accessor 0) reads past the end "
            "of buffer view 0: 5 elements of 12 bytes from byte 0 need more "
            "than its 48 bytes");
  s = with_accessor("5126", "5123");
  EXPECT_EQ(s.message(),
            "primitive 0 of mesh 0: POSITION (accessor 0) has component type "
            "5123 (unsigned short), which glTF does not allow there (without "
            "KHR_mesh_quantization)");
  s = with_accessor(R"("VEC3")", R"("VEC2")");
  EXPECT_EQ(s.message(),
            "primitive 0 of mesh 0: POSITION (accessor 0) has 2-component "
            "type; glTF requires 3 components");
}

// The glTF 2 files of assimp-testmodels the reader refuses, each with its
// sentence; it reads every other one.
struct AssimpRefusal {
  const char* file;
  StatusCode code;
  const char* message;
};
const AssimpRefusal kAssimpRefusals[] = {
    {"IncorrectVertexArrays/Cube.gltf", StatusCode::kCorruptFile,
     "primitive 0 of mesh 1 has 35 vertices, not a multiple of 3 for "
     "TRIANGLES"},
    {"IndexOutOfRange/IndexOutOfRange.gltf", StatusCode::kInvalidInput,
     "primitive 0 of mesh 0: index 255 refers past the 24 vertices"},
    {"IndexOutOfRange/AllIndicesOutOfRange.gltf", StatusCode::kInvalidInput,
     "primitive 0 of mesh 0: index 65535 refers past the 24 vertices"},
    {"MissingBin/BoxTextured.gltf", StatusCode::kCorruptFile,
     "the buffer file 'BoxTextured0.bin' is missing"},
    {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb",
     StatusCode::kInvalidInput,
     "primitive 0 of mesh 0: vertex 0 has a non-finite position (-inf, "
     "-0.500000, 0.500000)"},
    {"RecursiveNodes/RecursiveNodes.gltf", StatusCode::kInvalidInput,
     "node 0 is its own ancestor"},
    {"TestNoRootNode/NoScene.gltf", StatusCode::kInvalidInput,
     "the file has no scene"},
    {"TestNoRootNode/SceneWithoutNodes.gltf", StatusCode::kInvalidInput,
     "scene 0 has no triangles"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf",
     StatusCode::kInvalidInput,
     "scene 0 has no triangles (1 points and 0 lines primitives skipped)"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_01.gltf",
     StatusCode::kInvalidInput,
     "scene 0 has no triangles (0 points and 1 lines primitives skipped)"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_02.gltf",
     StatusCode::kInvalidInput,
     "scene 0 has no triangles (0 points and 1 lines primitives skipped)"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_03.gltf",
     StatusCode::kInvalidInput,
     "scene 0 has no triangles (0 points and 1 lines primitives skipped)"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_07.gltf",
     StatusCode::kInvalidInput,
     "scene 0 has no triangles (1 points and 0 lines primitives skipped)"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_08.gltf",
     StatusCode::kInvalidInput,
     "scene 0 has no triangles (0 points and 1 lines primitives skipped)"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_09.gltf",
     StatusCode::kInvalidInput,
     "scene 0 has no triangles (0 points and 1 lines primitives skipped)"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_10.gltf",
     StatusCode::kInvalidInput,
     "scene 0 has no triangles (0 points and 1 lines primitives skipped)"},
    // Types the glTF 2.0 schema forbids (tinygltf reads past them).
    {"wrongTypes/badArray.gltf", StatusCode::kCorruptFile,
     "meshes[0].primitives is an object, not an array (glTF 2.0 schema)"},
    {"wrongTypes/badExtension.gltf", StatusCode::kCorruptFile,
     "materials[0].pbrMetallicRoughness.baseColorTexture.extensions."
     "KHR_texture_transform is \"Not an object\", not an object (glTF 2.0 "
     "schema)"},
    {"wrongTypes/badNumber.gltf", StatusCode::kCorruptFile,
     "materials[0].normalTexture.scale is \"not a number\", not a number "
     "(glTF 2.0 schema)"},
    {"wrongTypes/badObject.gltf", StatusCode::kCorruptFile,
     "materials[0].pbrMetallicRoughness is an array, not an object (glTF "
     "2.0 schema)"},
    {"wrongTypes/badString.gltf", StatusCode::kCorruptFile,
     "scenes[0].name is 42, not a string (glTF 2.0 schema)"},
    {"wrongTypes/badUint.gltf", StatusCode::kCorruptFile,
     "materials[0].pbrMetallicRoughness.baseColorTexture.index is -1, not a "
     "non-negative integer (glTF 2.0 schema)"},
    {"SchemaFailures/sceneWrongType.gltf", StatusCode::kCorruptFile,
     "scene is \"hello\", not a non-negative integer (glTF 2.0 schema)"},
};

TEST(GltfImport, MalformedAssimpTestModelsGiveOneSentenceEach) {
  if (!std::filesystem::exists(kAssimpGltf2)) GTEST_SKIP();
  for (const AssimpRefusal& c : kAssimpRefusals) {
    const std::string path = std::string(kAssimpGltf2) + "/" + c.file;
    const Status s = ReadGltf(path).status();
    EXPECT_EQ(s.code(), c.code) << c.file << ": " << s.message();
    EXPECT_EQ(s.message(), path + ": " + c.message);
  }
}

// assimp-testmodels' glTF 1 files (their asset.version "1.0", or the
// number 1 in the Cesium Milk Truck's; a GLB's header version 1) are
// refused as glTF 1, naming the converter.
TEST(GltfImport, GltfOneFilesAreRefusedAsSuch) {
  const std::string dir = "/usr/share/assimp/models/glTF";
  if (!std::filesystem::exists(dir)) GTEST_SKIP();
  for (const char* file : {"BoxTextured-glTF/BoxTextured.gltf",
                           "CesiumMilkTruck/CesiumMilkTruck.gltf"}) {
    const Status s = ReadGltf(dir + "/" + file).status();
    EXPECT_EQ(s.code(), StatusCode::kUnsupported) << s.message();
    EXPECT_NE(s.message().find(": the file is glTF 1"), std::string::npos)
        << s.message();
    EXPECT_NE(s.message().find("-f glb2"), std::string::npos);
  }
  const Status glb =
      ReadGltf(dir + "/BoxTextured-glTF-Binary/BoxTextured.glb").status();
  EXPECT_EQ(glb.code(), StatusCode::kCorruptFile);
  EXPECT_NE(glb.message().find("the GLB is of version 1, not 2"),
            std::string::npos)
      << glb.message();
}

TEST(GltfImport, EveryOtherAssimpTestModelIsRead) {
  if (!std::filesystem::exists(kAssimpGltf2)) GTEST_SKIP();
  std::set<std::string> refused;
  for (const AssimpRefusal& c : kAssimpRefusals) refused.insert(c.file);
  int read = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(kAssimpGltf2)) {
    const std::string path = entry.path().string();
    const std::string file = path.substr(std::strlen(kAssimpGltf2) + 1);
    if (!IsGltfPath(path) || refused.count(file) != 0) continue;
    const Status s = ReadGltf(path).status();
    EXPECT_TRUE(s.ok()) << s.message();
    ++read;
  }
  EXPECT_EQ(read, 23);
}

// The Khronos validator's JSON pointer for each schema type error of
// assimp-testmodels (scripts/gltf_tools/validate.js, transcribed: "Property
// value 42 is not a 'string'. (/scenes/0/name)") is the path the sentence
// names.
TEST(GltfImport, SchemaTypeErrorsNameTheValidatorsPath) {
  if (!std::filesystem::exists(kAssimpGltf2)) GTEST_SKIP();
  const std::pair<const char*, const char*> cases[] = {
      {"wrongTypes/badArray.gltf", "/meshes/0/primitives"},
      {"wrongTypes/badExtension.gltf",
       "/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/"
       "KHR_texture_transform"},
      {"wrongTypes/badNumber.gltf", "/materials/0/normalTexture/scale"},
      {"wrongTypes/badObject.gltf", "/materials/0/pbrMetallicRoughness"},
      {"wrongTypes/badString.gltf", "/scenes/0/name"},
      {"wrongTypes/badUint.gltf",
       "/materials/0/pbrMetallicRoughness/baseColorTexture/index"},
      {"SchemaFailures/sceneWrongType.gltf", "/scene"},
  };
  for (const auto& [file, pointer] : cases) {
    // "/a/0/b" as the reader writes it: "a[0].b".
    std::string path;
    std::string segment;
    std::istringstream segments(std::string(pointer).substr(1));
    while (std::getline(segments, segment, '/')) {
      const bool number =
          segment.find_first_not_of("0123456789") == std::string::npos;
      if (number) {
        path += "[" + segment + "]";
      } else {
        path += (path.empty() ? "" : ".") + segment;
      }
    }
    const std::string name = std::string(kAssimpGltf2) + "/" + file;
    const Status s = ReadGltf(name).status();
    EXPECT_EQ(s.code(), StatusCode::kCorruptFile) << file;
    EXPECT_EQ(s.message().rfind(name + ": " + path + " is ", 0), 0u)
        << s.message();
  }
}

// Each kind of rule on a hand-written file: the square read when valid,
// refused with the path when one property has the wrong type.
TEST(GltfImport, SchemaTypesAreCheckedForEachKindOfProperty) {
  const std::string valid =
      SquareText(R"("scene": 0, "scenes": [{"nodes": [0]}],
                 "nodes": [{"mesh": 0}])");
  ASSERT_TRUE(ReadGltfFromBuffer(valid).ok());
  struct Case {
    const char* from;
    std::string to;
    const char* message;  // before " (glTF 2.0 schema)"
  };
  const Case cases[] = {
      // glTF ids: integers >= 0.
      {R"("scene": 0)", R"("scene": -1)",
       "scene is -1, not a non-negative integer"},
      {R"("scene": 0)", R"("scene": 1.5)",
       "scene is 1.5, not a non-negative integer"},
      {R"("mesh": 0)", R"("mesh": 0, "children": [true])",
       "nodes[0].children[0] is true, not a non-negative integer"},
      {R"("POSITION": 0)", R"("POSITION": "0")",
       "meshes[0].primitives[0].attributes.POSITION is \"0\", not a "
       "non-negative integer"},
      {R"("mode": 5)", R"("mode": 5, "targets": [{"POSITION": -2}])",
       "meshes[0].primitives[0].targets[0].POSITION is -2, not a "
       "non-negative integer"},
      // Other integers, numbers, booleans, strings.
      {R"("mode": 5)", R"("mode": "5")",
       "meshes[0].primitives[0].mode is \"5\", not an integer"},
      {R"("scene": 0)", R"("samplers": [{"magFilter": 9729.5}], "scene": 0)",
       "samplers[0].magFilter is 9729.5, not an integer"},
      {R"("mesh": 0)", R"("mesh": 0, "scale": [1, null, 1])",
       "nodes[0].scale[1] is null, not a number"},
      {R"("scene": 0)",
       R"("materials": [{"emissiveFactor": [1, "0", 0]}], "scene": 0)",
       "materials[0].emissiveFactor[1] is \"0\", not a number"},
      {R"("scene": 0)", R"("materials": [{"doubleSided": 1}], "scene": 0)",
       "materials[0].doubleSided is 1, not a boolean"},
      {R"("nodes": [0])", R"("nodes": [0], "name": 42)",
       "scenes[0].name is 42, not a string"},
      {R"("scene": 0)", R"("images": [{"uri": 7}], "scene": 0)",
       "images[0].uri is 7, not a string"},
      {R"("version": "2.0")", R"("version": 2)",
       "asset.version is 2, not a string"},
      {R"("scene": 0)", R"("extensionsUsed": ["KHR_x", 3], "scene": 0)",
       "extensionsUsed[1] is 3, not a string"},
      // Objects and arrays.
      {R"({"version": "2.0"})", R"("2.0")", "asset is \"2.0\", not an object"},
      {R"("mesh": 0)", R"("mesh": 0, "matrix": 3)",
       "nodes[0].matrix is 3, not an array"},
      {R"("type": "VEC3")",
       R"("type": "VEC3", "sparse": {"count": 1, "indices": []})",
       "accessors[0].sparse.indices is an array, not an object"},
      // Extensions: an object of objects, anywhere.
      {R"("scene": 0)", R"("extensions": [], "scene": 0)",
       "extensions is an array, not an object"},
      {R"("mesh": 0)", R"("mesh": 0, "extensions": {"EXT_x": 1})",
       "nodes[0].extensions.EXT_x is 1, not an object"},
      {R"("mesh": 0)", R"("mesh": 0, "extensions": {"a b\n": []})",
       R"(nodes[0].extensions["a b\n"] is an array, not an object)"},
      // Long strings are cut.
      {R"("scene": 0)", "\"scene\": \"" + std::string(100, 'x') + "\"",
       "scene is \"xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx...\", not a "
       "non-negative integer"},
  };
  for (const Case& c : cases) {
    std::string text = valid;
    text.replace(text.find(c.from), std::strlen(c.from), c.to);
    const Status s = ReadGltfFromBuffer(text).status();
    EXPECT_EQ(s.code(), StatusCode::kCorruptFile) << c.message;
    EXPECT_EQ(s.message(), std::string(c.message) + " (glTF 2.0 schema)");
  }
  // Not an object at all.
  EXPECT_EQ(ReadGltfFromBuffer("[]").status().message(),
            "the JSON is an array, not an object (glTF 2.0 schema)");
  // The JSON chunk of a GLB is checked as a .gltf is.
  std::string bad_name = valid;
  bad_name.replace(bad_name.find(R"("nodes": [0])"), 12,
                   R"("nodes": [0], "name": 42)");
  EXPECT_EQ(ReadGltfFromBuffer(PackGlb(bad_name, "")).status().message(),
            "scenes[0].name is 42, not a string (glTF 2.0 schema)");
  // Unknown properties and extras of any type, an id written 0.0 (JSON
  // Schema's integer) and extensions that are objects are read.
  std::string allowed = valid;
  allowed.replace(allowed.find(R"("scene": 0)"), 10,
                  R"("scene": 0.0, "extras": 5, "unknown": "x")");
  allowed.replace(allowed.find(R"("mesh": 0)"), 9,
                  R"("mesh": 0, "extras": [1], "foo": null,
                     "extensions": {"EXT_x": {}})");
  const StatusOr<GltfAsset> asset = ReadGltfFromBuffer(allowed);
  ASSERT_TRUE(asset.ok()) << asset.status().message();
  EXPECT_EQ(asset->primitives.size(), 1u);
}

}  // namespace
}  // namespace sdcb

namespace sdcb {
namespace {

// The fuzzer's corpus (fuzz/corpus/gltf, with the inputs of past findings as
// regression-NAME): seeds read, every file reads or fails in one sentence.
TEST(GltfImport, FuzzCorpusReadsOrFailsInOneSentence) {
  const std::filesystem::path dir =
      std::filesystem::path(SDCB_SOURCE_DIR) / "fuzz" / "corpus" / "gltf";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    SCOPED_TRACE(entry.path().string());
    const StatusOr<GltfAsset> asset =
        ReadGltfFromBuffer(ReadBytes(entry.path().string()));
    if (entry.path().filename().string().rfind("regression-", 0) != 0) {
      EXPECT_TRUE(asset.ok()) << asset.status().message();
    }
    if (!asset.ok()) {
      EXPECT_FALSE(asset.status().message().empty());
      EXPECT_EQ(asset.status().message().find('\n'), std::string::npos);
    }
    ++files;
  }
  EXPECT_GE(files, 4);
}

}  // namespace
}  // namespace sdcb
