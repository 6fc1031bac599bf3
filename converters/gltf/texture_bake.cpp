#include "sdcb/converters/gltf/texture_bake.h"

#include <stb_image.h>
#include <stb_image_write.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <nlohmann/json.hpp>

#include "sdcb/core/sphere/sphere_triangle_locator.h"

namespace sdcb {
namespace {

using Json = nlohmann::json;

constexpr int kClampToEdge = 33071;
constexpr int kMirroredRepeat = 33648;

// Texel index `i` of a side of `n` texels under wrap `mode`.
int Wrap(int i, int n, int mode) {
  if (mode == kClampToEdge) return std::clamp(i, 0, n - 1);
  if (mode == kMirroredRepeat) {
    const int period = 2 * n;
    int m = i % period;
    if (m < 0) m += period;
    return m < n ? m : period - 1 - m;
  }
  int m = i % n;
  return m < 0 ? m + n : m;
}

// The encoded bytes of image `index` of `doc`.
StatusOr<std::string_view> ImageBytes(const GltfDocument& document,
                                      const Json& doc, size_t index) {
  const Json& image = doc.at("images").at(index);
  if (image.contains("bufferView")) {
    const Json& view =
        doc.at("bufferViews").at(image["bufferView"].get<size_t>());
    const size_t buffer = view.at("buffer").get<size_t>();
    const size_t offset = view.value("byteOffset", size_t{0});
    const size_t length = view.at("byteLength").get<size_t>();
    if (buffer >= document.buffers.size() ||
        offset + length > document.buffers[buffer].size()) {
      return InvalidInputError("image " + std::to_string(index) +
                               ": its buffer view reads past its buffer");
    }
    return std::string_view(document.buffers[buffer]).substr(offset, length);
  }
  if (index >= document.images.size() || document.images[index].empty()) {
    return UnsupportedError("image " + std::to_string(index) +
                            ": its file was not read");
  }
  return std::string_view(document.images[index]);
}

StatusOr<GltfTexture> LoadTexture(const GltfDocument& document, int material) {
  GltfTexture out;
  if (material < 0) return out;
  const Json doc = Json::parse(document.json);
  const Json& m = doc.at("materials").at(material);
  if (!m.contains("pbrMetallicRoughness") ||
      !m["pbrMetallicRoughness"].contains("baseColorTexture")) {
    return out;
  }
  const Json& info = m["pbrMetallicRoughness"]["baseColorTexture"];
  int tex_coord = info.value("texCoord", 0);
  if (info.contains("extensions") &&
      info["extensions"].contains("KHR_texture_transform")) {
    const Json& t = info["extensions"]["KHR_texture_transform"];
    tex_coord = t.value("texCoord", tex_coord);
    const std::array<double, 2> offset =
        t.value("offset", std::array<double, 2>{0, 0});
    const std::array<double, 2> scale =
        t.value("scale", std::array<double, 2>{1, 1});
    const double rotation = t.value("rotation", 0.0);
    const double c = std::cos(rotation), s = std::sin(rotation);
    out.transform << c * scale[0], s * scale[1], offset[0], -s * scale[0],
        c * scale[1], offset[1];
  }
  if (tex_coord != 0) return out;
  const Json& texture = doc.at("textures").at(info.at("index").get<size_t>());
  if (!texture.contains("source")) return out;
  if (texture.contains("sampler")) {
    const Json& sampler =
        doc.at("samplers").at(texture["sampler"].get<size_t>());
    out.wrap_s = sampler.value("wrapS", out.wrap_s);
    out.wrap_t = sampler.value("wrapT", out.wrap_t);
  }
  const size_t source = texture["source"].get<size_t>();
  SDCB_ASSIGN_OR_RETURN(const std::string_view bytes,
                        ImageBytes(document, doc, source));
  int w = 0, h = 0, channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(
      reinterpret_cast<const stbi_uc*>(bytes.data()),
      static_cast<int>(bytes.size()), &w, &h, &channels, 4);
  if (pixels == nullptr) {
    return CorruptFileError("image " + std::to_string(source) +
                            " does not decode (" + stbi_failure_reason() + ")");
  }
  std::array<float, 256> linear;
  for (int i = 0; i < 256; ++i) linear[i] = SrgbToLinear(i / 255.0);
  out.width = w;
  out.height = h;
  out.texels.resize(static_cast<size_t>(w) * h);
  for (size_t i = 0; i < out.texels.size(); ++i) {
    const stbi_uc* p = pixels + 4 * i;
    out.texels[i] = {linear[p[0]], linear[p[1]], linear[p[2]], p[3] / 255.0f};
  }
  stbi_image_free(pixels);
  return out;
}

// The tile side that matches the input's texel density (BakeCubeAtlas).
int TileSide(const std::vector<TextureBakePart>& parts,
             const GltfTexture& texture, const TextureBakeOptions& options,
             double extent) {
  // (texels per steradian, texels) per triangle; the median by texels.
  std::vector<std::pair<double, double>> density;
  double faces = 0, sphere_area = 0;
  for (const TextureBakePart& p : parts) {
    faces += p.faces.rows();
    for (Eigen::Index f = 0; f < p.faces.rows(); ++f) {
      const Eigen::Vector3d a = p.sphere_points.row(p.faces(f, 0));
      const Eigen::Vector3d b = p.sphere_points.row(p.faces(f, 1));
      const Eigen::Vector3d c = p.sphere_points.row(p.faces(f, 2));
      const double area = 0.5 * (b - a).cross(c - a).norm();
      sphere_area += area;
      if (texture.width == 0 || p.texcoords.rows() == 0 || area <= 0) continue;
      const Eigen::Vector2d u0 = p.texcoords.row(3 * f);
      const Eigen::Vector2d e1 = p.texcoords.row(3 * f + 1).transpose() - u0;
      const Eigen::Vector2d e2 = p.texcoords.row(3 * f + 2).transpose() - u0;
      const double texels = 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x()) *
                            texture.width * texture.height;
      if (texels > 0) density.emplace_back(texels / area, texels);
    }
  }
  double per_steradian = 16.0 * faces / std::max(sphere_area, 1e-12);
  if (!density.empty()) {
    std::sort(density.begin(), density.end());
    double total = 0;
    for (const auto& d : density) total += d.second;
    double sum = 0;
    for (const auto& d : density) {
      sum += d.second;
      if (sum >= 0.5 * total) {
        per_steradian = d.first;
        break;
      }
    }
  }
  // At a face's centre a tile of side T covers (2 e / T)^2 steradians per
  // texel.
  const int parts_n = static_cast<int>(parts.size());
  const int largest =
      std::min(options.max_side / 3, options.max_side / (2 * parts_n));
  int tile = static_cast<int>(2 * extent * std::sqrt(per_steradian));
  tile = std::clamp(tile, std::min(options.min_tile, largest), largest);
  return std::max(4, tile / 4 * 4);
}

// Fills every texel of `held` == 0 from its nearest held texel of the same
// tile (breadth first, 4-neighbours, in scan order); a tile without any
// takes `fallback`.
void Dilate(const CubeAtlasLayout& layout, std::vector<char>* held,
            std::vector<Eigen::Vector4f>* color,
            const Eigen::Vector4f& fallback) {
  const int w = layout.width(), t = layout.tile;
  for (int ty = 0; ty < layout.height() / t; ++ty) {
    for (int tx = 0; tx < 3; ++tx) {
      std::deque<int> queue;
      for (int y = ty * t; y < (ty + 1) * t; ++y) {
        for (int x = tx * t; x < (tx + 1) * t; ++x) {
          if ((*held)[y * w + x]) queue.push_back(y * w + x);
        }
      }
      if (queue.empty()) {
        for (int y = ty * t; y < (ty + 1) * t; ++y) {
          for (int x = tx * t; x < (tx + 1) * t; ++x) {
            (*color)[y * w + x] = fallback;
            (*held)[y * w + x] = 1;
          }
        }
        continue;
      }
      while (!queue.empty()) {
        const int i = queue.front();
        queue.pop_front();
        const int x = i % w, y = i / w;
        const int next[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (const auto& n : next) {
          if (n[0] < tx * t || n[0] >= (tx + 1) * t || n[1] < ty * t ||
              n[1] >= (ty + 1) * t) {
            continue;
          }
          const int j = n[1] * w + n[0];
          if ((*held)[j]) continue;
          (*held)[j] = 1;
          (*color)[j] = (*color)[i];
          queue.push_back(j);
        }
      }
    }
  }
}

void AppendBytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             size);
}

}  // namespace

double SrgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double LinearToSrgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}

StatusOr<GltfTexture> LoadBaseColorTexture(const GltfDocument& document,
                                           int material) {
  try {
    return LoadTexture(document, material);
  } catch (const nlohmann::json::exception& e) {
    return InvalidInputError(std::string("the glTF document: ") + e.what());
  }
}

Eigen::Vector4d SampleTexture(const GltfTexture& texture,
                              const Eigen::Vector2d& uv) {
  const Eigen::Vector2d at = texture.transform * uv.homogeneous();
  const double x = at[0] * texture.width - 0.5;
  const double y = at[1] * texture.height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double wx = x - fx, wy = y - fy;
  // Far outside [0, 1] the wrap repeats; keep the indices in int range.
  const int x0 = static_cast<int>(std::clamp(fx, -1e8, 1e8));
  const int y0 = static_cast<int>(std::clamp(fy, -1e8, 1e8));
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  for (int dy = 0; dy < 2; ++dy) {
    const int row = Wrap(y0 + dy, texture.height, texture.wrap_t);
    for (int dx = 0; dx < 2; ++dx) {
      const int col = Wrap(x0 + dx, texture.width, texture.wrap_s);
      const double weight = (dx ? wx : 1 - wx) * (dy ? wy : 1 - wy);
      sum += weight *
             texture.texels[static_cast<size_t>(row) * texture.width + col]
                 .cast<double>();
    }
  }
  return sum;
}

