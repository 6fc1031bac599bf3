#include "sdcb/converters/gltf/gltf_asset.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "sdcb/converters/gltf/glb_container.h"
#include "sdcb/converters/gltf/gltf_gather.h"

namespace sdcb {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kPartsKey = "sdcb_parts";
constexpr const char* kAtlasKey = "sdcb_atlas";
constexpr int kLinear = 9729;
constexpr int kClampToEdge = 33071;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kElementArrayBuffer = 34963;

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

// The material `m` without any texture or extension.
Json WithoutTextures(Json m) {
  for (const char* key :
       {"normalTexture", "occlusionTexture", "emissiveTexture", "extensions"}) {
    m.erase(key);
  }
  if (m.contains("pbrMetallicRoughness")) {
    m["pbrMetallicRoughness"].erase("baseColorTexture");
    m["pbrMetallicRoughness"].erase("metallicRoughnessTexture");
  }
  return m;
}

// Calls `f(index_json)` for every texture index under `j` (the "index" of
// any object whose key ends in "Texture": glTF's texture infos, those of
// KHR_materials_* too).
template <typename F>
void ForEachTextureUse(Json& j, F f) {
  if (!j.is_object() && !j.is_array()) return;
  for (auto& [key, value] : j.items()) {
    if (value.is_object() && key.size() >= 7 &&
        key.compare(key.size() - 7, 7, "Texture") == 0 &&
        value.contains("index")) {
      f(value["index"]);
    }
    ForEachTextureUse(value, f);
  }
}

// Drops the materials no primitive uses any more (those an atlas replaced),
// then the textures no material uses, then the images and samplers no
// texture uses, renumbering what names them.
void DropUnusedMaterials(Json* doc) {
  if (!doc->contains("materials")) return;
  std::vector<bool> used((*doc)["materials"].size(), false);
  for (Json& mesh : (*doc)["meshes"]) {
    for (Json& p : mesh["primitives"]) {
      if (p.contains("material")) used.at(p["material"].get<size_t>()) = true;
    }
  }
  const std::vector<int> material_of = KeepUsed(doc, "materials", used);
  for (Json& mesh : (*doc)["meshes"]) {
    for (Json& p : mesh["primitives"]) {
      if (p.contains("material"))
        p["material"] = material_of[p["material"].get<size_t>()];
    }
  }
  if (!doc->contains("textures")) return;
  used.assign((*doc)["textures"].size(), false);
  if (doc->contains("materials")) {
    ForEachTextureUse((*doc)["materials"],
                      [&](Json& t) { used.at(t.get<size_t>()) = true; });
  }
  const std::vector<int> texture_of = KeepUsed(doc, "textures", used);
  if (doc->contains("materials")) {
    ForEachTextureUse((*doc)["materials"],
                      [&](Json& t) { t = texture_of[t.get<size_t>()]; });
  }
  for (const char* key : {"images", "samplers"}) {
    if (!doc->contains(key)) continue;
    const char* field = key[0] == 'i' ? "source" : "sampler";
    used.assign((*doc)[key].size(), false);
    for (Json& t : doc->value("textures", Json::array())) {
      if (t.contains(field)) used.at(t[field].get<size_t>()) = true;
    }
    const std::vector<int> of = KeepUsed(doc, key, used);
    if (!doc->contains("textures")) continue;
    for (Json& t : (*doc)["textures"]) {
      if (t.contains(field)) t[field] = of[t[field].get<size_t>()];
    }
  }
}

// Collects the names of the extensions every "extensions" object under `j`
// holds (extras skipped: what they hold is the application's).
void CollectExtensionNames(const Json& j, std::set<std::string>* names) {
  if (j.is_array()) {
    for (const Json& v : j) CollectExtensionNames(v, names);
    return;
  }
  if (!j.is_object()) return;
  for (const auto& [key, value] : j.items()) {
    if (key == "extras") continue;
    if (key == "extensions" && value.is_object()) {
      for (const auto& [name, ext] : value.items()) names->insert(name);
    }
    CollectExtensionNames(value, names);
  }
}

// Drops from extensionsUsed and extensionsRequired the names no object uses
// (gltf_asset.h, MakeGltfShell), FB_ngon_encoding too when `fitted`.
void DropUnusedExtensionNames(Json* doc, bool fitted) {
  std::set<std::string> used;
  CollectExtensionNames(*doc, &used);
  // Names a file may list without any object: the quantized accessor
  // types of kept primitives; FB_ngon_encoding as a flag of the whole file,
  // which a fitted primitive's triangles make false.
  used.insert("KHR_mesh_quantization");
  if (!fitted) used.insert("FB_ngon_encoding");
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (!doc->contains(key) || !(*doc)[key].is_array()) continue;
    Json& names = (*doc)[key];
    names.erase(std::remove_if(names.begin(), names.end(),
                               [&](const Json& name) {
                                 return !name.is_string() ||
                                        used.count(name.get<std::string>()) ==
                                            0;
                               }),
                names.end());
    if (names.empty()) doc->erase(key);
  }
}

