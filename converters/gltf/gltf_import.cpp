#include "sdcb/converters/gltf/gltf_import.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>
#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <set>

#include "sdcb/converters/gltf/glb_container.h"
#include "sdcb/converters/gltf/gltf_schema_check.h"

namespace sdcb {
namespace {

namespace fs = std::filesystem;

// Decoded bytes per compressed byte a meshopt view or a Draco primitive may
// claim, and elements per byte of the file an accessor without a buffer
// view (zeros, or a sparse accessor's base) may have.
constexpr int64_t kMaxExpansion = 256;

constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122,
              kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;

std::string Str(int64_t n) { return std::to_string(n); }

// tinygltf's error text, lines ending in "\n", as one sentence: the lines
// joined by "; ", control bytes shown as spaces.
std::string OneSentence(const std::string& text) {
  std::string out;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    while (!line.empty() &&
           std::isspace(static_cast<unsigned char>(line.back()))) {
      line.pop_back();
    }
    if (!line.empty()) {
      if (!out.empty()) out += "; ";
      out += line;
    }
    start = end + 1;
  }
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = ' ';
  }
  if (out.size() > 400) out = out.substr(0, 400) + "...";
  return out.empty() ? "tinygltf could not parse the file" : out;
}

// --- What tinygltf may open -------------------------------------------------

// Files are read only under `base_dir` (never the working directory, which
// tinygltf also searches), only regular ones, within the limits. Without a
// base directory (a buffer read) no file is opened.
struct FileAccess {
  std::string base_dir;  // absolute, "" for none
  const MeshReadLimits* limits = nullptr;
  std::string missing;  // the last file asked for that was not there
};

bool UnderBase(const FileAccess& access, const std::string& path) {
  if (access.base_dir.empty()) return false;
  const fs::path p(path);
  if (!p.is_absolute()) return false;
  const std::string base = access.base_dir + "/";
  return path.compare(0, base.size(), base) == 0;
}

bool FileExistsCallback(const std::string& path, void* user) {
  auto* access = static_cast<FileAccess*>(user);
  std::error_code ec;
  if (UnderBase(*access, path) && fs::is_regular_file(path, ec)) return true;
  if (access->missing.empty() || UnderBase(*access, path)) {
    access->missing = fs::path(path).filename().string();
  }
  return false;
}

std::string ExpandFilePathCallback(const std::string& path, void*) {
  return path;  // tinygltf's default runs wordexp: no shell expansion here
}

bool ReadWholeFileCallback(std::vector<unsigned char>* out, std::string* err,
                           const std::string& path, void* user) {
  auto* access = static_cast<FileAccess*>(user);
  if (!UnderBase(*access, path)) {
    *err = "not under the glTF file's directory";
    return false;
  }
  StatusOr<std::string> bytes = ReadMeshFileBytes(path, *access->limits);
  if (!bytes.ok()) {
    *err = bytes.status().message();
    return false;
  }
  out->assign(bytes->begin(), bytes->end());
  return true;
}

bool WriteWholeFileCallback(std::string* err, const std::string&,
                            const std::vector<unsigned char>&, void*) {
  *err = "writing is not allowed";
  return false;
}

// Images are not decoded (the fit needs geometry only); the encoded bytes
// of each are kept (GltfDocument::images), within the read's memory limit.
struct ImageBytes {
  std::vector<std::string> bytes;
  int64_t budget = 0;
};

bool KeepImageBytes(tinygltf::Image* image, const int index, std::string* err,
                    std::string*, int, int, const unsigned char* data, int size,
                    void* user) {
  auto* images = static_cast<ImageBytes*>(user);
  // An image in a buffer view keeps its bytes there; tinygltf passes them
  // without checking the view against its buffer, so they are not read.
  if (image == nullptr || image->bufferView >= 0) return true;
  if (index < 0 || size < 0) return true;
  images->budget -= size;
  if (images->budget < 0) {
    *err = "the images need more memory than the read may use";
    return false;
  }
  if (images->bytes.size() <= static_cast<size_t>(index)) {
    images->bytes.resize(index + 1);
  }
  images->bytes[index].assign(reinterpret_cast<const char*>(data), size);
  return true;
}

// --- Reading accessors ------------------------------------------------------

int ComponentBytes(int component_type) {
  switch (component_type) {
    case kByte:
    case kUnsignedByte:
      return 1;
    case kShort:
    case kUnsignedShort:
      return 2;
    case kUnsignedInt:
    case kFloat:
      return 4;
    default:
      return 0;
  }
}

const char* ComponentName(int component_type) {
  switch (component_type) {
    case kByte:
      return "byte";
    case kUnsignedByte:
      return "unsigned byte";
    case kShort:
      return "short";
    case kUnsignedShort:
      return "unsigned short";
    case kUnsignedInt:
      return "unsigned int";
    case kFloat:
      return "float";
    default:
      return "unknown";
  }
}

int TypeComponents(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;  // matrices: no attribute sdcb reads has them
  }
}

