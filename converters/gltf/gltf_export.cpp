#include "sdcb/converters/gltf/gltf_export.h"

#include <draco/io/gltf_encoder.h>
#include <draco/mesh/mesh.h>
#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "sdcb/converters/gltf/glb_container.h"
#include "sdcb/converters/gltf/gltf_gather.h"
#include "sdcb/io/common/atomic_file.h"

namespace sdcb {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122,
              kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::string PackGlbJson(const Json& json, std::string bin) {
  return PackGlb(json.dump(), std::move(bin));
}

// Splits a GLB the encoder wrote into its JSON and BIN chunks.
Status UnpackGlb(const std::string& glb, Json* json, std::string* bin) {
  StatusOr<GlbChunks> chunks = SplitGlb(glb);
  if (!chunks.ok()) {
    return InternalError("the encoder wrote a bad GLB: " +
                         chunks.status().message());
  }
  *json = Json::parse(chunks->json);
  *bin = std::string(chunks->bin);
  return Status::Ok();
}

std::string Base64(const std::string& data) {
  static const char* kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = static_cast<unsigned char>(data[i]) << 16;
    if (i + 1 < data.size()) v |= static_cast<unsigned char>(data[i + 1]) << 8;
    if (i + 2 < data.size()) v |= static_cast<unsigned char>(data[i + 2]);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(i + 1 < data.size() ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back(i + 2 < data.size() ? kAlphabet[v & 63] : '=');
  }
  return out;
}

// The file bytes for `json` + `bin` (buffer 0): a GLB, or a .gltf with the
// buffer as a data URI.
std::string Container(Json json, const std::string& bin, bool glb) {
  if (glb) return PackGlbJson(json, bin);
  if (!bin.empty()) {
    json["buffers"][0]["uri"] =
        "data:application/octet-stream;base64," + Base64(bin);
  }
  return json.dump(1) + "\n";
}

// Draco's encoder names itself; the contract says "sdcb".
void SetGenerator(Json* json) {
  (*json)["asset"]["generator"] = "sdcb";
  (*json)["asset"]["version"] = "2.0";
}

template <typename T>
void Append(std::string* bin, const T* data, size_t count) {
  bin->append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

// --- plain: float32 through tinygltf ---------------------------------------

StatusOr<std::string> EncodePlain(const SurfaceMesh& mesh, bool glb) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "sdcb";
  const size_t nv = mesh.positions.rows(), nf = mesh.faces.rows();
  const bool normals = mesh.normals.rows() > 0;
  const bool colors = mesh.colors.rows() > 0;
  const bool texcoords = mesh.texcoords.rows() > 0;
  std::string bin;
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  auto add_view = [&](size_t offset, size_t length, int target, int stride) {
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = length;
    view.byteStride = stride;
    view.target = target;
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size()) - 1;
  };
  auto add_accessor = [&](int view, int component, int type, size_t count,
                          bool normalized) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.type = type;
    a.count = count;
    a.normalized = normalized;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size()) - 1;
  };
  // Positions with min / max.
  {
    std::vector<float> xyz(3 * nv);
    std::vector<double> lo(3, std::numeric_limits<double>::max()),
        hi(3, std::numeric_limits<double>::lowest());
    for (size_t v = 0; v < nv; ++v) {
      for (int k = 0; k < 3; ++k) {
        xyz[3 * v + k] = static_cast<float>(mesh.positions(v, k));
        lo[k] = std::min(lo[k], double{xyz[3 * v + k]});
        hi[k] = std::max(hi[k], double{xyz[3 * v + k]});
      }
    }
    const size_t offset = bin.size();
    Append(&bin, xyz.data(), xyz.size());
    const int a =
        add_accessor(add_view(offset, bin.size() - offset, kArrayBuffer, 0),
                     kFloat, TINYGLTF_TYPE_VEC3, nv, false);
    model.accessors[a].minValues = lo;
    model.accessors[a].maxValues = hi;
    primitive.attributes["POSITION"] = a;
  }
  if (normals) {
    std::vector<float> n(3 * nv);
    for (size_t v = 0; v < nv; ++v) {
      Eigen::Vector3f u = mesh.normals.row(v).transpose().cast<float>();
      u.normalize();
      for (int k = 0; k < 3; ++k) n[3 * v + k] = u[k];
    }
    const size_t offset = bin.size();
    Append(&bin, n.data(), n.size());
    primitive.attributes["NORMAL"] =
        add_accessor(add_view(offset, bin.size() - offset, kArrayBuffer, 0),
                     kFloat, TINYGLTF_TYPE_VEC3, nv, false);
  }
  if (colors) {
    // RGBA8: vertex attribute elements must be 4-byte aligned.
    std::vector<uint8_t> c(4 * nv);
    for (size_t v = 0; v < nv; ++v) {
      for (int k = 0; k < 3; ++k) c[4 * v + k] = mesh.colors(v, k);
      c[4 * v + 3] = 255;
    }
    const size_t offset = bin.size();
    Append(&bin, c.data(), c.size());
    primitive.attributes["COLOR_0"] =
        add_accessor(add_view(offset, bin.size() - offset, kArrayBuffer, 0),
                     kUnsignedByte, TINYGLTF_TYPE_VEC4, nv, true);
  }
  if (texcoords) {
    std::vector<float> uv(2 * nv);
    for (size_t v = 0; v < nv; ++v) {
      for (int k = 0; k < 2; ++k) uv[2 * v + k] = float(mesh.texcoords(v, k));
    }
    const size_t offset = bin.size();
    Append(&bin, uv.data(), uv.size());
    primitive.attributes["TEXCOORD_0"] =
        add_accessor(add_view(offset, bin.size() - offset, kArrayBuffer, 0),
                     kFloat, TINYGLTF_TYPE_VEC2, nv, false);
  }
  {
    const size_t offset = bin.size();
    if (nv <= 65535) {
      std::vector<uint16_t> idx(3 * nf);
      for (size_t f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k)
          idx[3 * f + k] = static_cast<uint16_t>(mesh.faces(f, k));
      Append(&bin, idx.data(), idx.size());
      primitive.indices = add_accessor(
          add_view(offset, bin.size() - offset, kElementArrayBuffer, 0),
          kUnsignedShort, TINYGLTF_TYPE_SCALAR, 3 * nf, false);
    } else {
      std::vector<uint32_t> idx(3 * nf);
      for (size_t f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k)
          idx[3 * f + k] = static_cast<uint32_t>(mesh.faces(f, k));
      Append(&bin, idx.data(), idx.size());
      primitive.indices = add_accessor(
          add_view(offset, bin.size() - offset, kElementArrayBuffer, 0),
          kUnsignedInt, TINYGLTF_TYPE_SCALAR, 3 * nf, false);
    }
  }
  Pad4(&bin, '\0');
  tinygltf::Buffer buffer;
  buffer.data.assign(bin.begin(), bin.end());
  model.buffers.push_back(std::move(buffer));
  tinygltf::Mesh m;
  m.primitives.push_back(primitive);
  model.meshes.push_back(m);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/!glb,
                                     glb)) {
    return InternalError("tinygltf could not serialize the mesh");
  }
  return stream.str();
}

