#include "sdcb/converters/gltf/gltf_asset.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <nlohmann/json.hpp>

#include "sdcb/converters/gltf/glb_container.h"
#include "sdcb/converters/gltf/gltf_gather.h"

namespace sdcb {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kPartsKey = "sdcb_parts";

// Calls `f(index_json)` for every place the document names an accessor.
template <typename F>
void ForEachAccessorUse(Json& doc, F f) {
  if (doc.contains("meshes")) {
    for (Json& mesh : doc["meshes"]) {
      if (!mesh.contains("primitives")) continue;
      for (Json& p : mesh["primitives"]) {
        if (p.contains("attributes")) {
          for (auto& [key, a] : p["attributes"].items()) f(a);
        }
        if (p.contains("indices")) f(p["indices"]);
        if (p.contains("targets")) {
          for (Json& target : p["targets"]) {
            for (auto& [key, a] : target.items()) f(a);
          }
        }
      }
    }
  }
  if (doc.contains("skins")) {
    for (Json& skin : doc["skins"]) {
      if (skin.contains("inverseBindMatrices")) f(skin["inverseBindMatrices"]);
    }
  }
  if (doc.contains("animations")) {
    for (Json& animation : doc["animations"]) {
      if (!animation.contains("samplers")) continue;
      for (Json& sampler : animation["samplers"]) {
        if (sampler.contains("input")) f(sampler["input"]);
        if (sampler.contains("output")) f(sampler["output"]);
      }
    }
  }
}

// Calls `f(index_json)` for every place the document names a buffer view.
template <typename F>
void ForEachViewUse(Json& doc, F f) {
  if (doc.contains("accessors")) {
    for (Json& a : doc["accessors"]) {
      if (a.contains("bufferView")) f(a["bufferView"]);
      if (a.contains("sparse")) {
        for (const char* key : {"indices", "values"}) {
          if (a["sparse"].contains(key)) f(a["sparse"][key]["bufferView"]);
        }
      }
    }
  }
  if (doc.contains("images")) {
    for (Json& image : doc["images"]) {
      if (image.contains("bufferView")) f(image["bufferView"]);
    }
  }
  if (doc.contains("meshes")) {
    for (Json& mesh : doc["meshes"]) {
      if (!mesh.contains("primitives")) continue;
      for (Json& p : mesh["primitives"]) {
        if (p.contains("extensions") &&
            p["extensions"].contains("KHR_draco_mesh_compression")) {
          f(p["extensions"]["KHR_draco_mesh_compression"]["bufferView"]);
        }
      }
    }
  }
}

// Keeps the entries of doc[key] that `used` marks, renumbered in order, and
// returns old index -> new index (-1 for dropped).
std::vector<int> KeepUsed(Json* doc, const char* key,
                          const std::vector<bool>& used) {
  std::vector<int> renumber(used.size(), -1);
  Json kept = Json::array();
  for (size_t i = 0; i < used.size(); ++i) {
    if (!used[i]) continue;
    renumber[i] = static_cast<int>(kept.size());
    kept.push_back(std::move((*doc)[key][i]));
  }
  if (kept.empty()) {
    doc->erase(key);
  } else {
    (*doc)[key] = std::move(kept);
  }
  return renumber;
}

std::string MimeTypeOf(const std::string& uri) {
  if (uri.rfind("data:", 0) == 0) {
    const size_t end = uri.find_first_of(";,");
    return uri.substr(5, end == std::string::npos ? 0 : end - 5);
  }
  std::string ext = uri.substr(uri.find_last_of('.') + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == "png") return "image/png";
  if (ext == "jpg" || ext == "jpeg") return "image/jpeg";
  if (ext == "ktx2") return "image/ktx2";
  if (ext == "webp") return "image/webp";
  return "application/octet-stream";
}

StatusOr<std::string> MakeShell(const GltfDocument& document,
                                const std::vector<GltfFittedPrimitive>& fitted) {
  Json doc = Json::parse(document.json);
  for (const GltfFittedPrimitive& f : fitted) {
    Json& p = doc.at("meshes").at(f.mesh).at("primitives").at(f.primitive);
    p.erase("attributes");
    p.erase("indices");
    p.erase("targets");
    if (p.contains("extensions")) {
      p["extensions"].erase("KHR_draco_mesh_compression");
      if (p["extensions"].empty()) p.erase("extensions");
    }
    if (!p.contains("extras") || !p["extras"].is_object()) {
      p["extras"] = Json::object();
    }
    p["extras"][kPartsKey] = f.parts;
  }
  // The compression extensions only kept primitives may still need.
  bool draco_left = false;
  for (const Json& mesh : doc.value("meshes", Json::array())) {
    for (const Json& p : mesh.value("primitives", Json::array())) {
      draco_left = draco_left ||
                   (p.contains("extensions") &&
                    p["extensions"].contains("KHR_draco_mesh_compression"));
    }
  }
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (!doc.contains(key) || draco_left) continue;
    Json& names = doc[key];
    names.erase(std::remove(names.begin(), names.end(),
                            Json("KHR_draco_mesh_compression")),
                names.end());
    if (names.empty()) doc.erase(key);
  }
  // Accessors, then buffer views, that anything still names.
  const size_t num_accessors =
      doc.contains("accessors") ? doc["accessors"].size() : 0;
  std::vector<bool> accessor_used(num_accessors, false);
  ForEachAccessorUse(doc,
                     [&](Json& a) { accessor_used.at(a.get<size_t>()) = true; });
  const std::vector<int> accessor_of =
      KeepUsed(&doc, "accessors", accessor_used);
  ForEachAccessorUse(doc, [&](Json& a) { a = accessor_of[a.get<size_t>()]; });

