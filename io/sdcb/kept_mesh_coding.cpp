#include "sdcb/io/sdcb/kept_mesh_coding.h"

#include <meshoptimizer.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "sdcb/io/sdcb/byte_packing.h"
#include "sdcb/io/sdcb/sdcb_chunks.h"

namespace sdcb::sdcb_internal {
namespace {

constexpr size_t kKeptHeadBytes = 20;  // u64 V, u64 F, u32 position form
// The position forms of a kept part's HEAD.
constexpr uint32_t kFloat64Positions = 0;  // 24 bytes per vertex
constexpr uint32_t kFloat32Positions = 1;  // 12 bytes per vertex
// EXT_meshopt_compression's index format; decodable by meshoptimizer 0.14+.
constexpr int kIndexCodecVersion = 1;

bool IsFloat(double x) {
  const double back = static_cast<double>(static_cast<float>(x));
  return std::memcmp(&back, &x, sizeof x) == 0;
}

// The vertices as meshoptimizer's vertex codec takes them: `form`'s bytes
// per vertex, x y z in order, little-endian (the machines sdcb builds on).
std::vector<unsigned char> VertexBytes(const Eigen::MatrixX3d& v,
                                       uint32_t form) {
  const size_t width = form == kFloat32Positions ? 4 : 8;
  std::vector<unsigned char> out(static_cast<size_t>(v.rows()) * 3 * width);
  unsigned char* p = out.data();
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    for (int c = 0; c < 3; ++c, p += width) {
      if (form == kFloat32Positions) {
        const auto f = static_cast<float>(v(i, c));
        std::memcpy(p, &f, width);
      } else {
        std::memcpy(p, &v(i, c), width);
      }
    }
  }
  return out;
}

Status Bad(const std::string& what) {
  return Corrupt("the KEPT chunk " + what);
}

}  // namespace

KeptMeshPayloads EncodeKeptMesh(const TriangleMesh& mesh) {
  const auto nv = static_cast<size_t>(mesh.num_vertices());
  const auto nf = static_cast<size_t>(mesh.num_faces());
  bool floats = true;
  for (Eigen::Index i = 0; floats && i < mesh.vertices.size(); ++i) {
    floats = IsFloat(mesh.vertices.data()[i]);
  }
  const uint32_t form = floats ? kFloat32Positions : kFloat64Positions;
  const size_t vertex_size = floats ? 12 : 24;

  const std::vector<unsigned char> vertices = VertexBytes(mesh.vertices, form);
  std::vector<unsigned char> vertex_stream(
      meshopt_encodeVertexBufferBound(nv, vertex_size));
  vertex_stream.resize(
      meshopt_encodeVertexBuffer(vertex_stream.data(), vertex_stream.size(),
                                 vertices.data(), nv, vertex_size));

  std::vector<unsigned int> indices(3 * nf);
  for (size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      indices[3 * f + k] = static_cast<unsigned int>(mesh.faces(f, k));
    }
  }
  meshopt_encodeIndexVersion(kIndexCodecVersion);
  std::vector<unsigned char> index_stream(
      meshopt_encodeIndexBufferBound(indices.size(), nv));
  index_stream.resize(
      meshopt_encodeIndexBuffer(index_stream.data(), index_stream.size(),
                                indices.data(), indices.size()));
  // The codec's rotations: decoded (d0, d1, d2) is the input (a, b, c) read
  // from `r` on, a = d_r.
  std::vector<unsigned int> decoded(indices.size());
  (void)meshopt_decodeIndexBuffer(decoded.data(), decoded.size(),
                                  sizeof(unsigned int), index_stream.data(),
                                  index_stream.size());
  std::string rotations(nf, '\0');
  for (size_t f = 0; f < nf; ++f) {
    for (char r = 0; r < 3; ++r) {
      if (decoded[3 * f + r] == indices[3 * f] &&
          decoded[3 * f + (r + 1) % 3] == indices[3 * f + 1]) {
        rotations[f] = r;
        break;
      }
    }
  }

  KeptMeshPayloads out;
  ByteWriter head;
  head.U64(nv);
  head.U64(nf);
  head.U32(form);
  out.head = std::move(head.str());
  ByteWriter kept;
  kept.U64(vertex_stream.size());
  kept.Bytes(
      std::string_view(reinterpret_cast<const char*>(vertex_stream.data()),
                       vertex_stream.size()));
  kept.U64(index_stream.size());
  kept.Bytes(std::string_view(
      reinterpret_cast<const char*>(index_stream.data()), index_stream.size()));
  kept.Bytes(Packed(rotations));
  out.kept = std::move(kept.str());
  return out;
}