// One stored component as a double: normalized integers map to [0, 1] or
// [-1, 1] (glTF 2.0, "Animation samplers"/"Accessors": max(c / (2^(b-1) -
// 1), -1) for signed ones).
double DecodeComponent(const unsigned char* p, int component_type,
                       bool normalized) {
  switch (component_type) {
    case kByte: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case kUnsignedByte:
      return normalized ? p[0] / 255.0 : p[0];
    case kShort: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case kUnsignedShort: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case kUnsignedInt: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// Values of an accessor: count rows of `components`, row-major.
struct AccessorValues {
  int64_t count = 0;
  int components = 0;
  std::vector<double> values;
  double at(int64_t row, int c) const { return values[row * components + c]; }
};

// Which component types an attribute may have.
struct AllowedTypes {
  std::vector<int> types;             // normalized or not as the flags say
  std::vector<int> normalized_types;  // these only when normalized
  std::vector<int> plain_types;       // these only when not normalized
};

class Reader {
 public:
  Reader(const tinygltf::Model& model, const MeshReadLimits& limits)
      : model_(model), limits_(limits) {
    for (const std::string& e : model.extensionsUsed) used_.insert(e);
    budget_ = limits.max_memory_bytes;
    for (const tinygltf::Buffer& buffer : model.buffers) {
      file_bytes_ += static_cast<int64_t>(buffer.data.size());
    }
    file_bytes_ = std::max<int64_t>(file_bytes_, 1024);
  }

  StatusOr<GltfAsset> Read();

 private:
  Status Charge(int64_t bytes, const std::string& what) {
    if (bytes < 0 || bytes > budget_) {
      return UnsupportedError(what + " needs more memory than the limit of " +
                              Str(limits_.max_memory_bytes >> 20) + " MB");
    }
    budget_ -= bytes;
    return Status::Ok();
  }

  Status ReadNodes(GltfAsset* asset) const;
  Status ReadPrimitive(int mesh_index, int primitive_index, GltfPrimitive* out);
  StatusOr<std::string_view> ViewBytes(int view_index, const std::string& what);
  StatusOr<std::string_view> MeshoptView(int view_index,
                                         const tinygltf::Value& ext);
  Status CheckAccessorType(const tinygltf::Accessor& accessor,
                           const std::string& what, int components_min,
                           int components_max,
                           const AllowedTypes& allowed) const;
  StatusOr<AccessorValues> ReadAccessor(int index, const std::string& what);
  Status ApplySparse(const tinygltf::Accessor& accessor,
                     const std::string& name, int64_t element_bytes,
                     AccessorValues* out);
  bool ReadsMeshoptViews(const tinygltf::Primitive& primitive) const;
  Status ReadDraco(const tinygltf::Primitive& primitive,
                   const tinygltf::Value& ext, const std::string& what,
                   std::map<std::string, AccessorValues>* attributes,
                   std::vector<int64_t>* indices);

  const tinygltf::Model& model_;
  const MeshReadLimits& limits_;
  std::set<std::string> used_;
  int64_t budget_ = 0;
  int64_t file_bytes_ = 0;  // the buffers' bytes (at least 1 KB)
  std::map<int, std::string> decoded_views_;  // EXT_meshopt_compression
};

StatusOr<std::string_view> Reader::ViewBytes(int view_index,
                                             const std::string& what) {
  if (view_index < 0 ||
      static_cast<size_t>(view_index) >= model_.bufferViews.size()) {
    return CorruptFileError(what + " refers to buffer view " + Str(view_index) +
                            ", but the file has " +
                            Str(model_.bufferViews.size()));
  }
  const tinygltf::BufferView& view = model_.bufferViews[view_index];
  const std::string name = "buffer view " + Str(view_index);
  const auto meshopt = view.extensions.find("EXT_meshopt_compression");
  if (meshopt != view.extensions.end()) {
    return MeshoptView(view_index, meshopt->second);
  }
  if (view.buffer < 0 ||
      static_cast<size_t>(view.buffer) >= model_.buffers.size()) {
    return CorruptFileError(name + " refers to buffer " + Str(view.buffer) +
                            ", but the file has " + Str(model_.buffers.size()));
  }
  const std::vector<unsigned char>& data = model_.buffers[view.buffer].data;
  if (view.byteOffset > data.size() ||
      view.byteLength > data.size() - view.byteOffset) {
    return CorruptFileError(name + " (bytes " + Str(view.byteOffset) + " to " +
                            Str(view.byteOffset + view.byteLength) +
                            ") reads past the end of buffer " +
                            Str(view.buffer) + " (" + Str(data.size()) +
                            " bytes)");
  }
  return std::string_view(
      reinterpret_cast<const char*>(data.data()) + view.byteOffset,
      view.byteLength);
}

StatusOr<std::string_view> Reader::MeshoptView(int view_index,
                                               const tinygltf::Value& ext) {
  const auto cached = decoded_views_.find(view_index);
  if (cached != decoded_views_.end()) return std::string_view(cached->second);
  const std::string name =
      "buffer view " + Str(view_index) + " (EXT_meshopt_compression)";
  if (!ext.IsObject()) return CorruptFileError(name + " is not an object");
  auto number = [&](const char* key, int64_t fallback) -> int64_t {
    if (!ext.Has(key)) return fallback;
    const tinygltf::Value& v = ext.Get(key);
    if (!v.IsNumber()) return -1;
    const double d = v.GetNumberAsDouble();
    if (!(d >= 0 && d <= 9e15) || d != std::floor(d)) return -1;
    return static_cast<int64_t>(d);
  };
  auto text = [&](const char* key, const char* fallback) -> std::string {
    if (!ext.Has(key)) return fallback;
    const tinygltf::Value& v = ext.Get(key);
    return v.IsString() ? v.Get<std::string>() : std::string("?");
  };
  const int64_t buffer = number("buffer", -1);
  const int64_t offset = number("byteOffset", 0);
  const int64_t length = number("byteLength", -1);
  const int64_t stride = number("byteStride", -1);
  const int64_t count = number("count", -1);
  const std::string mode = text("mode", "?");
  const std::string filter = text("filter", "NONE");
  if (buffer < 0 || offset < 0 || length < 0 || stride <= 0 || count < 0) {
    return CorruptFileError(
        name +
        " needs buffer, byteLength, byteStride and count as "
        "non-negative integers");
  }
  if (static_cast<size_t>(buffer) >= model_.buffers.size()) {
    return CorruptFileError(name + " refers to buffer " + Str(buffer) +
                            ", but the file has " + Str(model_.buffers.size()));
  }
  const std::vector<unsigned char>& data = model_.buffers[buffer].data;
  if (static_cast<uint64_t>(offset) > data.size() ||
      static_cast<uint64_t>(length) > data.size() - offset) {
    return CorruptFileError(name + " (bytes " + Str(offset) + " to " +
                            Str(offset + length) +
                            ") reads past the end of buffer " + Str(buffer) +
                            " (" + Str(data.size()) + " bytes)");
  }
  if (mode == "ATTRIBUTES") {
    if (stride % 4 != 0 || stride > 256) {
      return CorruptFileError(name + " has byteStride " + Str(stride) +
                              " (ATTRIBUTES need a multiple of 4 up to 256)");
    }
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) {
      return CorruptFileError(name + " has byteStride " + Str(stride) +
                              " (indices need 2 or 4)");
    }
    if (mode == "TRIANGLES" && count % 3 != 0) {
      return CorruptFileError(name + " has " + Str(count) +
                              " indices, not a multiple of 3");
    }
    if (filter != "NONE") {
      return CorruptFileError(name + " has filter " + filter +
                              " on indices (filters apply to ATTRIBUTES)");
    }
  } else {
    return CorruptFileError(name + " has mode '" + mode +
                            "' (ATTRIBUTES, TRIANGLES or INDICES)");
  }
  if (count > limits_.max_vertices * 3 || count > limits_.max_triangles * 3) {
    return UnsupportedError(name + " holds " + Str(count) +
                            " elements, more than the limits allow");
  }
  // The decoded size is known before decoding; a few compressed bytes must
  // not claim gigabytes. meshopt's codecs spend at least a byte per 4 to 16
  // bytes of typical data; beyond 256 times (all-zero attributes come
  // near 64) the view is refused.
  if (count * stride > kMaxExpansion * length + (int64_t{1} << 20)) {
    return CorruptFileError(name + " claims " + Str(count * stride) +
                            " decoded bytes from " + Str(length) +
                            " compressed ones, more than " +
                            Str(kMaxExpansion) + " times as many");
  }
  SDCB_RETURN_IF_ERROR(Charge(count * stride, name));
  std::string out(static_cast<size_t>(count * stride), '\0');
  const unsigned char* source = data.data() + offset;
  int result = 0;
  if (mode == "ATTRIBUTES") {
    result =
        meshopt_decodeVertexBuffer(out.data(), count, stride, source, length);
  } else if (mode == "TRIANGLES") {
    result =
        meshopt_decodeIndexBuffer(out.data(), count, stride, source, length);
  } else {
    result =
        meshopt_decodeIndexSequence(out.data(), count, stride, source, length);
  }
  if (result != 0) {
    return CorruptFileError(name + ": the " + mode +
                            " data does not decode (meshopt error " +
                            Str(result) + ")");
  }
  if (filter == "OCTAHEDRAL") {
    if (stride != 4 && stride != 8) {
      return CorruptFileError(name + ": OCTAHEDRAL needs byteStride 4 or 8");
    }
    meshopt_decodeFilterOct(out.data(), count, stride);
  } else if (filter == "QUATERNION") {
    if (stride != 8) {
      return CorruptFileError(name + ": QUATERNION needs byteStride 8");
    }
    meshopt_decodeFilterQuat(out.data(), count, stride);
  } else if (filter == "EXPONENTIAL") {
    meshopt_decodeFilterExp(out.data(), count, stride);
  } else if (filter != "NONE") {
    return CorruptFileError(name + " has filter '" + filter +
                            "' (NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL)");
  }
  return std::string_view(
      decoded_views_.emplace(view_index, std::move(out)).first->second);
}

Status Reader::CheckAccessorType(const tinygltf::Accessor& accessor,
                                 const std::string& what, int components_min,
                                 int components_max,
                                 const AllowedTypes& allowed) const {
  const int components = TypeComponents(accessor.type);
  if (components < components_min || components > components_max) {
    return CorruptFileError(
        what + " has " +
        (components == 0 ? std::string("a matrix or unknown")
                         : Str(components) + "-component") +
        " type; glTF requires " +
        (components_min == components_max
             ? Str(components_min)
             : Str(components_min) + " to " + Str(components_max)) +
        " components");
  }
  const int t = accessor.componentType;
  auto has = [t](const std::vector<int>& v) {
    return std::find(v.begin(), v.end(), t) != v.end();
  };
  if (has(allowed.types) ||
      (accessor.normalized && has(allowed.normalized_types)) ||
      (!accessor.normalized && has(allowed.plain_types))) {
    return Status::Ok();
  }
  return CorruptFileError(
      what + " has component type " + Str(t) + " (" + ComponentName(t) +
      (accessor.normalized ? ", normalized" : "") +
      "), which glTF does not allow there" +
      (used_.count("KHR_mesh_quantization") != 0
           ? std::string()
           : std::string(" (without KHR_mesh_quantization)")));
}

StatusOr<AccessorValues> Reader::ReadAccessor(int index,
                                              const std::string& what) {
  if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size()) {
    return CorruptFileError(what + " refers to accessor " + Str(index) +
                            ", but the file has " +
                            Str(model_.accessors.size()));
  }
  const tinygltf::Accessor& accessor = model_.accessors[index];
  const std::string name = what + " (accessor " + Str(index) + ")";
  AccessorValues out;
  out.components = TypeComponents(accessor.type);
  const int component_bytes = ComponentBytes(accessor.componentType);
  if (out.components == 0 || component_bytes == 0) {
    return CorruptFileError(name + " has an unknown type or component type");
  }
  const int64_t element_bytes = int64_t{out.components} * component_bytes;
  const uint64_t count = accessor.count;
  if (count > static_cast<uint64_t>(
                  std::max(limits_.max_vertices, 3 * limits_.max_triangles))) {
    return UnsupportedError(name + " has " + Str(count) +
                            " elements, more than the limits allow");
  }
  out.count = static_cast<int64_t>(count);
  std::string_view bytes;
  int64_t stride = element_bytes;
  if (accessor.bufferView < 0 && out.count > kMaxExpansion * file_bytes_) {
    return CorruptFileError(name + " has " + Str(out.count) +
                            " elements but no buffer view, more than " +
                            Str(kMaxExpansion) + " per byte of the file");
  }
  if (accessor.bufferView >= 0) {
    SDCB_ASSIGN_OR_RETURN(bytes, ViewBytes(accessor.bufferView, name));
    const tinygltf::BufferView& view = model_.bufferViews[accessor.bufferView];
    if (view.byteStride != 0) {
      if (static_cast<int64_t>(view.byteStride) < element_bytes) {
        return CorruptFileError(name + ": buffer view " +
                                Str(accessor.bufferView) + " has byteStride " +
                                Str(view.byteStride) + ", less than the " +
                                Str(element_bytes) + " bytes of an element");
      }
      stride = static_cast<int64_t>(view.byteStride);
    }
    if (accessor.byteOffset % component_bytes != 0) {
      return CorruptFileError(name + " has byteOffset " +
                              Str(accessor.byteOffset) +
                              ", not a multiple of its component size");
    }
    // The last element ends at byteOffset + stride (count - 1) + element.
    const uint64_t available = bytes.size();
    if (count > 0 &&
        (accessor.byteOffset > available ||
         (available - accessor.byteOffset <
          static_cast<uint64_t>(element_bytes)) ||
         (count - 1) > (available - accessor.byteOffset - element_bytes) /
                           static_cast<uint64_t>(stride))) {
      return CorruptFileError(
          name + " reads past the end of buffer view " +
          Str(accessor.bufferView) + ": " + Str(count) + " elements of " +
          Str(element_bytes) + " bytes from byte " + Str(accessor.byteOffset) +
          " need more than its " + Str(available) + " bytes");
    }
  }
  SDCB_RETURN_IF_ERROR(
      Charge(out.count * out.components * int64_t{sizeof(double)}, name));
  out.values.assign(static_cast<size_t>(out.count * out.components), 0.0);
  if (bytes.data() != nullptr) {  // else zeros
    const auto* base = reinterpret_cast<const unsigned char*>(bytes.data()) +
                       accessor.byteOffset;
    for (int64_t i = 0; i < out.count; ++i) {
      const unsigned char* element = base + i * stride;
      for (int c = 0; c < out.components; ++c) {
        out.values[i * out.components + c] =
            DecodeComponent(element + c * component_bytes,
                            accessor.componentType, accessor.normalized);
      }
    }
  }
  if (accessor.sparse.isSparse) {
    SDCB_RETURN_IF_ERROR(ApplySparse(accessor, name, element_bytes, &out));
  }
  return out;
}