// --- Draco ------------------------------------------------------------------

StatusOr<std::string> EncodeDraco(const SurfaceMesh& mesh,
                                  const GltfExportOptions& options, bool glb) {
  const int nv = static_cast<int>(mesh.positions.rows());
  draco::Mesh dm;
  dm.set_num_points(nv);
  auto add = [&](draco::GeometryAttribute::Type type, int components,
                 draco::DataType data_type, bool normalized, int bytes) {
    draco::GeometryAttribute a;
    a.Init(type, nullptr, components, data_type, normalized, bytes * components,
           0);
    return dm.AddAttribute(a, /*identity_mapping=*/true, nv);
  };
  const int pos =
      add(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32, false, 4);
  for (int v = 0; v < nv; ++v) {
    const float p[3] = {float(mesh.positions(v, 0)),
                        float(mesh.positions(v, 1)),
                        float(mesh.positions(v, 2))};
    dm.attribute(pos)->SetAttributeValue(draco::AttributeValueIndex(v), p);
  }
  if (mesh.normals.rows() > 0) {
    const int nrm =
        add(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32, false, 4);
    for (int v = 0; v < nv; ++v) {
      Eigen::Vector3f u =
          mesh.normals.row(v).transpose().cast<float>().normalized();
      dm.attribute(nrm)->SetAttributeValue(draco::AttributeValueIndex(v),
                                           u.data());
    }
  }
  if (mesh.colors.rows() > 0) {
    const int col =
        add(draco::GeometryAttribute::COLOR, 4, draco::DT_UINT8, true, 1);
    for (int v = 0; v < nv; ++v) {
      const uint8_t c[4] = {mesh.colors(v, 0), mesh.colors(v, 1),
                            mesh.colors(v, 2), 255};
      dm.attribute(col)->SetAttributeValue(draco::AttributeValueIndex(v), c);
    }
  }
  if (mesh.texcoords.rows() > 0) {
    const int uv = add(draco::GeometryAttribute::TEX_COORD, 2,
                       draco::DT_FLOAT32, false, 4);
    for (int v = 0; v < nv; ++v) {
      // Draco's meshes hold v up (its glTF decoder flips v, its encoder
      // flips it back).
      const float t[2] = {float(mesh.texcoords(v, 0)),
                          float(1.0 - mesh.texcoords(v, 1))};
      dm.attribute(uv)->SetAttributeValue(draco::AttributeValueIndex(v), t);
    }
  }
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    dm.AddFace({draco::PointIndex(mesh.faces(f, 0)),
                draco::PointIndex(mesh.faces(f, 1)),
                draco::PointIndex(mesh.faces(f, 2))});
  }
  draco::DracoCompressionOptions compression;
  compression.compression_level = options.draco_level;
  compression.quantization_position.SetQuantizationBits(options.position_bits);
  compression.quantization_bits_normal = 12;
  // A 2048-texel atlas to a sixteenth of a texel.
  compression.quantization_bits_tex_coord = 15;
  dm.SetCompressionEnabled(true);
  dm.SetCompressionOptions(compression);
  draco::GltfEncoder encoder;
  draco::EncoderBuffer buffer;
  const draco::Status s = encoder.EncodeToBuffer(dm, &buffer);
  if (!s.ok()) return InternalError("Draco: " + s.error_msg_string());
  Json json;
  std::string bin;
  SDCB_RETURN_IF_ERROR(
      UnpackGlb(std::string(buffer.data(), buffer.size()), &json, &bin));
  SetGenerator(&json);
  return Container(json, bin, glb);
}

