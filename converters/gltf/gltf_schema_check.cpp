#include "sdcb/converters/gltf/gltf_schema_check.h"

#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace sdcb {
namespace {

// What a JSON value must be.
enum class JsonType {
  kObject,
  kArray,
  kString,
  kNumber,
  kInteger,
  kIndex,  // glTFid.schema.json: an integer >= 0
  kBoolean,
};

struct Property;

// The rule of one JSON value. An object is either a glTF property, whose
// `properties` are checked when present (others are allowed) and whose
// `extensions` is checked in every one, or a map whose every value follows
// `each` (a primitive's `attributes`); an array's elements follow `each`.
struct Rule {
  JsonType type;
  const Property* properties = nullptr;
  size_t property_count = 0;
  const Rule* each = nullptr;
};

struct Property {
  const char* name;
  Rule rule;
};

constexpr Rule kObject{JsonType::kObject};  // any object
constexpr Rule kString{JsonType::kString};
constexpr Rule kNumber{JsonType::kNumber};
constexpr Rule kInteger{JsonType::kInteger};
constexpr Rule kIndex{JsonType::kIndex};
constexpr Rule kBoolean{JsonType::kBoolean};

constexpr Rule ArrayOf(const Rule& each) {
  return {JsonType::kArray, nullptr, 0, &each};
}
constexpr Rule MapOf(const Rule& each) {
  return {JsonType::kObject, nullptr, 0, &each};
}
template <size_t N>
constexpr Rule GltfProperty(const Property (&properties)[N]) {
  return {JsonType::kObject, properties, N, nullptr};
}

constexpr Rule kNumbers = ArrayOf(kNumber);
constexpr Rule kIndices = ArrayOf(kIndex);
constexpr Rule kStrings = ArrayOf(kString);
// extension.schema.json: every extension's value is an object.
constexpr Rule kExtensions = MapOf(kObject);

// One table per schema file, named after it; `name` is
// glTFChildOfRootProperty's.
constexpr Property kAccessorSparseIndices[] = {
    {"bufferView", kIndex},
    {"byteOffset", kInteger},
    {"componentType", kInteger},
};
constexpr Property kAccessorSparseValues[] = {
    {"bufferView", kIndex},
    {"byteOffset", kInteger},
};
constexpr Property kAccessorSparse[] = {
    {"count", kInteger},
    {"indices", GltfProperty(kAccessorSparseIndices)},
    {"values", GltfProperty(kAccessorSparseValues)},
};
constexpr Property kAccessor[] = {
    {"bufferView", kIndex},
    {"byteOffset", kInteger},
    {"componentType", kInteger},
    {"normalized", kBoolean},
    {"count", kInteger},
    {"type", kString},
    {"max", kNumbers},
    {"min", kNumbers},
    {"sparse", GltfProperty(kAccessorSparse)},
    {"name", kString},
};

constexpr Property kAnimationChannelTarget[] = {
    {"node", kIndex},
    {"path", kString},
};
constexpr Property kAnimationChannel[] = {
    {"sampler", kIndex},
    {"target", GltfProperty(kAnimationChannelTarget)},
};
constexpr Property kAnimationSampler[] = {
    {"input", kIndex},
    {"interpolation", kString},
    {"output", kIndex},
};
constexpr Rule kAnimationChannelRule = GltfProperty(kAnimationChannel);
constexpr Rule kAnimationSamplerRule = GltfProperty(kAnimationSampler);
constexpr Property kAnimation[] = {
    {"channels", ArrayOf(kAnimationChannelRule)},
    {"samplers", ArrayOf(kAnimationSamplerRule)},
    {"name", kString},
};

constexpr Property kAsset[] = {
    {"copyright", kString},
    {"generator", kString},
    {"version", kString},
    {"minVersion", kString},
};

constexpr Property kBuffer[] = {
    {"uri", kString},
    {"byteLength", kInteger},
    {"name", kString},
};

constexpr Property kBufferView[] = {
    {"buffer", kIndex},       {"byteOffset", kInteger},
    {"byteLength", kInteger}, {"byteStride", kInteger},
    {"target", kInteger},     {"name", kString},
};

constexpr Property kCameraOrthographic[] = {
    {"xmag", kNumber},
    {"ymag", kNumber},
    {"zfar", kNumber},
    {"znear", kNumber},
};
constexpr Property kCameraPerspective[] = {
    {"aspectRatio", kNumber},
    {"yfov", kNumber},
    {"zfar", kNumber},
    {"znear", kNumber},
};
constexpr Property kCamera[] = {
    {"orthographic", GltfProperty(kCameraOrthographic)},
    {"perspective", GltfProperty(kCameraPerspective)},
    {"type", kString},
    {"name", kString},
};

constexpr Property kImage[] = {
    {"uri", kString},
    {"mimeType", kString},
    {"bufferView", kIndex},
    {"name", kString},
};

constexpr Property kTextureInfo[] = {
    {"index", kIndex},
    {"texCoord", kInteger},
};
constexpr Property kMaterialNormalTextureInfo[] = {
    {"index", kIndex},
    {"texCoord", kInteger},
    {"scale", kNumber},
};
constexpr Property kMaterialOcclusionTextureInfo[] = {
    {"index", kIndex},
    {"texCoord", kInteger},
    {"strength", kNumber},
};
constexpr Property kMaterialPbrMetallicRoughness[] = {
    {"baseColorFactor", kNumbers},
    {"baseColorTexture", GltfProperty(kTextureInfo)},
    {"metallicFactor", kNumber},
    {"roughnessFactor", kNumber},
    {"metallicRoughnessTexture", GltfProperty(kTextureInfo)},
};
constexpr Property kMaterial[] = {
    {"name", kString},
    {"pbrMetallicRoughness", GltfProperty(kMaterialPbrMetallicRoughness)},
    {"normalTexture", GltfProperty(kMaterialNormalTextureInfo)},
    {"occlusionTexture", GltfProperty(kMaterialOcclusionTextureInfo)},
    {"emissiveTexture", GltfProperty(kTextureInfo)},
    {"emissiveFactor", kNumbers},
    {"alphaMode", kString},
    {"alphaCutoff", kNumber},
    {"doubleSided", kBoolean},
};

// `attributes` and each morph target: semantic -> accessor index.
constexpr Rule kAttributes = MapOf(kIndex);
constexpr Property kMeshPrimitive[] = {
    {"attributes", kAttributes},
    {"indices", kIndex},
    {"material", kIndex},
    {"mode", kInteger},
    {"targets", ArrayOf(kAttributes)},
};
constexpr Rule kMeshPrimitiveRule = GltfProperty(kMeshPrimitive);
constexpr Property kMesh[] = {
    {"primitives", ArrayOf(kMeshPrimitiveRule)},
    {"weights", kNumbers},
    {"name", kString},
};

constexpr Property kNode[] = {
    {"camera", kIndex},   {"children", kIndices},    {"skin", kIndex},
    {"matrix", kNumbers}, {"mesh", kIndex},          {"rotation", kNumbers},
    {"scale", kNumbers},  {"translation", kNumbers}, {"weights", kNumbers},
    {"name", kString},
};

constexpr Property kSampler[] = {
    {"magFilter", kInteger}, {"minFilter", kInteger}, {"wrapS", kInteger},
    {"wrapT", kInteger},     {"name", kString},
};

constexpr Property kScene[] = {
    {"nodes", kIndices},
    {"name", kString},
};

constexpr Property kSkin[] = {
    {"inverseBindMatrices", kIndex},
    {"skeleton", kIndex},
    {"joints", kIndices},
    {"name", kString},
};

constexpr Property kTexture[] = {
    {"sampler", kIndex},
    {"source", kIndex},
    {"name", kString},
};

constexpr Rule kAccessorRule = GltfProperty(kAccessor);
constexpr Rule kAnimationRule = GltfProperty(kAnimation);
constexpr Rule kBufferRule = GltfProperty(kBuffer);
constexpr Rule kBufferViewRule = GltfProperty(kBufferView);
constexpr Rule kCameraRule = GltfProperty(kCamera);
constexpr Rule kImageRule = GltfProperty(kImage);
constexpr Rule kMaterialRule = GltfProperty(kMaterial);
constexpr Rule kMeshRule = GltfProperty(kMesh);
constexpr Rule kNodeRule = GltfProperty(kNode);
constexpr Rule kSamplerRule = GltfProperty(kSampler);
constexpr Rule kSceneRule = GltfProperty(kScene);
constexpr Rule kSkinRule = GltfProperty(kSkin);
constexpr Rule kTextureRule = GltfProperty(kTexture);
constexpr Property kGltf[] = {
    {"extensionsUsed", kStrings},
    {"extensionsRequired", kStrings},
    {"accessors", ArrayOf(kAccessorRule)},
    {"animations", ArrayOf(kAnimationRule)},
    {"asset", GltfProperty(kAsset)},
    {"buffers", ArrayOf(kBufferRule)},
    {"bufferViews", ArrayOf(kBufferViewRule)},
    {"cameras", ArrayOf(kCameraRule)},
    {"images", ArrayOf(kImageRule)},
    {"materials", ArrayOf(kMaterialRule)},
    {"meshes", ArrayOf(kMeshRule)},
    {"nodes", ArrayOf(kNodeRule)},
    {"samplers", ArrayOf(kSamplerRule)},
    {"scene", kIndex},
    {"scenes", ArrayOf(kSceneRule)},
    {"skins", ArrayOf(kSkinRule)},
    {"textures", ArrayOf(kTextureRule)},
};
constexpr Rule kGltfRule = GltfProperty(kGltf);

// JSON Schema's "integer": a number with a zero fractional part (1.0 is
// one; the Khronos validator and tinygltf accept it as an index).
bool IsInteger(const nlohmann::json& value) {
  if (value.is_number_integer()) return true;
  if (!value.is_number_float()) return false;
  const double x = value.get<double>();
  return std::isfinite(x) && std::floor(x) == x;
}

bool IsNonNegative(const nlohmann::json& value) {
  if (value.is_number_unsigned()) return true;
  if (value.is_number_integer()) return value.get<int64_t>() >= 0;
  return value.get<double>() >= 0;
}

bool HasType(const nlohmann::json& value, JsonType type) {
  switch (type) {
    case JsonType::kObject:
      return value.is_object();
    case JsonType::kArray:
      return value.is_array();
    case JsonType::kString:
      return value.is_string();
    case JsonType::kNumber:
      return value.is_number();
    case JsonType::kInteger:
      return IsInteger(value);
    case JsonType::kIndex:
      return IsInteger(value) && IsNonNegative(value);
    case JsonType::kBoolean:
      return value.is_boolean();
  }
  return false;
}

const char* TypeName(JsonType type) {
  switch (type) {
    case JsonType::kObject:
      return "an object";
    case JsonType::kArray:
      return "an array";
    case JsonType::kString:
      return "a string";
    case JsonType::kNumber:
      return "a number";
    case JsonType::kInteger:
      return "an integer";
    case JsonType::kIndex:
      return "a non-negative integer";
    case JsonType::kBoolean:
      return "a boolean";
  }
  return "?";
}

// `text` JSON-quoted (control bytes and non-ASCII escaped), its first 40
// bytes only, with "..." inside the quotes when cut.
std::string Quoted(const std::string& text) {
  constexpr size_t kShown = 40;
  const bool cut = text.size() > kShown;
  std::string quoted =
      nlohmann::json(cut ? text.substr(0, kShown) : text)
          .dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
  if (cut) quoted.insert(quoted.size() - 1, "...");
  return quoted;
}

// A value as the message shows it: a scalar as written, a string quoted,
// an object or an array by its kind only.
std::string Shown(const nlohmann::json& value) {
  if (value.is_object()) return "an object";
  if (value.is_array()) return "an array";
  if (value.is_string()) return Quoted(value.get<std::string>());
  return value.dump();
}

// `path` with the member `key` appended: ".key", or ["key"] (quoted) when
// the key is not a plain identifier (keys of maps come from the file).
void AppendKey(const std::string& key, std::string* path) {
  bool plain = !key.empty() && key.size() <= 40;
  for (const char c : key) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') {
      plain = false;
    }
  }
  if (!plain) {
    *path += "[" + Quoted(key) + "]";
  } else {
    if (!path->empty()) *path += ".";
    *path += key;
  }
}