// glTF 2.0 "Sparse accessors": `count` element indices (unsigned, strictly
// increasing, each below the accessor's count) and as many replacement
// elements, both tightly packed in their buffer views.
Status Reader::ApplySparse(const tinygltf::Accessor& accessor,
                           const std::string& name, int64_t element_bytes,
                           AccessorValues* out) {
  const auto& sparse = accessor.sparse;
  const std::string what = name + " (sparse)";
  const int index_bytes = ComponentBytes(sparse.indices.componentType);
  if (sparse.indices.componentType != kUnsignedByte &&
      sparse.indices.componentType != kUnsignedShort &&
      sparse.indices.componentType != kUnsignedInt) {
    return CorruptFileError(what + " has indices of component type " +
                            Str(sparse.indices.componentType) +
                            " (glTF allows unsigned byte, short or int)");
  }
  const int64_t count = sparse.count;
  if (count < 1 || count > out->count) {
    return CorruptFileError(what + " replaces " + Str(count) +
                            " elements of the " + Str(out->count));
  }
  SDCB_ASSIGN_OR_RETURN(const std::string_view indices,
                        ViewBytes(sparse.indices.bufferView, what));
  SDCB_ASSIGN_OR_RETURN(const std::string_view values,
                        ViewBytes(sparse.values.bufferView, what));
  const int64_t index_offset = sparse.indices.byteOffset;
  const int64_t value_offset = sparse.values.byteOffset;
  if (index_offset < 0 || value_offset < 0 ||
      index_offset > static_cast<int64_t>(indices.size()) ||
      (static_cast<int64_t>(indices.size()) - index_offset) / index_bytes <
          count ||
      value_offset > static_cast<int64_t>(values.size()) ||
      (static_cast<int64_t>(values.size()) - value_offset) / element_bytes <
          count) {
    return CorruptFileError(what + ": its " + Str(count) +
                            " indices or values reach past their buffer views");
  }
  const auto* index_base =
      reinterpret_cast<const unsigned char*>(indices.data()) + index_offset;
  const auto* value_base =
      reinterpret_cast<const unsigned char*>(values.data()) + value_offset;
  const int component_bytes = ComponentBytes(accessor.componentType);
  int64_t previous = -1;
  for (int64_t i = 0; i < count; ++i) {
    const int64_t target = static_cast<int64_t>(DecodeComponent(
        index_base + i * index_bytes, sparse.indices.componentType, false));
    if (target <= previous || target >= out->count) {
      return CorruptFileError(what + ": index " + Str(target) +
                              " is out of order or past the " +
                              Str(out->count) + " elements");
    }
    previous = target;
    for (int c = 0; c < out->components; ++c) {
      out->values[target * out->components + c] =
          DecodeComponent(value_base + i * element_bytes + c * component_bytes,
                          accessor.componentType, accessor.normalized);
    }
  }
  return Status::Ok();
}