// --- meshopt ----------------------------------------------------------------

// POSITION through EXT_meshopt_compression's EXPONENTIAL filter.
struct ExponentialPositions {
  std::vector<uint32_t> data;  // what the view holds, 3 words per vertex
  std::vector<float> decoded;  // what a decoder reads back
  int bits = 0;                // mantissa bits K; 24: unfiltered floats
  double error = 0.0;          // largest distance decoded - exact
  double step = 0.0;           // largest 2^exponent (0 unfiltered)
  std::vector<double> lo, hi;  // the decoded values' min / max, 3 each
};

// The largest distance between the vertices of `decoded` and `exact` (3
// values per vertex each).
double LargestDistance(const std::vector<double>& exact,
                       const std::vector<float>& decoded) {
  double worst = 0.0;
  for (size_t i = 0; i + 2 < exact.size(); i += 3) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double d = double{decoded[i + k]} - exact[i + k];
      d2 += d * d;
    }
    worst = std::max(worst, std::sqrt(d2));
  }
  return worst;
}

// Sets `p`'s lo and hi from its decoded values.
void SetBounds(ExponentialPositions* p) {
  p->lo.assign(3, 0.0);
  p->hi.assign(3, 0.0);
  for (size_t i = 0; i < p->decoded.size(); ++i) {
    const double x = p->decoded[i];
    const int k = i % 3;
    p->lo[k] = i < 3 ? x : std::min(p->lo[k], x);
    p->hi[k] = i < 3 ? x : std::max(p->hi[k], x);
  }
}

