#include "sdcb/converters/gltf_writer.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

#include "sdcb/io/atomic_file.h"

namespace sdcb {
namespace {

bool IsGlb(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".glb";
}

}  // namespace

Status WriteGltfMesh(const TriangleMesh& mesh, const std::string& path) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "sdcb";

  const size_t nv = static_cast<size_t>(mesh.num_vertices());
  const size_t nf = static_cast<size_t>(mesh.num_faces());
  tinygltf::Buffer buffer;
  buffer.data.resize(nv * 3 * sizeof(float) + nf * 3 * sizeof(uint32_t));
  std::vector<double> lo(3, std::numeric_limits<double>::max());
  std::vector<double> hi(3, std::numeric_limits<double>::lowest());
  unsigned char* out = buffer.data.data();
  for (size_t v = 0; v < nv; ++v) {
    for (int k = 0; k < 3; ++k) {
      const float c = static_cast<float>(mesh.vertices(v, k));
      std::memcpy(out, &c, sizeof c);
      out += sizeof c;
      lo[k] = std::min(lo[k], static_cast<double>(c));
      hi[k] = std::max(hi[k], static_cast<double>(c));
    }
  }
  for (size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t index = static_cast<uint32_t>(mesh.faces(f, k));
      std::memcpy(out, &index, sizeof index);
      out += sizeof index;
    }
  }
  model.buffers.push_back(std::move(buffer));

  tinygltf::BufferView positions_view;
  positions_view.buffer = 0;
  positions_view.byteOffset = 0;
  positions_view.byteLength = nv * 3 * sizeof(float);
  positions_view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  tinygltf::BufferView indices_view;
  indices_view.buffer = 0;
  indices_view.byteOffset = positions_view.byteLength;
  indices_view.byteLength = nf * 3 * sizeof(uint32_t);
  indices_view.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
  model.bufferViews = {positions_view, indices_view};

  tinygltf::Accessor positions;
  positions.bufferView = 0;
  positions.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  positions.count = nv;
  positions.type = TINYGLTF_TYPE_VEC3;
  positions.minValues = lo;
  positions.maxValues = hi;
  tinygltf::Accessor indices;
  indices.bufferView = 1;
  indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  indices.count = nf * 3;
  indices.type = TINYGLTF_TYPE_SCALAR;
  model.accessors = {positions, indices};

  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = 0;
  primitive.indices = 1;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh gltf_mesh;
  gltf_mesh.primitives.push_back(primitive);
  model.meshes.push_back(gltf_mesh);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  const bool glb = IsGlb(path);
  return WriteFileAtomically(
      [&](std::ostream& stream) {
        tinygltf::TinyGLTF writer;
        if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/!glb,
                                           glb)) {
          return IoError(path + ": tinygltf could not serialize the mesh");
        }
        return Status::Ok();
      },
      path);
}

StatusOr<TriangleMesh> ReadGltfMesh(const std::string& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  const bool ok = IsGlb(path)
                      ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                      : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) {
    std::string first_line = err.substr(0, err.find('\n'));
    return CorruptFileError(path + ": not a readable glTF file (" + first_line +
                            ")");
  }
  if (model.meshes.empty() || model.meshes[0].primitives.empty()) {
    return InvalidInputError(path + ": the glTF file holds no mesh");
  }
  const tinygltf::Primitive& primitive = model.meshes[0].primitives[0];
  auto it = primitive.attributes.find("POSITION");
  if (it == primitive.attributes.end() || primitive.indices < 0) {
    return InvalidInputError(path +
                             ": the first primitive has no indexed positions");
  }
  // Reads accessor element (i, k) as double, with bounds checks.
  auto read = [&](int accessor_index, size_t count_expected,
                  int components) -> StatusOr<std::vector<double>> {
    if (accessor_index < 0 ||
        accessor_index >= static_cast<int>(model.accessors.size())) {
      return CorruptFileError(path + ": accessor index out of range");
    }
    const tinygltf::Accessor& a = model.accessors[accessor_index];
    if (a.bufferView < 0 ||
        a.bufferView >= static_cast<int>(model.bufferViews.size())) {
      return CorruptFileError(path + ": buffer view index out of range");
    }
    const tinygltf::BufferView& view = model.bufferViews[a.bufferView];
    if (view.buffer < 0 ||
        view.buffer >= static_cast<int>(model.buffers.size())) {
      return CorruptFileError(path + ": buffer index out of range");
    }
    const auto& data = model.buffers[view.buffer].data;
    const int size = tinygltf::GetComponentSizeInBytes(a.componentType);
    const int n = tinygltf::GetNumComponentsInType(a.type);
    if (size <= 0 || n != components) {
      return CorruptFileError(path + ": unexpected accessor layout");
    }
    const size_t stride = view.byteStride ? view.byteStride : size_t(size) * n;
    const size_t start = view.byteOffset + a.byteOffset;
    if (a.count > 0 &&
        start + stride * (a.count - 1) + size_t(size) * n > data.size()) {
      return CorruptFileError(path + ": accessor runs past its buffer");
    }
    (void)count_expected;
    std::vector<double> values(a.count * n);
    for (size_t i = 0; i < a.count; ++i) {
      for (int k = 0; k < n; ++k) {
        const unsigned char* p =
            data.data() + start + stride * i + size_t(size) * k;
        switch (a.componentType) {
          case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float f;
            std::memcpy(&f, p, 4);
            values[i * n + k] = f;
            break;
          }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            uint32_t u;
            std::memcpy(&u, p, 4);
            values[i * n + k] = u;
            break;
          }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t u;
            std::memcpy(&u, p, 2);
            values[i * n + k] = u;
            break;
          }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            values[i * n + k] = *p;
            break;
          default:
            return CorruptFileError(path + ": unsupported component type");
        }
      }
    }
    return values;
  };
  SDCB_ASSIGN_OR_RETURN(const std::vector<double> xyz, read(it->second, 0, 3));
  SDCB_ASSIGN_OR_RETURN(const std::vector<double> idx,
                        read(primitive.indices, 0, 1));
  if (idx.size() % 3 != 0)
    return CorruptFileError(path + ": index count is not a multiple of 3");
  TriangleMesh mesh;
  const Eigen::Index nv = static_cast<Eigen::Index>(xyz.size() / 3);
  mesh.vertices.resize(nv, 3);
  for (Eigen::Index v = 0; v < nv; ++v) {
    for (int k = 0; k < 3; ++k) mesh.vertices(v, k) = xyz[3 * v + k];
  }
  mesh.faces.resize(static_cast<Eigen::Index>(idx.size() / 3), 3);
  for (size_t i = 0; i < idx.size(); ++i) {
    if (idx[i] >= nv) return CorruptFileError(path + ": index out of range");
    mesh.faces(i / 3, i % 3) = static_cast<int>(idx[i]);
  }
  return mesh;
}

}  // namespace sdcb