// KHR_draco_mesh_compression: the attributes the extension maps, per
// point, and the triangles' point indices.
Status Reader::ReadDraco(const tinygltf::Primitive& primitive,
                         const tinygltf::Value& ext, const std::string& what,
                         std::map<std::string, AccessorValues>* attributes,
                         std::vector<int64_t>* indices) {
  const std::string name = what + " (KHR_draco_mesh_compression)";
  if (!ext.IsObject() || !ext.Has("bufferView") ||
      !ext.Get("bufferView").IsNumber() || !ext.Has("attributes") ||
      !ext.Get("attributes").IsObject()) {
    return CorruptFileError(name + " needs a bufferView and attributes");
  }
  if (primitive.mode != TINYGLTF_MODE_TRIANGLES) {
    return CorruptFileError(name + " is not of mode TRIANGLES");
  }
  SDCB_ASSIGN_OR_RETURN(
      const std::string_view bytes,
      ViewBytes(ext.Get("bufferView").GetNumberAsInt(), name));
  // Draco's decoder allocates as its header says: this much per compressed
  // byte is charged to the budget before decoding (a point of position,
  // normal and texture coordinates takes a few bits).
  SDCB_RETURN_IF_ERROR(Charge(int64_t{64} * bytes.size(), name));
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) {
    return CorruptFileError(name + ": the Draco data does not decode (" +
                            OneSentence(decoded.status().error_msg_string()) +
                            ")");
  }
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  const int64_t points = mesh->num_points();
  const int64_t faces = mesh->num_faces();
  if (points > limits_.max_vertices || faces > limits_.max_triangles) {
    return UnsupportedError(name + " holds " + Str(points) + " points and " +
                            Str(faces) + " triangles, more than the limits");
  }
  const tinygltf::Value& map = ext.Get("attributes");
  for (const std::string& semantic : map.Keys()) {
    if (semantic != "POSITION" && semantic != "TEXCOORD_0" &&
        semantic != "COLOR_0") {
      continue;
    }
    const tinygltf::Value& id = map.Get(semantic);
    const draco::PointAttribute* attribute =
        id.IsNumber() ? mesh->GetAttributeByUniqueId(id.GetNumberAsInt())
                      : nullptr;
    if (attribute == nullptr) {
      return CorruptFileError(name + ": " + semantic +
                              " names no attribute of the Draco data");
    }
    const auto declared = primitive.attributes.find(semantic);
    const bool normalized =
        declared != primitive.attributes.end() && declared->second >= 0 &&
        static_cast<size_t>(declared->second) < model_.accessors.size() &&
        model_.accessors[declared->second].normalized;
    AccessorValues values;
    values.count = points;
    values.components = attribute->num_components();
    if (values.components < 1 || values.components > 4) {
      return CorruptFileError(name + ": " + semantic + " has " +
                              Str(values.components) + " components");
    }
    SDCB_RETURN_IF_ERROR(
        Charge(points * values.components * int64_t{sizeof(double)}, name));
    values.values.resize(static_cast<size_t>(points * values.components));
    // Integer data the accessor declares normalized, which Draco stored as
    // plain integers: scaled as glTF normalizes them.
    double scale = 1.0;
    if (normalized && !attribute->normalized()) {
      switch (attribute->data_type()) {
        case draco::DT_UINT8:
          scale = 1.0 / 255;
          break;
        case draco::DT_UINT16:
          scale = 1.0 / 65535;
          break;
        case draco::DT_INT8:
          scale = 1.0 / 127;
          break;
        case draco::DT_INT16:
          scale = 1.0 / 32767;
          break;
        default:
          break;
      }
    }
    float row[4];
    for (int64_t p = 0; p < points; ++p) {
      const draco::AttributeValueIndex value =
          attribute->mapped_index(draco::PointIndex(static_cast<uint32_t>(p)));
      if (!attribute->ConvertValue<float>(value, values.components, row)) {
        return CorruptFileError(name + ": " + semantic + " of point " + Str(p) +
                                " does not convert");
      }
      for (int c = 0; c < values.components; ++c) {
        // Normalized signed integers: max(c / (2^(b-1) - 1), -1).
        const double value = row[c] * scale;
        values.values[p * values.components + c] =
            scale == 1.0 ? value : std::max(value, -1.0);
      }
    }
    (*attributes)[semantic] = std::move(values);
  }
  SDCB_RETURN_IF_ERROR(Charge(faces * 3 * int64_t{sizeof(int64_t)}, name));
  indices->resize(static_cast<size_t>(faces * 3));
  for (int64_t f = 0; f < faces; ++f) {
    const draco::Mesh::Face& face =
        mesh->face(draco::FaceIndex(static_cast<uint32_t>(f)));
    for (int k = 0; k < 3; ++k) (*indices)[f * 3 + k] = face[k].value();
  }
  return Status::Ok();
}

AllowedTypes PositionTypes(bool quantized) {
  if (!quantized) return {{kFloat}, {}, {}};
  return {{kFloat, kByte, kUnsignedByte, kShort, kUnsignedShort}, {}, {}};
}

AllowedTypes TexcoordTypes(bool quantized) {
  if (!quantized) return {{kFloat}, {kUnsignedByte, kUnsignedShort}, {}};
  return {{kFloat, kByte, kUnsignedByte, kShort, kUnsignedShort}, {}, {}};
}