// `exact` (3 values per vertex) as float32 encoded by meshopt_encodeFilterExp
// (one exponent per vertex) with the fewest mantissa bits whose decoded
// positions (meshopt_decodeFilterExp, as a loader decodes them) are within
// `max_error` of `exact`. Bits stop at 23: meshoptimizer 0.18 wraps a 24-bit
// mantissa that rounds up to 2^23 into the sign bit. Where 23 are not
// enough, the floats themselves (filter NONE).
ExponentialPositions EncodeExponential(const std::vector<double>& exact,
                                       double max_error) {
  const size_t n = exact.size() / 3;
  std::vector<float> xyz(exact.size());
  for (size_t i = 0; i < exact.size(); ++i) xyz[i] = float(exact[i]);
  ExponentialPositions out;
  out.data.resize(xyz.size());
  out.decoded.resize(xyz.size());
  for (int bits = 1; bits <= 23; ++bits) {
    meshopt_encodeFilterExp(out.data.data(), n, 12, bits, xyz.data());
    std::memcpy(out.decoded.data(), out.data.data(), 4 * xyz.size());
    meshopt_decodeFilterExp(out.decoded.data(), n, 12);
    out.error = LargestDistance(exact, out.decoded);
    if (out.error <= max_error) {
      out.bits = bits;
      for (size_t i = 0; i < out.data.size(); i += 3) {
        const int exponent = static_cast<int8_t>(out.data[i] >> 24);
        out.step = std::max(out.step, std::ldexp(1.0, exponent));
      }
      SetBounds(&out);
      return out;
    }
  }
  out.bits = 24;
  std::memcpy(out.data.data(), xyz.data(), 4 * xyz.size());
  out.decoded = xyz;
  out.error = LargestDistance(exact, out.decoded);
  out.step = 0.0;
  SetBounds(&out);
  return out;
}

// EncodeMeshopt's vertex streams in meshopt's order (vertex cache order for
// the triangles, then vertex fetch order); only the vertices a face uses.
struct MeshoptStreams {
  std::vector<unsigned int> indices;  // 3 per triangle
  size_t count = 0;                   // vertices
  // Quantized positions (x, y, z, 0) on the grid of `step` from `lo`, or
  // for exponential ones the exact positions (x, y, z).
  std::vector<uint16_t> q;
  uint16_t qmin[3] = {65535, 65535, 65535}, qmax[3] = {0, 0, 0};
  std::vector<double> exact;
  std::vector<int16_t> n;    // normals (x, y, z, 0), normalized shorts
  std::vector<uint8_t> c;    // colors (r, g, b, 255)
  std::vector<uint16_t> uv;  // texture coordinates, normalized
};

MeshoptStreams MakeMeshoptStreams(const SurfaceMesh& mesh, bool exponential,
                                  int bits, double step,
                                  const Eigen::RowVector3d& lo) {
  const size_t nv = mesh.positions.rows(), ni = 3 * mesh.faces.rows();
  MeshoptStreams s;
  std::vector<unsigned int>& indices = s.indices;
  indices.resize(ni);
  for (size_t i = 0; i < ni; ++i) indices[i] = mesh.faces(i / 3, i % 3);
  meshopt_optimizeVertexCache(indices.data(), indices.data(), ni, nv);
  std::vector<unsigned int> remap(nv);
  const size_t unique =
      meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), ni, nv);
  meshopt_remapIndexBuffer(indices.data(), indices.data(), ni, remap.data());
  s.count = unique;
  // Vertices never referenced by a face do not exist in a closed mesh.
  std::vector<size_t> source(unique);
  for (size_t v = 0; v < nv; ++v) {
    if (remap[v] != ~0u) source[remap[v]] = v;
  }
  const bool normals = mesh.normals.rows() > 0, colors = mesh.colors.rows() > 0,
             texcoords = mesh.texcoords.rows() > 0;
  s.q.assign(exponential ? 0 : 4 * unique, 0);
  s.exact.resize(exponential ? 3 * unique : 0);
  s.n.assign(4 * unique, 0);
  s.c.assign(4 * unique, 255);
  s.uv.resize(texcoords ? 2 * unique : 0);
  const double levels = std::pow(2.0, bits) - 1.0;
  for (size_t i = 0; i < unique; ++i) {
    const size_t v = source[i];
    for (int k = 0; k < 3; ++k) {
      if (exponential) {
        s.exact[3 * i + k] = mesh.positions(v, k);
        continue;
      }
      const double t = std::round((mesh.positions(v, k) - lo[k]) / step);
      const uint16_t u = static_cast<uint16_t>(std::clamp(t, 0.0, levels));
      s.q[4 * i + k] = u;
      s.qmin[k] = std::min(s.qmin[k], u);
      s.qmax[k] = std::max(s.qmax[k], u);
    }
    if (normals) {
      const Eigen::Vector3d u = mesh.normals.row(v).transpose().normalized();
      for (int k = 0; k < 3; ++k)
        s.n[4 * i + k] = static_cast<int16_t>(std::lround(u[k] * 32767.0));
    }
    if (colors) {
      for (int k = 0; k < 3; ++k) s.c[4 * i + k] = mesh.colors(v, k);
    }
    if (texcoords) {
      for (int k = 0; k < 2; ++k) {
        s.uv[2 * i + k] =
            static_cast<uint16_t>(std::lround(mesh.texcoords(v, k) * 65535.0));
      }
    }
  }
  return s;
}