StatusOr<BakedAtlas> BakeCubeAtlas(const std::vector<TextureBakePart>& parts,
                                   const GltfTexture& texture,
                                   const TextureBakeOptions& options) {
  if (parts.empty()) return InvalidArgumentError("no parts to bake");
  for (const TextureBakePart& p : parts) {
    const Eigen::Index corners = 3 * p.faces.rows();
    if ((p.texcoords.rows() != 0 && p.texcoords.rows() != corners) ||
        (p.colors.rows() != 0 && p.colors.rows() != corners)) {
      return InvalidArgumentError(
          "per-corner texture coordinates or colours do not match the "
          "faces");
    }
  }
  BakedAtlas out;
  CubeAtlasLayout& layout = out.layout;
  layout.parts = static_cast<int>(parts.size());
  layout.tile = TileSide(parts, texture, options, layout.extent);
  const int w = layout.width(), h = layout.height();
  std::vector<Eigen::Vector4f> color(static_cast<size_t>(w) * h);
  std::vector<char> held(color.size(), 0);
  std::vector<SphereTriangleLocator> locators;
  for (const TextureBakePart& p : parts) {
    locators.emplace_back(p.sphere_points, p.faces);
  }
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const CubeAtlasTexel texel = CubeAtlasTexelAt(layout, x, y);
      const TextureBakePart& p = parts[texel.part];
      const SphereTriangleLocator::Location at =
          locators[texel.part].Locate(texel.direction);
      if (at.face < 0) continue;
      Eigen::Vector4d c = Eigen::Vector4d::Ones();
      if (texture.width > 0 && p.texcoords.rows() > 0) {
        Eigen::Vector2d uv = Eigen::Vector2d::Zero();
        for (int k = 0; k < 3; ++k) {
          uv +=
              at.barycentric[k] * p.texcoords.row(3 * at.face + k).transpose();
        }
        c = SampleTexture(texture, uv);
      }
      if (p.colors.rows() > 0) {
        Eigen::Vector4d v = Eigen::Vector4d::Zero();
        for (int k = 0; k < 3; ++k) {
          v += at.barycentric[k] * p.colors.row(3 * at.face + k).transpose();
        }
        c = c.cwiseProduct(v);
      }
      color[static_cast<size_t>(y) * w + x] = c.cast<float>();
      held[static_cast<size_t>(y) * w + x] = 1;
    }
  });
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();
  size_t count = 0;
  for (size_t i = 0; i < color.size(); ++i) {
    if (!held[i]) continue;
    mean += color[i].cast<double>();
    ++count;
  }
  out.uncovered_fraction = 1.0 - static_cast<double>(count) / color.size();
  mean = count > 0 ? Eigen::Vector4d(mean / count) : Eigen::Vector4d::Ones();
  Dilate(layout, &held, &color, mean.cast<float>());

  bool opaque = true;
  for (const Eigen::Vector4f& c : color)
    opaque = opaque && c[3] >= 1.0f - 0.5f / 255;
  const int channels = opaque ? 3 : 4;
  std::vector<uint8_t> pixels(color.size() * channels);
  tbb::parallel_for(0, h, [&](int y) {
    for (size_t i = static_cast<size_t>(y) * w;
         i < static_cast<size_t>(y + 1) * w; ++i) {
      for (int k = 0; k < channels; ++k) {
        const double v = k < 3 ? LinearToSrgb(color[i][k])
                               : std::clamp<double>(color[i][k], 0.0, 1.0);
        pixels[i * channels + k] = static_cast<uint8_t>(std::lround(255 * v));
      }
    }
  });
  if (stbi_write_png_to_func(&AppendBytes, &out.png, w, h, channels,
                             pixels.data(), w * channels) == 0) {
    return InternalError("the atlas image could not be encoded as PNG");
  }
  return out;
}

}  // namespace sdcb