AllowedTypes ColorTypes() {
  return {{kFloat}, {kUnsignedByte, kUnsignedShort}, {}};
}

AllowedTypes IndexTypes() {
  return {{}, {}, {kUnsignedByte, kUnsignedShort, kUnsignedInt}};
}

// Triangles of the primitive's mode from its index list (glTF 2.0,
// "Meshes"): strip triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}), fan
// triangle i is (v_{i+1}, v_{i+2}, v_0).
std::vector<int64_t> TriangleCorners(const std::vector<int64_t>& list,
                                     int mode) {
  if (mode == TINYGLTF_MODE_TRIANGLES) return list;
  std::vector<int64_t> corners;
  const int64_t n = static_cast<int64_t>(list.size());
  if (n < 3) return corners;
  corners.reserve(static_cast<size_t>(3 * (n - 2)));
  for (int64_t i = 0; i + 2 < n; ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      corners.push_back(list[i]);
      corners.push_back(list[i + 1 + i % 2]);
      corners.push_back(list[i + 2 - i % 2]);
    } else {
      corners.push_back(list[i + 1]);
      corners.push_back(list[i + 2]);
      corners.push_back(list[0]);
    }
  }
  return corners;
}

// Whether an accessor of `primitive` (attributes, indices, morph targets)
// reads a view that is EXT_meshopt_compression's, sparse values included.
bool Reader::ReadsMeshoptViews(const tinygltf::Primitive& primitive) const {
  auto compressed_view = [&](int v) {
    return v >= 0 && static_cast<size_t>(v) < model_.bufferViews.size() &&
           model_.bufferViews[v].extensions.count("EXT_meshopt_compression");
  };
  auto compressed = [&](int a) {
    if (a < 0 || static_cast<size_t>(a) >= model_.accessors.size()) {
      return false;
    }
    const tinygltf::Accessor& accessor = model_.accessors[a];
    return compressed_view(accessor.bufferView) ||
           (accessor.sparse.isSparse &&
            (compressed_view(accessor.sparse.indices.bufferView) ||
             compressed_view(accessor.sparse.values.bufferView)));
  };
  if (compressed(primitive.indices)) return true;
  for (const auto& [semantic, a] : primitive.attributes) {
    if (compressed(a)) return true;
  }
  for (const std::map<std::string, int>& target : primitive.targets) {
    for (const auto& [semantic, a] : target) {
      if (compressed(a)) return true;
    }
  }
  return false;
}