// `result` holds the grid's step and error (QuantizationStep of
// options.position_bits); exponential positions replace them with theirs.
StatusOr<std::string> EncodeMeshopt(const SurfaceMesh& mesh,
                                    const GltfExportOptions& options, bool glb,
                                    GltfExportResult* result) {
  const bool exponential =
      options.meshopt_positions == GltfMeshoptPositions::kExponential;
  const double step = result->quantization_step;
  const Eigen::RowVector3d lo = mesh.positions.colwise().minCoeff();
  const MeshoptStreams s =
      MakeMeshoptStreams(mesh, exponential, options.position_bits, step, lo);
  const std::vector<unsigned int>& indices = s.indices;
  const size_t unique = s.count, ni = indices.size();
  const bool normals = mesh.normals.rows() > 0, colors = mesh.colors.rows() > 0,
             texcoords = mesh.texcoords.rows() > 0;
  std::string bin;
  Json views = Json::array();
  size_t fallback_size = 0;
  // One compressed buffer view: the uncompressed layout lives in the
  // fallback buffer 1, the encoded bytes in buffer 0.
  auto add_view = [&](const std::vector<unsigned char>& encoded, size_t stride,
                      size_t count, const char* mode, int target,
                      const char* filter = nullptr) {
    Pad4(&bin, '\0');
    Json ext = {{"buffer", 0},
                {"byteOffset", bin.size()},
                {"byteLength", encoded.size()},
                {"byteStride", stride},
                {"count", count},
                {"mode", mode}};
    if (filter != nullptr) ext["filter"] = filter;
    bin.append(reinterpret_cast<const char*>(encoded.data()), encoded.size());
    Json view = {{"buffer", 1},
                 {"byteOffset", fallback_size},
                 {"byteLength", stride * count}};
    if (target == kArrayBuffer) view["byteStride"] = stride;
    view["target"] = target;
    view["extensions"] = {{"EXT_meshopt_compression", ext}};
    fallback_size += stride * count;
    fallback_size = (fallback_size + 3) / 4 * 4;
    views.push_back(view);
    return static_cast<int>(views.size()) - 1;
  };
  auto encode_vertices = [&](const void* data, size_t stride) {
    std::vector<unsigned char> out(
        meshopt_encodeVertexBufferBound(unique, stride));
    out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data, unique,
                                          stride));
    return out;
  };
  Json accessors = Json::array();
  Json attributes;
  if (exponential) {
    const ExponentialPositions p =
        EncodeExponential(s.exact, std::sqrt(3.0) / 2.0 * step);
    result->quantization_error = p.error;
    result->quantization_step = p.step;
    result->exponential_bits = p.bits;
    const int view =
        add_view(encode_vertices(p.data.data(), 12), 12, unique, "ATTRIBUTES",
                 kArrayBuffer, p.bits <= 23 ? "EXPONENTIAL" : nullptr);
    accessors.push_back({{"bufferView", view},
                         {"componentType", kFloat},
                         {"count", unique},
                         {"type", "VEC3"},
                         {"min", p.lo},
                         {"max", p.hi}});
    attributes["POSITION"] = accessors.size() - 1;
  } else {
    const int view = add_view(encode_vertices(s.q.data(), 8), 8, unique,
                              "ATTRIBUTES", kArrayBuffer);
    accessors.push_back({{"bufferView", view},
                         {"componentType", kUnsignedShort},
                         {"count", unique},
                         {"type", "VEC3"},
                         {"min", {s.qmin[0], s.qmin[1], s.qmin[2]}},
                         {"max", {s.qmax[0], s.qmax[1], s.qmax[2]}}});
    attributes["POSITION"] = accessors.size() - 1;
  }
  // A normalized integer attribute, `stride` bytes per vertex.
  auto add_normalized = [&](const char* name, const void* data, size_t stride,
                            int component, const char* type) {
    const int view = add_view(encode_vertices(data, stride), stride, unique,
                              "ATTRIBUTES", kArrayBuffer);
    accessors.push_back({{"bufferView", view},
                         {"componentType", component},
                         {"normalized", true},
                         {"count", unique},
                         {"type", type}});
    attributes[name] = accessors.size() - 1;
  };
  if (normals) add_normalized("NORMAL", s.n.data(), 8, kShort, "VEC3");
  if (colors) add_normalized("COLOR_0", s.c.data(), 4, kUnsignedByte, "VEC4");
  if (texcoords) {
    add_normalized("TEXCOORD_0", s.uv.data(), 4, kUnsignedShort, "VEC2");
  }
  {
    meshopt_encodeIndexVersion(
        1);  // the version EXT_meshopt_compression requires
    std::vector<unsigned char> out(meshopt_encodeIndexBufferBound(ni, unique));
    out.resize(
        meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), ni));
    const bool small = unique <= 65535;
    const int view =
        add_view(out, small ? 2 : 4, ni, "TRIANGLES", kElementArrayBuffer);
    accessors.push_back(
        {{"bufferView", view},
         {"componentType", small ? kUnsignedShort : kUnsignedInt},
         {"count", ni},
         {"type", "SCALAR"}});
  }
  Pad4(&bin, '\0');
  Json json;
  json["asset"] = {{"version", "2.0"}, {"generator", "sdcb"}};
  // KHR_mesh_quantization for the short positions and normals (normalized
  // unsigned short texture coordinates are core glTF).
  Json extensions = Json::array({"EXT_meshopt_compression"});
  if (!exponential || normals) extensions.push_back("KHR_mesh_quantization");
  json["extensionsUsed"] = extensions;
  json["extensionsRequired"] = extensions;
  json["scene"] = 0;
  json["scenes"] = {{{"nodes", {0}}}};
  if (exponential) {
    json["nodes"] = {{{"mesh", 0}}};
  } else {
    json["nodes"] = {{{"mesh", 0},
                      {"translation", {lo[0], lo[1], lo[2]}},
                      {"scale", {step, step, step}}}};
  }
  json["meshes"] = {{{"primitives",
                      {{{"attributes", attributes},
                        {"indices", accessors.size() - 1},
                        {"mode", 4}}}}}};
  json["accessors"] = accessors;
  json["bufferViews"] = views;
  json["buffers"] = {
      {{"byteLength", bin.size()}},
      {{"byteLength", fallback_size},
       {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
  (void)kByte;
  return Container(json, bin, glb);
}

}  // namespace

double QuantizationStep(const Eigen::MatrixX3d& positions, int bits) {
  if (positions.rows() == 0) return 0.0;
  const double range =
      (positions.colwise().maxCoeff() - positions.colwise().minCoeff())
          .maxCoeff();
  return range / (std::pow(2.0, bits) - 1.0);
}

int PositionBitsFor(const Eigen::MatrixX3d& positions, double max_error,
                    int max_bits) {
  for (int bits = 1; bits < max_bits; ++bits) {
    if (std::sqrt(3.0) / 2.0 * QuantizationStep(positions, bits) <= max_error) {
      return bits;
    }
  }
  return max_bits;
}

StatusOr<EncodedGltf> EncodeGltf(const SurfaceMesh& mesh,
                                 const GltfExportOptions& options,
                                 bool binary) {
  const int max_bits =
      options.compression == GltfCompression::kMeshopt ? 16 : 30;
  if (options.compression != GltfCompression::kNone &&
      (options.position_bits < 1 || options.position_bits > max_bits)) {
    return InvalidArgumentError("position quantization bits must be in 1.." +
                                std::to_string(max_bits));
  }
  if (options.draco_level < 0 || options.draco_level > 10) {
    return InvalidArgumentError("Draco compression level must be in 0..10");
  }
  if (mesh.normals.rows() > 0) {
    for (Eigen::Index v = 0; v < mesh.normals.rows(); ++v) {
      if (std::abs(mesh.normals.row(v).norm() - 1.0) > 1e-6) {
        return InvalidArgumentError("vertex normal " + std::to_string(v) +
                                    " is not a unit vector");
      }
    }
  }
  if (mesh.texcoords.rows() != 0 &&
      mesh.texcoords.rows() != mesh.positions.rows()) {
    return InvalidArgumentError("texture coordinates are not one per vertex");
  }
  // meshopt stores them as normalized unsigned shorts.
  if (options.compression == GltfCompression::kMeshopt &&
      mesh.texcoords.rows() > 0 &&
      !(mesh.texcoords.minCoeff() >= 0.0 && mesh.texcoords.maxCoeff() <= 1.0)) {
    return InvalidArgumentError(
        "meshopt writes texture coordinates in [0, 1] only");
  }
  EncodedGltf out;
  GltfExportResult& result = out.result;
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    for (int k = 0; k < 3; ++k) {
      const double x = mesh.positions(v, k);
      result.float32_error =
          std::max(result.float32_error, std::abs(double(float(x)) - x));
    }
  }
  StatusOr<std::string> bytes = std::string();
  switch (options.compression) {
    case GltfCompression::kNone:
      bytes = EncodePlain(mesh, binary);
      break;
    case GltfCompression::kDraco: {
      // Draco quantizes the float32 positions over their bounding box.
      result.quantization_step =
          QuantizationStep(mesh.positions, options.position_bits);
      result.quantization_error =
          std::sqrt(3.0) / 2.0 * result.quantization_step;
      bytes = EncodeDraco(mesh, options, binary);
      break;
    }
    case GltfCompression::kMeshopt: {
      result.quantization_step =
          QuantizationStep(mesh.positions, options.position_bits);
      result.quantization_error =
          std::sqrt(3.0) / 2.0 * result.quantization_step;
      bytes = EncodeMeshopt(mesh, options, binary, &result);
      break;
    }
  }
  if (!bytes.ok()) return bytes.status();
  out.bytes = std::move(bytes).value();
  result.bytes = static_cast<int64_t>(out.bytes.size());
  return out;
}