// Drops from primitive `p` the extensions that describe its triangles as
// the file had them: Draco's data, FB_ngon_encoding's polygons (runs of
// consecutive triangles with one first vertex).
void DropTriangleExtensions(Json* p) {
  if (!p->contains("extensions")) return;
  (*p)["extensions"].erase("KHR_draco_mesh_compression");
  (*p)["extensions"].erase("FB_ngon_encoding");
  if ((*p)["extensions"].empty()) p->erase("extensions");
}

// Takes the geometry out of primitive `p`, which then holds `parts`.
void HoldParts(const std::vector<int>& parts, Json* p) {
  for (const char* key : {"attributes", "indices", "targets", "mode"}) {
    p->erase(key);
  }
  DropTriangleExtensions(p);
  if (!p->contains("extras") || !(*p)["extras"].is_object()) {
    (*p)["extras"] = Json::object();
  }
  (*p)["extras"][kPartsKey] = parts;
}

// A buffer view appended after the file's, and its target (0 for none).
struct AppendedView {
  std::string bytes;
  int target = 0;
};

// Appends an accessor of the triangles `corners` (#K by 3 vertex indices)
// and the view of its bytes (the `num_views` file's views come first);
// returns the accessor's index.
size_t AppendIndices(const Eigen::MatrixX3i& corners, size_t num_views,
                     Json* doc, std::vector<AppendedView>* appended) {
  // glTF forbids an index of the type's largest value (primitive restart).
  const bool shorts = corners.maxCoeff() < 65535;
  AppendedView view;
  view.target = kElementArrayBuffer;
  for (Eigen::Index f = 0; f < corners.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      // Little-endian, as glTF's buffers are (and this machine's words).
      const uint32_t index = static_cast<uint32_t>(corners(f, k));
      const uint16_t index16 = static_cast<uint16_t>(index);
      if (shorts) {
        view.bytes.append(reinterpret_cast<const char*>(&index16), 2);
      } else {
        view.bytes.append(reinterpret_cast<const char*>(&index), 4);
      }
    }
  }
  Json& accessors = (*doc)["accessors"];
  accessors.push_back(
      {{"bufferView", num_views + appended->size()},
       {"componentType", shorts ? kUnsignedShort : kUnsignedInt},
       {"count", 3 * corners.rows()},
       {"type", "SCALAR"}});
  appended->push_back(std::move(view));
  return accessors.size() - 1;
}

// Takes the geometry of `fitted` out of `doc` (HoldParts); a primitive with
// kept triangles is split, its indices' bytes appended to `appended` (after
// the `num_views` file's views). Returns, per fitted primitive, the index in
// its mesh of the primitive that holds its parts.
StatusOr<std::vector<size_t>> TakeGeometryOut(
    const std::vector<GltfFittedPrimitive>& fitted, size_t num_views, Json* doc,
    std::vector<AppendedView>* appended) {
  std::vector<size_t> holder(fitted.size());
  for (size_t i = 0; i < fitted.size(); ++i) {
    const GltfFittedPrimitive& f = fitted[i];
    Json& primitives = doc->at("meshes").at(f.mesh).at("primitives");
    Json& p = primitives.at(f.primitive);
    holder[i] = static_cast<size_t>(f.primitive);
    if (f.kept_corners.rows() == 0) {
      HoldParts(f.parts, &p);
      continue;
    }
    if (p.contains("extensions") &&
        p["extensions"].contains("KHR_draco_mesh_compression")) {
      return InvalidArgumentError(
          "kept triangles of a Draco-compressed primitive cannot be "
          "re-indexed");
    }
    if (f.kept_corners.minCoeff() < 0) {
      return InvalidArgumentError("a kept triangle has a negative index");
    }
    Json holding = p;
    HoldParts(f.parts, &holding);
    p["indices"] = AppendIndices(f.kept_corners, num_views, doc, appended);
    p.erase("mode");
    // With the fitted triangles gone from between them, two polygons of
    // the kept ones could become consecutive and read as one.
    DropTriangleExtensions(&p);
    holder[i] = primitives.size();
    primitives.push_back(std::move(holding));
  }
  return holder;
}