// Checks `value` against `rule`; `path` names it (restored on return).
Status Check(const nlohmann::json& value, const Rule& rule, std::string* path);

Status CheckMember(const nlohmann::json& value, const std::string& key,
                   const Rule& rule, std::string* path) {
  const size_t length = path->size();
  AppendKey(key, path);
  SDCB_RETURN_IF_ERROR(Check(value, rule, path));
  path->resize(length);
  return Status::Ok();
}

Status Check(const nlohmann::json& value, const Rule& rule, std::string* path) {
  if (!HasType(value, rule.type)) {
    return CorruptFileError((path->empty() ? "the JSON" : *path) + " is " +
                            Shown(value) + ", not " + TypeName(rule.type) +
                            " (glTF 2.0 schema)");
  }
  if (rule.type == JsonType::kArray) {
    const size_t length = path->size();
    for (size_t i = 0; i < value.size(); ++i) {
      *path += "[" + std::to_string(i) + "]";
      SDCB_RETURN_IF_ERROR(Check(value[i], *rule.each, path));
      path->resize(length);
    }
  } else if (rule.type == JsonType::kObject && rule.each != nullptr) {
    for (const auto& [key, member] : value.items()) {
      SDCB_RETURN_IF_ERROR(CheckMember(member, key, *rule.each, path));
    }
  } else if (rule.type == JsonType::kObject && rule.properties != nullptr) {
    for (size_t i = 0; i < rule.property_count; ++i) {
      const Property& property = rule.properties[i];
      const auto member = value.find(property.name);
      if (member == value.end()) continue;
      SDCB_RETURN_IF_ERROR(
          CheckMember(*member, property.name, property.rule, path));
    }
    const auto extensions = value.find("extensions");
    if (extensions != value.end()) {
      SDCB_RETURN_IF_ERROR(
          CheckMember(*extensions, "extensions", kExtensions, path));
    }
  }
  return Status::Ok();
}

}  // namespace

Status CheckGltfSchemaTypes(const nlohmann::json& root) {
  std::string path;
  return Check(root, kGltfRule, &path);
}

}  // namespace sdcb