GltfGather::GltfGather(Json json, std::string bin)
    : json_(std::move(json)), bin_(std::move(bin)) {
  if (!json_.contains("buffers") || json_["buffers"].empty()) {
    json_["buffers"] = Json::array({Json::object()});
  }
  for (const char* key : {"bufferViews", "accessors", "materials", "meshes",
                          "nodes", "extensionsUsed", "extensionsRequired"}) {
    if (!json_.contains(key)) json_[key] = Json::array();
  }
}

StatusOr<Json> GltfGather::AppendMesh(const EncodedGltf& encoded,
                                      bool keep_materials) {
  GltfExportResult& r = result_;
  r.quantization_error =
      std::max(r.quantization_error, encoded.result.quantization_error);
  r.quantization_step =
      std::max(r.quantization_step, encoded.result.quantization_step);
  r.float32_error = std::max(r.float32_error, encoded.result.float32_error);
  r.exponential_bits =
      std::max(r.exponential_bits, encoded.result.exponential_bits);
  Json j;
  std::string part_bin;
  SDCB_RETURN_IF_ERROR(UnpackGlb(encoded.bytes, &j, &part_bin));
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (!j.contains(key)) continue;
    Json& to = json_[key];
    for (const Json& e : j[key]) {
      if (std::find(to.begin(), to.end(), e) == to.end()) to.push_back(e);
    }
  }
  Pad4(&bin_, '\0');
  const size_t offset = bin_.size();
  bin_ += part_bin;
  // The part's buffer 0 (its BIN chunk) becomes part of buffer 0; other
  // buffers (meshopt's fallback, without data) are appended.
  Json& buffers = json_["buffers"];
  std::vector<int> buffer_of;
  if (j.contains("buffers")) {
    for (size_t b = 0; b < j["buffers"].size(); ++b) {
      if (b == 0) {
        buffer_of.push_back(0);
      } else {
        buffers.push_back(j["buffers"][b]);
        buffer_of.push_back(static_cast<int>(buffers.size()) - 1);
      }
    }
  }
  const auto rebase = [&](Json* v) {
    const int b = buffer_of.at((*v)["buffer"].get<int>());
    (*v)["buffer"] = b;
    if (b == 0) (*v)["byteOffset"] = v->value("byteOffset", size_t{0}) + offset;
  };
  Json& views = json_["bufferViews"];
  Json& accessors = json_["accessors"];
  Json& materials = json_["materials"];
  const size_t view0 = views.size(), accessor0 = accessors.size(),
               material0 = materials.size();
  if (j.contains("bufferViews")) {
    for (Json v : j["bufferViews"]) {
      rebase(&v);
      if (v.contains("extensions") &&
          v["extensions"].contains("EXT_meshopt_compression")) {
        rebase(&v["extensions"]["EXT_meshopt_compression"]);
      }
      views.push_back(v);
    }
  }
  if (j.contains("accessors")) {
    for (Json a : j["accessors"]) {
      if (a.contains("bufferView")) {
        a["bufferView"] = a["bufferView"].get<size_t>() + view0;
      }
      accessors.push_back(a);
    }
  }
  if (keep_materials && j.contains("materials")) {
    for (const Json& m : j["materials"]) materials.push_back(m);
  }
  Json mesh = j["meshes"].at(0);
  for (Json& p : mesh["primitives"]) {
    for (auto& [key, a] : p["attributes"].items()) {
      a = a.get<size_t>() + accessor0;
    }
    if (p.contains("indices")) {
      p["indices"] = p["indices"].get<size_t>() + accessor0;
    }
    if (p.contains("material")) {
      if (keep_materials) {
        p["material"] = p["material"].get<size_t>() + material0;
      } else {
        p.erase("material");
      }
    }
    if (p.contains("extensions") &&
        p["extensions"].contains("KHR_draco_mesh_compression")) {
      Json& d = p["extensions"]["KHR_draco_mesh_compression"];
      d["bufferView"] = d["bufferView"].get<size_t>() + view0;
    }
  }
  // The node EncodeGltf wrote (meshopt's dequantization transform).
  node_ = j["nodes"].at(0);
  node_.erase("mesh");
  return mesh;
}