Status Reader::ReadPrimitive(int mesh_index, int primitive_index,
                             GltfPrimitive* out) {
  const tinygltf::Mesh& mesh = model_.meshes[mesh_index];
  const tinygltf::Primitive& primitive = mesh.primitives[primitive_index];
  const std::string what =
      "primitive " + Str(primitive_index) + " of mesh " + Str(mesh_index);
  out->mesh = mesh_index;
  out->primitive = primitive_index;
  out->name = mesh.name.empty() ? "mesh " + Str(mesh_index) : mesh.name;
  if (mesh.primitives.size() > 1) out->name += "#" + Str(primitive_index);
  out->material = primitive.material;
  if (primitive.material >= 0 &&
      static_cast<size_t>(primitive.material) >= model_.materials.size()) {
    return CorruptFileError(what + " refers to material " +
                            Str(primitive.material) + ", but the file has " +
                            Str(model_.materials.size()));
  }
  const bool quantized = used_.count("KHR_mesh_quantization") != 0;

  // Declared accessors first: their types are checked even when Draco
  // holds the data.
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) {
    return CorruptFileError(what + " has no POSITION attribute");
  }
  struct Semantic {
    const char* name;
    int min, max;
    AllowedTypes allowed;
  };
  const Semantic semantics[] = {
      {"POSITION", 3, 3, PositionTypes(quantized)},
      {"TEXCOORD_0", 2, 2, TexcoordTypes(quantized)},
      {"COLOR_0", 3, 4, ColorTypes()},
  };
  for (const Semantic& s : semantics) {
    const auto it = primitive.attributes.find(s.name);
    if (it == primitive.attributes.end()) continue;
    const std::string name = what + ": " + s.name;
    if (it->second < 0 ||
        static_cast<size_t>(it->second) >= model_.accessors.size()) {
      return CorruptFileError(name + " refers to accessor " + Str(it->second) +
                              ", but the file has " +
                              Str(model_.accessors.size()));
    }
    SDCB_RETURN_IF_ERROR(CheckAccessorType(
        model_.accessors[it->second],
        name + " (accessor " + Str(it->second) + ")", s.min, s.max, s.allowed));
  }
  if (primitive.indices >= 0) {
    if (static_cast<size_t>(primitive.indices) >= model_.accessors.size()) {
      return CorruptFileError(what + ": indices refer to accessor " +
                              Str(primitive.indices) + ", but the file has " +
                              Str(model_.accessors.size()));
    }
    SDCB_RETURN_IF_ERROR(CheckAccessorType(
        model_.accessors[primitive.indices],
        what + ": indices (accessor " + Str(primitive.indices) + ")", 1, 1,
        IndexTypes()));
  }

  std::map<std::string, AccessorValues> attributes;
  std::vector<int64_t> list;
  bool indexed = primitive.indices >= 0;
  const auto draco = primitive.extensions.find("KHR_draco_mesh_compression");
  if (draco != primitive.extensions.end()) {
    SDCB_RETURN_IF_ERROR(
        ReadDraco(primitive, draco->second, what, &attributes, &list));
    indexed = true;
    if (attributes.count("POSITION") == 0) {
      return CorruptFileError(what + ": the Draco data has no POSITION");
    }
  } else {
    for (const Semantic& s : semantics) {
      const auto it = primitive.attributes.find(s.name);
      if (it == primitive.attributes.end()) continue;
      SDCB_ASSIGN_OR_RETURN(attributes[s.name],
                            ReadAccessor(it->second, what + ": " + s.name));
    }
    if (indexed) {
      SDCB_ASSIGN_OR_RETURN(
          const AccessorValues index_values,
          ReadAccessor(primitive.indices, what + ": indices"));
      SDCB_RETURN_IF_ERROR(Charge(index_values.count * int64_t{sizeof(int64_t)},
                                  what + ": indices"));
      list.resize(static_cast<size_t>(index_values.count));
      for (int64_t i = 0; i < index_values.count; ++i) {
        list[i] = static_cast<int64_t>(index_values.values[i]);
      }
    }
  }
  const AccessorValues& positions = attributes["POSITION"];
  const int64_t n = positions.count;
  for (const auto& [semantic, values] : attributes) {
    if (values.count != n) {
      return CorruptFileError(what + ": " + semantic + " has " +
                              Str(values.count) + " values, but POSITION has " +
                              Str(n));
    }
  }
  for (int64_t v = 0; v < n; ++v) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(positions.at(v, c))) {
        return InvalidInputError(what + ": vertex " + Str(v) +
                                 " has a non-finite position (" +
                                 std::to_string(positions.at(v, 0)) + ", " +
                                 std::to_string(positions.at(v, 1)) + ", " +
                                 std::to_string(positions.at(v, 2)) + ")");
      }
    }
  }
  if (!indexed) {
    SDCB_RETURN_IF_ERROR(
        Charge(n * int64_t{sizeof(int64_t)}, what + ": vertices"));
    list.resize(static_cast<size_t>(n));
    std::iota(list.begin(), list.end(), int64_t{0});
  }
  for (const int64_t index : list) {
    if (index < 0 || index >= n) {
      return InvalidInputError(what + ": index " + Str(index) +
                               " refers past the " + Str(n) + " vertices");
    }
  }
  const int mode = primitive.mode;
  if (mode == TINYGLTF_MODE_TRIANGLES && list.size() % 3 != 0) {
    return CorruptFileError(what + " has " + Str(list.size()) +
                            (indexed ? " indices" : " vertices") +
                            ", not a multiple of 3 for TRIANGLES");
  }
  SDCB_RETURN_IF_ERROR(Charge(
      3 * static_cast<int64_t>(list.size()) * int64_t{sizeof(int64_t)}, what));
  const std::vector<int64_t> corners = TriangleCorners(list, mode);
  if (static_cast<int64_t>(corners.size() / 3) > limits_.max_triangles) {
    return UnsupportedError(what + " has " + Str(corners.size() / 3) +
                            " triangles, more than the limit of " +
                            Str(limits_.max_triangles));
  }

  // Merge by exactly equal position: sort the vertices by position (ties by
  // index), each one's representative is the first of its run.
  std::vector<int64_t> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), int64_t{0});
  auto key = [&](int64_t v, int c) { return positions.at(v, c) + 0.0; };
  std::sort(order.begin(), order.end(), [&](int64_t a, int64_t b) {
    for (int c = 0; c < 3; ++c) {
      if (key(a, c) != key(b, c)) return key(a, c) < key(b, c);
    }
    return a < b;
  });
  std::vector<int64_t> representative(static_cast<size_t>(n));
  for (size_t i = 0; i < order.size(); ++i) {
    const bool same = i > 0 && key(order[i], 0) == key(order[i - 1], 0) &&
                      key(order[i], 1) == key(order[i - 1], 1) &&
                      key(order[i], 2) == key(order[i - 1], 2);
    representative[order[i]] = same ? representative[order[i - 1]] : order[i];
  }
  std::vector<int> merged(static_cast<size_t>(n), -1);
  std::vector<int64_t> kept_vertices;
  std::vector<int64_t> kept_corners;  // source vertex of each kept corner
  std::vector<int> faces;
  for (size_t f = 0; f + 2 < corners.size(); f += 3) {
    const int64_t r0 = representative[corners[f]],
                  r1 = representative[corners[f + 1]],
                  r2 = representative[corners[f + 2]];
    if (r0 == r1 || r1 == r2 || r0 == r2) {
      ++out->dropped_degenerate;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int64_t r = representative[corners[f + k]];
      if (merged[r] < 0) {
        merged[r] = static_cast<int>(kept_vertices.size());
        kept_vertices.push_back(r);
      }
      faces.push_back(merged[r]);
      kept_corners.push_back(corners[f + k]);
    }
  }
  TriangleMesh& triangles = out->triangles;
  triangles.vertices.resize(static_cast<Eigen::Index>(kept_vertices.size()), 3);
  for (size_t v = 0; v < kept_vertices.size(); ++v) {
    for (int c = 0; c < 3; ++c) {
      triangles.vertices(v, c) = positions.at(kept_vertices[v], c);
    }
  }
  const Eigen::Index num_faces = static_cast<Eigen::Index>(faces.size() / 3);
  triangles.faces.resize(num_faces, 3);
  for (Eigen::Index f = 0; f < num_faces; ++f) {
    for (int k = 0; k < 3; ++k) triangles.faces(f, k) = faces[3 * f + k];
  }
  if (draco == primitive.extensions.end() && !ReadsMeshoptViews(primitive)) {
    out->source_corners.resize(num_faces, 3);
    for (Eigen::Index f = 0; f < num_faces; ++f) {
      for (int k = 0; k < 3; ++k) {
        out->source_corners(f, k) = static_cast<int>(kept_corners[3 * f + k]);
      }
    }
  }
  out->source_vertices = static_cast<int>(n);
  const auto texcoords = attributes.find("TEXCOORD_0");
  if (texcoords != attributes.end()) {
    out->texcoords.resize(static_cast<Eigen::Index>(kept_corners.size()), 2);
    for (size_t i = 0; i < kept_corners.size(); ++i) {
      for (int c = 0; c < 2; ++c) {
        out->texcoords(i, c) = texcoords->second.at(kept_corners[i], c);
      }
    }
  }
  const auto colors = attributes.find("COLOR_0");
  if (colors != attributes.end()) {
    out->colors.resize(static_cast<Eigen::Index>(kept_corners.size()), 4);
    for (size_t i = 0; i < kept_corners.size(); ++i) {
      for (int c = 0; c < 4; ++c) {
        out->colors(i, c) = c < colors->second.components
                                ? colors->second.at(kept_corners[i], c)
                                : 1.0;
      }
    }
  }
  return Status::Ok();
}

Eigen::Matrix4d LocalTransform(const tinygltf::Node& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = node.matrix[i];
    return m;
  }
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) {
    t.translate(Eigen::Vector3d(node.translation[0], node.translation[1],
                                node.translation[2]));
  }
  if (node.rotation.size() == 4) {
    // glTF stores (x, y, z, w); Eigen's constructor takes (w, x, y, z).
    t.rotate(Eigen::Quaterniond(node.rotation[3], node.rotation[0],
                                node.rotation[1], node.rotation[2]));
  }
  if (node.scale.size() == 3) {
    t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  }
  return t.matrix();
}