  // Images given by a URI move into views appended after the file's.
  const size_t num_views =
      doc.contains("bufferViews") ? doc["bufferViews"].size() : 0;
  std::vector<std::string> image_bytes;
  if (doc.contains("images")) {
    for (size_t i = 0; i < doc["images"].size(); ++i) {
      Json& image = doc["images"][i];
      // An image whose file was not there keeps its URI.
      if (!image.contains("uri") || i >= document.images.size() ||
          document.images[i].empty()) {
        continue;
      }
      if (!image.contains("mimeType")) {
        image["mimeType"] = MimeTypeOf(image["uri"].get<std::string>());
      }
      image.erase("uri");
      image["bufferView"] = num_views + image_bytes.size();
      image_bytes.push_back(document.images[i]);
    }
  }
  std::vector<bool> view_used(num_views + image_bytes.size(), false);
  ForEachViewUse(doc, [&](Json& v) { view_used.at(v.get<size_t>()) = true; });
  // The bytes of every view kept, in one buffer, each view 4-aligned.
  std::string bin;
  Json views = Json::array();
  for (size_t v = 0; v < view_used.size(); ++v) {
    if (!view_used[v]) continue;
    Pad4(&bin, '\0');
    Json view;
    std::string_view bytes;
    if (v < num_views) {
      view = doc["bufferViews"][v];
      if (view.contains("extensions") &&
          view["extensions"].contains("EXT_meshopt_compression")) {
        return UnsupportedError(
            "a primitive kept as it was has meshopt-compressed data");
      }
      const size_t buffer = view.at("buffer").get<size_t>();
      const size_t offset = view.value("byteOffset", size_t{0});
      const size_t length = view.at("byteLength").get<size_t>();
      if (buffer >= document.buffers.size() ||
          offset + length > document.buffers[buffer].size()) {
        return InvalidInputError("buffer view " + std::to_string(v) +
                                 " reads past its buffer");
      }
      bytes = std::string_view(document.buffers[buffer]).substr(offset, length);
    } else {
      bytes = image_bytes[v - num_views];
    }
    view["buffer"] = 0;
    view["byteOffset"] = bin.size();
    view["byteLength"] = bytes.size();
    if (view["byteOffset"] == 0) view.erase("byteOffset");
    bin.append(bytes.data(), bytes.size());
    views.push_back(std::move(view));
  }
  doc["bufferViews"] = views;
  std::vector<int> view_of(view_used.size(), -1);
  int next = 0;
  for (size_t v = 0; v < view_used.size(); ++v) {
    if (view_used[v]) view_of[v] = next++;
  }
  ForEachViewUse(doc, [&](Json& v) { v = view_of[v.get<size_t>()]; });
  if (views.empty()) doc.erase("bufferViews");
  Pad4(&bin, '\0');
  if (bin.empty()) {
    doc.erase("buffers");
  } else {
    doc["buffers"] = Json::array({{{"byteLength", bin.size()}}});
  }
  return PackGlb(doc.dump(), std::move(bin));
}

}  // namespace