EncodedGltf GltfGather::Finish(bool binary) {
  Pad4(&bin_, '\0');
  json_["buffers"][0]["byteLength"] = bin_.size();
  for (const char* key : {"bufferViews", "accessors", "materials", "meshes",
                          "nodes", "extensionsUsed", "extensionsRequired"}) {
    if (json_[key].empty()) json_.erase(key);
  }
  // glTF's usual order of the top-level keys; any others after them.
  Json ordered;
  for (const char* key :
       {"asset", "extensionsUsed", "extensionsRequired", "scene", "scenes",
        "nodes", "meshes", "materials", "textures", "images", "samplers",
        "accessors", "bufferViews", "buffers"}) {
    if (json_.contains(key)) ordered[key] = std::move(json_[key]);
  }
  for (auto& [key, value] : json_.items()) {
    if (!ordered.contains(key)) ordered[key] = std::move(value);
  }
  EncodedGltf out;
  out.bytes = Container(ordered, bin_, binary);
  out.result = result_;
  out.result.bytes = static_cast<int64_t>(out.bytes.size());
  return out;
}

StatusOr<EncodedGltf> EncodeGltfParts(
    const std::vector<SurfaceMesh>& meshes,
    const std::vector<std::string>& names,
    const std::vector<GltfExportOptions>& options, bool binary) {
  if (meshes.empty() || names.size() != meshes.size() ||
      options.size() != meshes.size()) {
    return InvalidArgumentError(
        "glTF parts need one name and one set of options per mesh");
  }
  Json json;
  json["asset"] = {{"version", "2.0"}, {"generator", "sdcb"}};
  GltfGather gather(std::move(json), std::string());
  Json scene_nodes = Json::array();
  for (size_t i = 0; i < meshes.size(); ++i) {
    SDCB_ASSIGN_OR_RETURN(EncodedGltf part,
                          EncodeGltf(meshes[i], options[i], /*binary=*/true));
    SDCB_ASSIGN_OR_RETURN(Json mesh,
                          gather.AppendMesh(part, /*keep_materials=*/true));
    Json& doc = gather.json();
    mesh["name"] = names[i];
    Json node = gather.node();
    node["mesh"] = doc["meshes"].size();
    node["name"] = names[i];
    doc["meshes"].push_back(mesh);
    scene_nodes.push_back(doc["nodes"].size());
    doc["nodes"].push_back(node);
  }
  Json& doc = gather.json();
  doc["scene"] = 0;
  doc["scenes"] = {{{"nodes", scene_nodes}}};
  return gather.Finish(binary);
}

StatusOr<GltfExportResult> WriteGltf(const SurfaceMesh& mesh,
                                     const GltfExportOptions& options,
                                     const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext != ".gltf" && ext != ".glb") {
    return InvalidArgumentError(path +
                                ": a glTF file must end in .gltf or .glb");
  }
  StatusOr<EncodedGltf> encoded = EncodeGltf(mesh, options, ext == ".glb");
  if (!encoded.ok()) return encoded.status().WithPrefix(path);
  SDCB_RETURN_IF_ERROR(WriteFileAtomically(encoded->bytes, path));
  return encoded->result;
}

}  // namespace sdcb