Status Reader::ReadNodes(GltfAsset* asset) const {
  const int num_nodes = static_cast<int>(model_.nodes.size());
  std::vector<int> parent(static_cast<size_t>(num_nodes), -1);
  asset->nodes.resize(static_cast<size_t>(num_nodes));
  for (int i = 0; i < num_nodes; ++i) {
    const tinygltf::Node& node = model_.nodes[i];
    GltfNode& out = asset->nodes[i];
    out.name = node.name;
    out.mesh = node.mesh;
    if (node.mesh < -1 || (node.mesh >= 0 && static_cast<size_t>(node.mesh) >=
                                                 model_.meshes.size())) {
      return CorruptFileError("node " + Str(i) + " refers to mesh " +
                              Str(node.mesh) + ", but the file has " +
                              Str(model_.meshes.size()));
    }
    if ((!node.matrix.empty() && node.matrix.size() != 16) ||
        (!node.translation.empty() && node.translation.size() != 3) ||
        (!node.rotation.empty() && node.rotation.size() != 4) ||
        (!node.scale.empty() && node.scale.size() != 3)) {
      return CorruptFileError("node " + Str(i) +
                              " has a matrix, translation, rotation or scale "
                              "of the wrong length");
    }
    out.local = LocalTransform(node);
    if (!out.local.allFinite()) {
      return InvalidInputError("node " + Str(i) +
                               " has a non-finite transform");
    }
    for (const int child : node.children) {
      if (child < 0 || child >= num_nodes) {
        return CorruptFileError("node " + Str(i) + " has child " + Str(child) +
                                ", but the file has " + Str(num_nodes) +
                                " nodes");
      }
      if (child == i) {
        return InvalidInputError("node " + Str(i) + " is its own ancestor");
      }
      if (parent[child] >= 0) {
        return InvalidInputError("node " + Str(child) +
                                 " is a child of both node " +
                                 Str(parent[child]) + " and node " + Str(i));
      }
      parent[child] = i;
      out.children.push_back(child);
    }
  }
  // Each node has at most one parent, so a cycle is a walk up the parents
  // that comes back: 0 unvisited, 1 on the current walk, 2 done.
  std::vector<char> state(static_cast<size_t>(num_nodes), 0);
  for (int start = 0; start < num_nodes; ++start) {
    int v = start;
    while (v >= 0 && state[v] == 0) {
      state[v] = 1;
      v = parent[v];
    }
    if (v >= 0 && state[v] == 1) {
      return InvalidInputError("node " + Str(v) + " is its own ancestor");
    }
    for (int w = start; w >= 0 && state[w] == 1; w = parent[w]) state[w] = 2;
  }
  return Status::Ok();
}

StatusOr<GltfAsset> Reader::Read() {
  GltfAsset asset;
  if (model_.scenes.empty()) {
    return InvalidInputError("the file has no scene");
  }
  asset.scene = model_.defaultScene >= 0 ? model_.defaultScene : 0;
  if (static_cast<size_t>(asset.scene) >= model_.scenes.size()) {
    return CorruptFileError("the default scene is " + Str(asset.scene) +
                            ", but the file has " + Str(model_.scenes.size()) +
                            " scenes");
  }
  SDCB_RETURN_IF_ERROR(ReadNodes(&asset));
  const int num_nodes = static_cast<int>(model_.nodes.size());
  for (const int root : model_.scenes[asset.scene].nodes) {
    if (root < 0 || root >= num_nodes) {
      return CorruptFileError("scene " + Str(asset.scene) + " has node " +
                              Str(root) + ", but the file has " +
                              Str(num_nodes) + " nodes");
    }
    asset.roots.push_back(root);
  }
  // The meshes the scene's nodes use (the hierarchy is a forest: this walk
  // ends).
  std::set<int> meshes;
  std::vector<int> stack(asset.roots.rbegin(), asset.roots.rend());
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    if (asset.nodes[v].mesh >= 0) meshes.insert(asset.nodes[v].mesh);
    for (const int child : asset.nodes[v].children) stack.push_back(child);
  }
  int64_t vertices = 0, triangles = 0;
  for (const int m : meshes) {
    const tinygltf::Mesh& mesh = model_.meshes[m];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      const int mode = mesh.primitives[p].mode;
      if (mode == TINYGLTF_MODE_POINTS) {
        ++asset.point_primitives;
        continue;
      }
      if (mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
          mode == TINYGLTF_MODE_LINE_STRIP) {
        ++asset.line_primitives;
        continue;
      }
      if (mode != TINYGLTF_MODE_TRIANGLES &&
          mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        return CorruptFileError("primitive " + Str(p) + " of mesh " + Str(m) +
                                " has mode " + Str(mode) +
                                " (glTF's modes are 0 to 6)");
      }
      GltfPrimitive primitive;
      SDCB_RETURN_IF_ERROR(ReadPrimitive(m, static_cast<int>(p), &primitive));
      vertices += primitive.triangles.num_vertices();
      triangles += primitive.triangles.num_faces();
      if (vertices > limits_.max_vertices ||
          triangles > limits_.max_triangles) {
        return UnsupportedError("the scene has more than the limit of " +
                                Str(limits_.max_vertices) + " vertices or " +
                                Str(limits_.max_triangles) + " triangles");
      }
      if (primitive.triangles.num_faces() > 0) {
        asset.primitives.push_back(std::move(primitive));
      }
    }
  }
  if (asset.primitives.empty()) {
    std::string skipped;
    if (asset.point_primitives + asset.line_primitives > 0) {
      skipped = " (" + Str(asset.point_primitives) + " points and " +
                Str(asset.line_primitives) + " lines primitives skipped)";
    }
    return InvalidInputError("scene " + Str(asset.scene) + " has no triangles" +
                             skipped);
  }
  return asset;
}

// Debian 12's tinygltf (2.7.0) refuses two valid constructs that sdcb's own
// exporter writes: an indices accessor without a bufferView (a Draco
// primitive's: the Draco data holds its triangles) and, in a GLB, a buffer
// without uri after the first (EXT_meshopt_compression's fallback buffer,
// which has no data). A file that names either extension is rewritten for
// it: such a primitive loses its `indices`, and a fallback buffer becomes a
// data URI of 4 zero bytes (its views are decoded from the compressed
// buffer, never read from it). `json_in_out` is the file's JSON, changed in
// place; `chunks` the file's (a .gltf's text as chunks.json). Returns ""
// when nothing needs rewriting.
std::string RewriteForTinygltf(const GlbChunks& chunks, bool binary,
                               nlohmann::json* json_in_out) {
  if (chunks.json.find("KHR_draco_mesh_compression") ==
          std::string_view::npos &&
      chunks.json.find("EXT_meshopt_compression") == std::string_view::npos) {
    return std::string();
  }
  nlohmann::json& json = *json_in_out;
  bool changed = false;
  const auto accessors = json.find("accessors");
  const auto meshes = json.find("meshes");
  if (accessors != json.end() && accessors->is_array() &&
      meshes != json.end() && meshes->is_array()) {
    for (nlohmann::json& mesh : *meshes) {
      if (!mesh.is_object() || !mesh.contains("primitives") ||
          !mesh["primitives"].is_array()) {
        continue;
      }
      for (nlohmann::json& primitive : mesh["primitives"]) {
        if (!primitive.is_object() || !primitive.contains("indices") ||
            !primitive["indices"].is_number_unsigned() ||
            !primitive.contains("extensions") ||
            !primitive["extensions"].is_object() ||
            !primitive["extensions"].contains("KHR_draco_mesh_compression")) {
          continue;
        }
        const uint64_t index = primitive["indices"].get<uint64_t>();
        if (index < accessors->size() && (*accessors)[index].is_object() &&
            !(*accessors)[index].contains("bufferView")) {
          primitive.erase("indices");
          changed = true;
        }
      }
    }
  }
  const auto buffers = json.find("buffers");
  if (binary && buffers != json.end() && buffers->is_array()) {
    for (size_t i = 1; i < buffers->size(); ++i) {
      nlohmann::json& buffer = (*buffers)[i];
      if (buffer.is_object() && !buffer.contains("uri")) {
        buffer["uri"] = "data:application/octet-stream;base64,AAAAAA==";
        buffer["byteLength"] = 4;
        changed = true;
      }
    }
  }
  if (!changed) return std::string();
  if (!binary) return json.dump();
  return PackGlb(json.dump(), std::string(chunks.bin));
}