StatusOr<std::string> MakeGltfShell(
    const GltfDocument& document,
    const std::vector<GltfFittedPrimitive>& fitted) {
  try {
    return MakeShell(document, fitted);
  } catch (const nlohmann::json::exception& e) {
    return InvalidInputError(std::string("the glTF document: ") + e.what());
  }
}

StatusOr<std::vector<GltfFittedPrimitive>> ShellFittedPrimitives(
    std::string_view shell) {
  SDCB_ASSIGN_OR_RETURN(const GlbChunks chunks, SplitGlb(shell));
  std::vector<GltfFittedPrimitive> out;
  try {
    const Json doc = Json::parse(chunks.json);
    if (!doc.contains("meshes")) return out;
    for (size_t m = 0; m < doc["meshes"].size(); ++m) {
      const Json& primitives = doc["meshes"][m].at("primitives");
      for (size_t p = 0; p < primitives.size(); ++p) {
        const Json& prim = primitives[p];
        if (!prim.contains("extras") || !prim["extras"].is_object() ||
            !prim["extras"].contains(kPartsKey)) {
          continue;
        }
        GltfFittedPrimitive f;
        f.mesh = static_cast<int>(m);
        f.primitive = static_cast<int>(p);
        f.parts = prim["extras"][kPartsKey].get<std::vector<int>>();
        out.push_back(std::move(f));
      }
    }
  } catch (const nlohmann::json::exception& e) {
    return CorruptFileError(std::string("the stored glTF asset: ") + e.what());
  }
  return out;
}