StatusOr<std::string> MakeShell(
    const GltfDocument& document,
    const std::vector<GltfFittedPrimitive>& fitted) {
  Json doc = Json::parse(document.json);
  const size_t num_views =
      doc.contains("bufferViews") ? doc["bufferViews"].size() : 0;
  std::vector<AppendedView> appended;
  SDCB_ASSIGN_OR_RETURN(const std::vector<size_t> holder,
                        TakeGeometryOut(fitted, num_views, &doc, &appended));
  // Accessors, then buffer views, that anything still names.
  const size_t num_accessors =
      doc.contains("accessors") ? doc["accessors"].size() : 0;
  std::vector<bool> accessor_used(num_accessors, false);
  ForEachAccessorUse(
      doc, [&](Json& a) { accessor_used.at(a.get<size_t>()) = true; });
  const std::vector<int> accessor_of =
      KeepUsed(&doc, "accessors", accessor_used);
  ForEachAccessorUse(doc, [&](Json& a) { a = accessor_of[a.get<size_t>()]; });

  // Images given by a URI move into views appended after the file's.
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
      image["bufferView"] = num_views + appended.size();
      appended.push_back({document.images[i], 0});
    }
  }
  // Each atlas: an image in a new view, a sampler, a texture and a copy of
  // the primitive's material that samples it.
  for (size_t i = 0; i < fitted.size(); ++i) {
    const GltfFittedPrimitive& f = fitted[i];
    if (f.atlas_png.empty()) continue;
    Json& p = doc["meshes"][f.mesh]["primitives"][holder[i]];
    const size_t image = doc.contains("images") ? doc["images"].size() : 0;
    doc["images"].push_back({{"mimeType", "image/png"},
                             {"bufferView", num_views + appended.size()}});
    appended.push_back({f.atlas_png, 0});
    const size_t sampler =
        doc.contains("samplers") ? doc["samplers"].size() : 0;
    doc["samplers"].push_back({{"magFilter", kLinear},
                               {"minFilter", kLinear},
                               {"wrapS", kClampToEdge},
                               {"wrapT", kClampToEdge}});
    const size_t texture =
        doc.contains("textures") ? doc["textures"].size() : 0;
    doc["textures"].push_back({{"sampler", sampler}, {"source", image}});
    Json material =
        p.contains("material")
            ? WithoutTextures(doc["materials"].at(p["material"].get<size_t>()))
            : Json::object();
    material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", texture}};
    p["material"] = doc.contains("materials") ? doc["materials"].size() : 0;
    doc["materials"].push_back(std::move(material));
    p["extras"][kAtlasKey] = {{"tile", f.atlas_layout.tile},
                              {"parts", f.atlas_layout.parts},
                              {"extent", f.atlas_layout.extent}};
  }
  bool atlases = false;
  for (const GltfFittedPrimitive& f : fitted) atlases |= !f.atlas_png.empty();
  if (atlases) DropUnusedMaterials(&doc);
  std::vector<bool> view_used(num_views + appended.size(), false);
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
      const AppendedView& made = appended[v - num_views];
      bytes = made.bytes;
      if (made.target != 0) view["target"] = made.target;
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
  DropUnusedExtensionNames(&doc, !fitted.empty());
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
  for (const char* key :
       {"normalTexture", "occlusionTexture", "emissiveTexture"}) {
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

// `part` with its vertices split and texture coordinates set for the
// atlas tiles of block `slot` (CubeAtlasTexcoords).
StatusOr<SurfaceMesh> WithAtlasTexcoords(const SurfaceMesh& part,
                                         const CubeAtlasLayout& layout,
                                         int slot, int* beyond) {
  if (part.directions.rows() != part.positions.rows()) {
    return InvalidArgumentError(
        "a part of a primitive with a texture atlas has no sphere points");
  }
  const CubeAtlasMesh atlas =
      CubeAtlasTexcoords(layout, slot, part.directions, part.faces);
  *beyond += atlas.corners_beyond_extent;
  const Eigen::Index n = static_cast<Eigen::Index>(atlas.vertex.size());
  SurfaceMesh out;
  out.positions.resize(n, 3);
  out.normals.resize(part.normals.rows() > 0 ? n : 0, 3);
  out.colors.resize(part.colors.rows() > 0 ? n : 0, 3);
  out.directions.resize(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    const int from = atlas.vertex[v];
    out.positions.row(v) = part.positions.row(from);
    if (out.normals.rows() > 0) out.normals.row(v) = part.normals.row(from);
    if (out.colors.rows() > 0) out.colors.row(v) = part.colors.row(from);
    out.directions.row(v) = part.directions.row(from);
  }
  out.faces = atlas.faces;
  out.texcoords = atlas.texcoords;
  return out;
}

StatusOr<EncodedGltfAsset> EncodeAsset(
    std::string_view shell, const std::vector<SurfaceMesh>& parts,
    const std::vector<GltfExportOptions>& options, bool binary) {
  if (options.size() != parts.size()) {
    return InvalidArgumentError("glTF parts need one set of options each");
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
    for (const int k : f.parts) {
      if (k < 0 || k >= static_cast<int>(parts.size())) {
        return InvalidArgumentError("the asset names part " +
                                    std::to_string(k + 1) + " of " +
                                    std::to_string(parts.size()));
      }
    }
    // The parts as written: split for the atlas's tiles if it has one.
    const Json& shell_primitive =
        gather.json()["meshes"].at(f.mesh).at("primitives").at(f.primitive);
    const bool atlas = shell_primitive.contains("extras") &&
                       shell_primitive["extras"].contains(kAtlasKey);
    std::vector<SurfaceMesh> split;
    if (atlas) {
      const Json& a = shell_primitive["extras"][kAtlasKey];
      CubeAtlasLayout layout;
      layout.tile = a.at("tile").get<int>();
      layout.parts = a.at("parts").get<int>();
      layout.extent = a.at("extent").get<double>();
      if (layout.parts != static_cast<int>(f.parts.size()) || layout.tile < 1) {
        return CorruptFileError(
            "the stored glTF asset: an atlas's layout does not match its "
            "primitive's parts");
      }
      for (size_t slot = 0; slot < f.parts.size(); ++slot) {
        SDCB_ASSIGN_OR_RETURN(
            SurfaceMesh m,
            WithAtlasTexcoords(parts[f.parts[slot]], layout,
                               static_cast<int>(slot),
                               &out.atlas_vertices_beyond_extent));
        split.push_back(std::move(m));
      }
      ++out.atlas_primitives;
    }
    const auto part_mesh = [&](size_t slot) -> const SurfaceMesh& {
      return atlas ? split[slot] : parts[f.parts[slot]];
    };
    Eigen::Index nv = 0, nf = 0;
    for (size_t slot = 0; slot < f.parts.size(); ++slot) {
      nv += part_mesh(slot).positions.rows();
      nf += part_mesh(slot).faces.rows();
    }
    const SurfaceMesh& first = part_mesh(0);
    o = options[f.parts[0]];
    // The asset's nodes keep their own transforms: meshopt's positions are
    // floats, not a grid that a node transform undoes.
    o.meshopt_positions = GltfMeshoptPositions::kExponential;
    mesh.positions.resize(nv, 3);
    mesh.normals.resize(first.normals.rows() > 0 ? nv : 0, 3);
    mesh.colors.resize(first.colors.rows() > 0 ? nv : 0, 3);
    mesh.texcoords.resize(atlas ? nv : 0, 2);
    mesh.faces.resize(nf, 3);
    nv = nf = 0;
    for (size_t slot = 0; slot < f.parts.size(); ++slot) {
      const SurfaceMesh& p = part_mesh(slot);
      const Eigen::Index v = p.positions.rows();
      mesh.positions.middleRows(nv, v) = p.positions;
      if (mesh.normals.rows() > 0) mesh.normals.middleRows(nv, v) = p.normals;
      if (mesh.colors.rows() > 0) mesh.colors.middleRows(nv, v) = p.colors;
      if (atlas) mesh.texcoords.middleRows(nv, v) = p.texcoords;
      mesh.faces.middleRows(nf, p.faces.rows()) =
          p.faces.array() + static_cast<int>(nv);
      o.position_bits =
          std::max(o.position_bits, options[f.parts[slot]].position_bits);
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
    p["extras"].erase(kAtlasKey);
    if (p["extras"].empty()) p.erase("extras");
    if (p.contains("material") && !atlas) {
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
  DropUnusedExtensionNames(&gather.json(), !fitted.empty());
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