// kUnsupported, naming the converter, for a glTF 1 file (asset.version
// "1", "1.x" or the number 1), whose layout the glTF 2.0 schema check would
// otherwise report property by property.
Status RequireGltf2(const nlohmann::json& json) {
  if (!json.is_object() || !json.contains("asset")) return Status::Ok();
  const nlohmann::json& asset = json["asset"];
  if (!asset.is_object() || !asset.contains("version")) return Status::Ok();
  const nlohmann::json& v = asset["version"];
  // glTF 1 wrote the version as a string or, in early exporters, a number.
  const std::string version = v.is_string()           ? v.get<std::string>()
                              : v.is_number_integer() ? v.dump()
                                                      : std::string();
  if (version != "1" && version.rfind("1.", 0) != 0) return Status::Ok();
  return UnsupportedError(
      "the file is glTF " + version +
      "; sdcb reads glTF 2.0 (`assimp export FILE OUT.glb -f glb2` converts "
      "it)");
}

// The file's JSON (a .gltf's text, a GLB's JSON chunk) parsed once:
// checked against the schema's types (gltf_schema_check.h), then rewritten
// for tinygltf if needed (RewriteForTinygltf). JSON that does not parse is
// left to tinygltf, which names the syntax error. Returns "" when the bytes
// go to tinygltf as they are.
StatusOr<std::string> CheckAndRewriteJson(const GlbChunks& chunks,
                                          bool binary) {
  nlohmann::json json = nlohmann::json::parse(chunks.json, nullptr, false);
  if (json.is_discarded()) return std::string();
  SDCB_RETURN_IF_ERROR(RequireGltf2(json));
  SDCB_RETURN_IF_ERROR(CheckGltfSchemaTypes(json));
  return RewriteForTinygltf(chunks, binary, &json);
}

StatusOr<GltfAsset> Load(std::string_view bytes, const std::string& base_dir,
                         const MeshReadLimits& limits) {
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) {
    return UnsupportedError("the file has more than 4 GB");
  }
  FileAccess access;
  access.base_dir = base_dir;
  access.limits = &limits;
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&FileExistsCallback, &ExpandFilePathCallback,
                         &ReadWholeFileCallback, &WriteWholeFileCallback,
                         &access});
  ImageBytes images;
  images.budget = limits.max_memory_bytes - static_cast<int64_t>(bytes.size());
  loader.SetImageLoader(&KeepImageBytes, &images);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = bytes.size() >= 4 && bytes.substr(0, 4) == "glTF";
  GlbChunks chunks;  // views into the file's bytes
  if (binary) {
    SDCB_ASSIGN_OR_RETURN(chunks, SplitGlb(bytes));
  } else {
    chunks.json = bytes;
  }
  SDCB_ASSIGN_OR_RETURN(const std::string rewritten,
                        CheckAndRewriteJson(chunks, binary));
  if (!rewritten.empty()) bytes = rewritten;
  bool loaded = false;
  try {
    if (binary) {
      loaded = loader.LoadBinaryFromMemory(
          &model, &err, &warn,
          reinterpret_cast<const unsigned char*>(bytes.data()),
          static_cast<unsigned int>(bytes.size()), base_dir);
    } else {
      loaded = loader.LoadASCIIFromString(
          &model, &err, &warn, bytes.data(),
          static_cast<unsigned int>(bytes.size()), base_dir);
    }
  } catch (const std::exception& e) {
    return CorruptFileError(std::string("tinygltf: ") + e.what());
  }
  if (!loaded) {
    if (!access.missing.empty() &&
        err.find("File not found") != std::string::npos) {
      return CorruptFileError(
          "the buffer file '" + access.missing + "' " +
          (base_dir.empty() ? std::string("is external (a buffer read opens "
                                          "no files)")
                            : std::string("is missing")));
    }
    return CorruptFileError(OneSentence(err));
  }
  SDCB_ASSIGN_OR_RETURN(GltfAsset asset, Reader(model, limits).Read());
  GltfDocument& document = asset.document;
  document.json = std::string(chunks.json);
  for (tinygltf::Buffer& buffer : model.buffers) {
    document.buffers.emplace_back(buffer.data.begin(), buffer.data.end());
    buffer.data.clear();
  }
  // By the image's bufferView: tinygltf leaves `uri` empty for a data URI.
  images.bytes.resize(model.images.size());
  for (size_t i = 0; i < model.images.size(); ++i) {
    if (model.images[i].bufferView >= 0) images.bytes[i].clear();
  }
  document.images = std::move(images.bytes);
  return asset;
}

}  // namespace

StatusOr<GltfAsset> ReadGltfFromBuffer(std::string_view bytes,
                                       const MeshReadLimits& limits) {
  return Load(bytes, "", limits);
}

StatusOr<GltfAsset> ReadGltf(const std::string& path,
                             const MeshReadLimits& limits) {
  StatusOr<std::string> bytes = ReadMeshFileBytes(path, limits);
  if (!bytes.ok()) return bytes.status().WithPrefix(path);
  std::error_code ec;
  const fs::path dir = fs::absolute(fs::path(path), ec).parent_path();
  if (ec)
    return IoError("cannot resolve the file's directory").WithPrefix(path);
  MeshReadLimits rest = limits;
  rest.max_memory_bytes -= static_cast<int64_t>(bytes->size());
  StatusOr<GltfAsset> asset =
      Load(*bytes, dir.lexically_normal().string(), rest);
  if (!asset.ok()) return asset.status().WithPrefix(path);
  return asset;
}

TriangleMesh ConcatenatePrimitives(const GltfAsset& asset,
                                   std::vector<int>* face_primitive) {
  Eigen::Index vertices = 0, faces = 0;
  for (const GltfPrimitive& p : asset.primitives) {
    vertices += p.triangles.vertices.rows();
    faces += p.triangles.faces.rows();
  }
  TriangleMesh mesh;
  mesh.vertices.resize(vertices, 3);
  mesh.faces.resize(faces, 3);
  if (face_primitive != nullptr) face_primitive->assign(faces, 0);
  Eigen::Index v0 = 0, f0 = 0;
  for (size_t i = 0; i < asset.primitives.size(); ++i) {
    const TriangleMesh& t = asset.primitives[i].triangles;
    mesh.vertices.middleRows(v0, t.vertices.rows()) = t.vertices;
    mesh.faces.middleRows(f0, t.faces.rows()) =
        t.faces.array() + static_cast<int>(v0);
    if (face_primitive != nullptr) {
      std::fill(face_primitive->begin() + f0,
                face_primitive->begin() + f0 + t.faces.rows(),
                static_cast<int>(i));
    }
    v0 += t.vertices.rows();
    f0 += t.faces.rows();
  }
  return mesh;
}

bool IsGltfPath(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  return ext == ".gltf" || ext == ".glb";
}

}  // namespace sdcb
