// EncodeGltf's meshopt modes decoded here with libmeshoptimizer's own
// decoders (meshopt_decodeVertexBuffer, meshopt_decodeFilterExp), not with
// the encoder's code or sdcb's reader.
#include "sdcb/converters/gltf/gltf_export.h"

#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sdcb/converters/gltf/glb_container.h"
#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {
namespace {

using Json = nlohmann::json;

// The decoded bytes of buffer view `v` of a meshopt GLB (filter applied).
std::vector<unsigned char> DecodeView(const Json& json, std::string_view bin,
                                      int v) {
  const Json& ext =
      json["bufferViews"][v]["extensions"]["EXT_meshopt_compression"];
  const size_t count = ext["count"], stride = ext["byteStride"];
  const size_t offset = ext.value("byteOffset", size_t{0});
  const size_t length = ext["byteLength"];
  std::vector<unsigned char> out(count * stride);
  const auto* source =
      reinterpret_cast<const unsigned char*>(bin.data() + offset);
  EXPECT_EQ(ext["mode"], "ATTRIBUTES");
  EXPECT_EQ(
      meshopt_decodeVertexBuffer(out.data(), count, stride, source, length), 0);
  if (ext.value("filter", "NONE") == "EXPONENTIAL") {
    meshopt_decodeFilterExp(out.data(), count, stride);
  }
  return out;
}

// An icosphere of radius 2.5 away from the origin (so vertices take
// several exponents), each vertex's index in its first texture coordinate
// (index / 65535, which the normalized unsigned shorts hold exactly).
SurfaceMesh OffsetSphere() {
  const TriangleMesh sphere = MakeIcosphere(3);
  SurfaceMesh mesh;
  mesh.positions = sphere.vertices * 2.5;
  mesh.positions.rowwise() += Eigen::RowVector3d(7.0, -3.0, 1.5);
  mesh.normals = sphere.vertices.rowwise().normalized();
  mesh.faces = sphere.faces;
  mesh.texcoords.resize(mesh.positions.rows(), 2);
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    mesh.texcoords(v, 0) = v / 65535.0;
    mesh.texcoords(v, 1) = 0.5;
  }
  return mesh;
}

// The largest distance of the exponential filter's decoded positions with
// `bits` mantissa bits from `positions` (meshoptimizer's encoder and
// decoder, independently of EncodeGltf).
double ExponentialError(const Eigen::MatrixX3d& positions, int bits) {
  const size_t n = positions.rows();
  std::vector<float> xyz(3 * n);
  for (size_t v = 0; v < n; ++v) {
    for (int k = 0; k < 3; ++k) xyz[3 * v + k] = float(positions(v, k));
  }
  std::vector<float> decoded(3 * n);
  meshopt_encodeFilterExp(decoded.data(), n, 12, bits, xyz.data());
  meshopt_decodeFilterExp(decoded.data(), n, 12);
  double worst = 0.0;
  for (size_t v = 0; v < n; ++v) {
    const Eigen::Vector3d p(decoded[3 * v], decoded[3 * v + 1],
                            decoded[3 * v + 2]);
    worst = std::max(worst, (p - positions.row(v).transpose()).norm());
  }
  return worst;
}

TEST(GltfExportTest, ExponentialPositionsStateTheirDecodedError) {
  const SurfaceMesh mesh = OffsetSphere();
  for (const int bits : {6, 10, 14, 16}) {
    SCOPED_TRACE(bits);
    GltfExportOptions options;
    options.compression = GltfCompression::kMeshopt;
    options.meshopt_positions = GltfMeshoptPositions::kExponential;
    options.position_bits = bits;
    const StatusOr<EncodedGltf> encoded = EncodeGltf(mesh, options, true);
    ASSERT_TRUE(encoded.ok()) << encoded.status().message();
    const GltfExportResult& result = encoded->result;
    const StatusOr<GlbChunks> chunks = SplitGlb(encoded->bytes);
    ASSERT_TRUE(chunks.ok());
    const Json json = Json::parse(chunks->json);

    // No node transform; float positions through the exponential filter.
    ASSERT_EQ(json["nodes"].size(), 1u);
    EXPECT_EQ(json["nodes"][0], Json({{"mesh", 0}}));
    const Json& attributes = json["meshes"][0]["primitives"][0]["attributes"];
    const Json& position = json["accessors"][attributes["POSITION"].get<int>()];
    EXPECT_EQ(position["componentType"], 5126);
    const int view = position["bufferView"];
    const Json& ext =
        json["bufferViews"][view]["extensions"]["EXT_meshopt_compression"];
    EXPECT_EQ(ext["filter"], "EXPONENTIAL");
    EXPECT_EQ(ext["byteStride"], 12);
    EXPECT_EQ(json["bufferViews"][view]["byteStride"], 12);
    const Json& uv = json["accessors"][attributes["TEXCOORD_0"].get<int>()];
    EXPECT_EQ(uv["componentType"], 5123);
    EXPECT_EQ(uv["normalized"], true);

    const std::vector<unsigned char> p = DecodeView(json, chunks->bin, view);
    const std::vector<unsigned char> t =
        DecodeView(json, chunks->bin, uv["bufferView"].get<int>());
    const size_t count = position["count"];
    ASSERT_EQ(count, static_cast<size_t>(mesh.positions.rows()));
    double worst = 0.0;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL),
                    hi = Eigen::Vector3d::Constant(-HUGE_VAL);
    for (size_t i = 0; i < count; ++i) {
      float xyz[3];
      std::memcpy(xyz, p.data() + 12 * i, 12);
      uint16_t st[2];
      std::memcpy(st, t.data() + 4 * i, 4);
      const int v = st[0];  // the vertex's index before meshopt's reorder
      ASSERT_LT(v, mesh.positions.rows());
      const Eigen::Vector3d decoded(xyz[0], xyz[1], xyz[2]);
      worst =
          std::max(worst, (decoded - mesh.positions.row(v).transpose()).norm());
      lo = lo.cwiseMin(decoded);
      hi = hi.cwiseMax(decoded);
    }
    // The stated error is the decoded one (to the rounding of the distance
    // computed here), within the grid's budget.
    EXPECT_LE(worst, result.quantization_error * (1.0 + 1e-12));
    EXPECT_GE(worst, 0.999 * result.quantization_error);
    const double budget =
        std::sqrt(3.0) / 2.0 * QuantizationStep(mesh.positions, bits);
    EXPECT_LE(result.quantization_error, budget);
    // The fewest bits: one fewer misses the budget.
    ASSERT_GE(result.exponential_bits, 1);
    ASSERT_LE(result.exponential_bits, 23);
    if (result.exponential_bits > 1) {
      EXPECT_GT(ExponentialError(mesh.positions, result.exponential_bits - 1),
                budget);
    }
    // min / max are the decoded values'.
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(position["min"][k].get<double>(), lo[k]);
      EXPECT_EQ(position["max"][k].get<double>(), hi[k]);
    }
  }
}

TEST(GltfExportTest, MeshoptRefusesTextureCoordinatesOutsideTheUnitSquare) {
  SurfaceMesh mesh = OffsetSphere();
  mesh.texcoords(3, 1) = 1.5;
  GltfExportOptions options;
  options.compression = GltfCompression::kMeshopt;
  EXPECT_EQ(EncodeGltf(mesh, options, true).status().code(),
            StatusCode::kInvalidArgument);
  options.compression = GltfCompression::kNone;
  EXPECT_TRUE(EncodeGltf(mesh, options, true).ok());
}

}  // namespace
}  // namespace sdcb