namespace {

// Whether material `m` of `doc` samples any texture.
bool SamplesTexture(const Json& m) {
  for (const char* key : {"normalTexture", "occlusionTexture",
                          "emissiveTexture"}) {
    if (m.contains(key)) return true;
  }
  if (m.contains("pbrMetallicRoughness")) {
    const Json& pbr = m["pbrMetallicRoughness"];
    if (pbr.contains("baseColorTexture") ||
        pbr.contains("metallicRoughnessTexture")) {
      return true;
    }
  }
  return m.contains("extensions");  // e.g. KHR_materials_* textures
}

Json WithoutTextures(Json m) {
  for (const char* key : {"normalTexture", "occlusionTexture",
                          "emissiveTexture", "extensions"}) {
    m.erase(key);
  }
  if (m.contains("pbrMetallicRoughness")) {
    m["pbrMetallicRoughness"].erase("baseColorTexture");
    m["pbrMetallicRoughness"].erase("metallicRoughnessTexture");
  }
  return m;
}

StatusOr<EncodedGltfAsset> EncodeAsset(
    std::string_view shell, const std::vector<SurfaceMesh>& parts,
    const std::vector<GltfExportOptions>& options, bool binary) {
  if (options.size() != parts.size()) {
    return InvalidArgumentError("glTF parts need one set of options each");
  }
  for (const GltfExportOptions& o : options) {
    if (o.compression == GltfCompression::kMeshopt) {
      return UnsupportedError(
          "meshopt compression of a glTF asset is not supported (its "
          "dequantizing node transform would replace the asset's); use "
          "--draco or no compression");
    }
  }
  SDCB_ASSIGN_OR_RETURN(const std::vector<GltfFittedPrimitive> fitted,
                        ShellFittedPrimitives(shell));
  SDCB_ASSIGN_OR_RETURN(const GlbChunks chunks, SplitGlb(shell));
  GltfGather gather(Json::parse(chunks.json), std::string(chunks.bin));
  EncodedGltfAsset out;
  // Materials of fitted primitives that sample textures: each primitive
  // of them gets the material without its textures, one copy per material.
  std::map<int, int> textureless;
  std::vector<int> uses;
  {
    const Json& doc = gather.json();
    for (const Json& mesh : doc["meshes"]) {
      for (const Json& p : mesh.at("primitives")) {
        if (!p.contains("material")) continue;
        const size_t m = p["material"].get<size_t>();
        if (uses.size() <= m) uses.resize(m + 1, 0);
        ++uses[m];
      }
    }
  }
  for (const GltfFittedPrimitive& f : fitted) {
    if (f.parts.empty()) {
      return InvalidArgumentError("a fitted primitive names no part");
    }
    SurfaceMesh mesh;
    GltfExportOptions o;
    Eigen::Index nv = 0, nf = 0;
    for (const int k : f.parts) {
      if (k < 0 || k >= static_cast<int>(parts.size())) {
        return InvalidArgumentError("the asset names part " +
                                    std::to_string(k + 1) + " of " +
                                    std::to_string(parts.size()));
      }
      nv += parts[k].positions.rows();
      nf += parts[k].faces.rows();
    }
    const SurfaceMesh& first = parts[f.parts[0]];
    o = options[f.parts[0]];
    mesh.positions.resize(nv, 3);
    mesh.normals.resize(first.normals.rows() > 0 ? nv : 0, 3);
    mesh.colors.resize(first.colors.rows() > 0 ? nv : 0, 3);
    mesh.faces.resize(nf, 3);
    nv = nf = 0;
    for (const int k : f.parts) {
      const SurfaceMesh& p = parts[k];
      const Eigen::Index v = p.positions.rows();
      mesh.positions.middleRows(nv, v) = p.positions;
      if (mesh.normals.rows() > 0) mesh.normals.middleRows(nv, v) = p.normals;
      if (mesh.colors.rows() > 0) mesh.colors.middleRows(nv, v) = p.colors;
      mesh.faces.middleRows(nf, p.faces.rows()) =
          p.faces.array() + static_cast<int>(nv);
      o.position_bits = std::max(o.position_bits, options[k].position_bits);
      nv += v;
      nf += p.faces.rows();
    }
    SDCB_ASSIGN_OR_RETURN(const EncodedGltf encoded,
                          EncodeGltf(mesh, o, /*binary=*/true));
    SDCB_ASSIGN_OR_RETURN(Json made,
                          gather.AppendMesh(encoded, /*keep_materials=*/false));
    Json& doc = gather.json();
    Json& p = doc["meshes"].at(f.mesh).at("primitives").at(f.primitive);
    const Json& from = made.at("primitives").at(0);
    for (const char* key : {"attributes", "indices"}) {
      if (from.contains(key)) p[key] = from[key];
    }
    if (from.contains("extensions")) p["extensions"].update(from["extensions"]);
    p["extras"].erase(kPartsKey);
    if (p["extras"].empty()) p.erase("extras");
    if (p.contains("material")) {
      const int m = p["material"].get<int>();
      if (SamplesTexture(doc["materials"].at(m))) {
        auto it = textureless.find(m);
        if (it == textureless.end()) {
          int to = m;
          if (uses[m] > 1) {
            to = static_cast<int>(doc["materials"].size());
            doc["materials"].push_back(doc["materials"][m]);
          }
          doc["materials"][to] = WithoutTextures(doc["materials"][to]);
          it = textureless.emplace(m, to).first;
          ++out.textureless_materials;
        }
        p["material"] = it->second;
      }
    }
    ++out.fitted_primitives;
  }
  out.gltf = gather.Finish(binary);
  return out;
}

}  // namespace

StatusOr<EncodedGltfAsset> EncodeGltfAsset(
    std::string_view shell, const std::vector<SurfaceMesh>& parts,
    const std::vector<GltfExportOptions>& options, bool binary) {
  try {
    return EncodeAsset(shell, parts, options, binary);
  } catch (const nlohmann::json::exception& e) {
    return CorruptFileError(std::string("the stored glTF asset: ") + e.what());
  }
}

}  // namespace sdcb