StatusOr<TriangleMesh> DecodeKeptMesh(std::string_view head,
                                      std::string_view kept, size_t file_size) {
  if (head.size() != kKeptHeadBytes) {
    return Corrupt("a kept part's HEAD chunk has " + Str(head.size()) +
                   " bytes; it needs " + Str(kKeptHeadBytes));
  }
  ByteReader h(head);
  uint64_t nv = 0, nf = 0;
  uint32_t form = 0;
  (void)h.U64(&nv);
  (void)h.U64(&nf);
  (void)h.U32(&form);
  if (form != kFloat64Positions && form != kFloat32Positions) {
    return Corrupt("a kept part's HEAD declares position form " + Str(form) +
                   " (0 or 1)");
  }
  if (nf == 0) return Corrupt("a kept part's HEAD declares 0 triangles");
  const size_t vertex_size = form == kFloat32Positions ? 12 : 24;
  // meshoptimizer's codecs expand less than deflate does.
  SDCB_RETURN_IF_ERROR(
      CheckCount(nv, vertex_size, kMaxDeflateRatio, file_size, "vertices"));
  SDCB_RETURN_IF_ERROR(
      CheckCount(nf, 12, kMaxDeflateRatio, file_size, "triangles"));

  ByteReader r(kept);
  uint64_t vertex_bytes = 0;
  if (!r.U64(&vertex_bytes) || vertex_bytes > r.remaining()) {
    return Bad("is shorter than its vertex stream");
  }
  const std::string_view rest = r.Rest();
  const std::string_view vertex_stream = rest.substr(0, vertex_bytes);
  ByteReader r2(rest.substr(vertex_bytes));
  uint64_t index_bytes = 0;
  if (!r2.U64(&index_bytes) || index_bytes > r2.remaining()) {
    return Bad("is shorter than its index stream");
  }
  const std::string_view rest2 = r2.Rest();
  const std::string_view index_stream = rest2.substr(0, index_bytes);
  SDCB_ASSIGN_OR_RETURN(
      const std::string rotations,
      Unpacked(rest2.substr(index_bytes), static_cast<int64_t>(nf), "KEPT"));

  std::vector<unsigned char> vertices(nv * vertex_size);
  if (meshopt_decodeVertexBuffer(
          vertices.data(), nv, vertex_size,
          reinterpret_cast<const unsigned char*>(vertex_stream.data()),
          vertex_stream.size()) != 0) {
    return Bad("holds a vertex stream meshoptimizer cannot decode");
  }
  std::vector<unsigned int> indices(3 * nf);
  if (meshopt_decodeIndexBuffer(
          indices.data(), indices.size(), sizeof(unsigned int),
          reinterpret_cast<const unsigned char*>(index_stream.data()),
          index_stream.size()) != 0) {
    return Bad("holds an index stream meshoptimizer cannot decode");
  }

  TriangleMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(nv), 3);
  const unsigned char* p = vertices.data();
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      double x;
      if (form == kFloat32Positions) {
        float f;
        std::memcpy(&f, p, sizeof f);
        p += sizeof f;
        x = f;
      } else {
        std::memcpy(&x, p, sizeof x);
        p += sizeof x;
      }
      if (!std::isfinite(x)) {
        return Bad("holds a vertex that is not finite (vertex " + Str(i) + ")");
      }
      mesh.vertices(i, c) = x;
    }
  }
  mesh.faces.resize(static_cast<Eigen::Index>(nf), 3);
  for (uint64_t f = 0; f < nf; ++f) {
    const auto rot = static_cast<unsigned char>(rotations[f]);
    if (rot > 2) {
      return Bad("declares rotation " + Str(rot) + " for triangle " + Str(f) +
                 " (0, 1 or 2)");
    }
    for (int k = 0; k < 3; ++k) {
      const unsigned int v = indices[3 * f + (rot + k) % 3];
      if (v >= nv) {
        return Bad("has triangle " + Str(f) + " refer to vertex " + Str(v) +
                   " of " + Str(nv));
      }
      mesh.faces(static_cast<Eigen::Index>(f), k) = static_cast<int>(v);
    }
  }
  return mesh;
}

}  // namespace sdcb::sdcb_internal
