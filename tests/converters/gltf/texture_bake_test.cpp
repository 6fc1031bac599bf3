// Tests converters/gltf/texture_bake.*: the sampler's wrap modes on a 2 by 2
// image against their definitions, and atlases of a sphere whose texture
// coordinates and colours are closed-form functions of position, each
// atlas texel compared with the closed form at its direction.
#include "sdcb/converters/gltf/texture_bake.h"

#include <gtest/gtest.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <Eigen/Geometry>
#include <cmath>

#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {
namespace {

void Append(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             size);
}

// A document whose material 0 samples `png` (given by a URI that was read)
// with `wrap` on both axes.
GltfDocument DocumentWithImage(const std::string& png, int wrap) {
  GltfDocument d;
  d.json = R"({"materials":[{"pbrMetallicRoughness":{"baseColorTexture":)"
           R"({"index":0}}}],"textures":[{"source":0,"sampler":0}],)"
           R"("samplers":[{"wrapS":)" +
           std::to_string(wrap) + R"(,"wrapT":)" + std::to_string(wrap) +
           R"(}],"images":[{"uri":"t.png"}]})";
  d.images = {png};
  return d;
}

std::string Png(int w, int h, const std::vector<uint8_t>& rgb) {
  std::string out;
  stbi_write_png_to_func(&Append, &out, w, h, 3, rgb.data(), 3 * w);
  return out;
}

// The atlas's texels, sRGB bytes, RGB.
std::vector<uint8_t> Decode(const BakedAtlas& atlas) {
  int w = 0, h = 0, n = 0;
  stbi_uc* p =
      stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(atlas.png.data()),
                            static_cast<int>(atlas.png.size()), &w, &h, &n, 3);
  EXPECT_EQ(w, atlas.layout.width());
  EXPECT_EQ(h, atlas.layout.height());
  std::vector<uint8_t> out(p, p + 3 * w * h);
  stbi_image_free(p);
  return out;
}

TEST(TextureBakeTest, SamplerWrapModesFollowTheirDefinitions) {
  // Texels (sRGB): 0 and 255 red in the top row, green 0 / 255 below.
  const std::string png =
      Png(2, 2, {0, 0, 0, 255, 0, 0, 0, 255, 0, 255, 255, 0});
  for (const int wrap : {33071, 33648, 10497}) {
    const StatusOr<GltfTexture> t =
        LoadBaseColorTexture(DocumentWithImage(png, wrap), 0);
    ASSERT_TRUE(t.ok()) << t.status().message();
    ASSERT_EQ(t->width, 2);
    // At a texel centre: that texel.
    EXPECT_NEAR(SampleTexture(*t, {0.75, 0.25})[0], 1.0, 1e-6);
    EXPECT_NEAR(SampleTexture(*t, {0.25, 0.25})[0], 0.0, 1e-6);
    // At u = 0 (half a texel left of texel 0's centre): clamp reads texel
    // 0 alone; mirrored repeat reflects onto texel 0 too; repeat wraps to
    // texel 1 and averages.
    const double red = SampleTexture(*t, {0.0, 0.25})[0];
    EXPECT_NEAR(red, wrap == 10497 ? 0.5 : 0.0, 1e-6) << wrap;
  }
  GltfDocument none = DocumentWithImage(png, 10497);
  EXPECT_EQ(LoadBaseColorTexture(none, -1)->width, 0);
  none.images = {"not an image"};
  EXPECT_EQ(LoadBaseColorTexture(none, 0).status().code(),
            StatusCode::kCorruptFile);
}

// KHR_texture_transform on the base colour texture: a sample at uv reads
// the untransformed texture at translation * rotation * scale * (u, v, 1),
// the three matrices as the extension defines them; its texCoord 1 means
// no TEXCOORD_0 texture.
TEST(TextureBakeTest, TextureTransformFollowsTheExtensionsMatrices) {
  std::vector<uint8_t> rgb(3 * 8 * 8);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = (i * 37) % 251;
  const std::string png = Png(8, 8, rgb);
  const GltfDocument plain = DocumentWithImage(png, 10497);
  GltfDocument moved = plain;
  const std::string reference = R"("baseColorTexture":{"index":0})";
  const std::string transformed =
      R"("baseColorTexture":{"index":0,"extensions":{"KHR_texture_transform":)"
      R"({"offset":[0.25,-0.5],"rotation":0.7,"scale":[2,0.5]}}})";
  moved.json.replace(moved.json.find(reference), reference.size(), transformed);
  const StatusOr<GltfTexture> a = LoadBaseColorTexture(plain, 0);
  const StatusOr<GltfTexture> b = LoadBaseColorTexture(moved, 0);
  ASSERT_TRUE(a.ok() && b.ok());
  Eigen::Matrix3d translation, rotation, scale;
  translation << 1, 0, 0.25, 0, 1, -0.5, 0, 0, 1;
  rotation << std::cos(0.7), std::sin(0.7), 0, -std::sin(0.7), std::cos(0.7), 0,
      0, 0, 1;
  scale << 2, 0, 0, 0, 0.5, 0, 0, 0, 1;
  for (const Eigen::Vector2d& uv :
       {Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(0.63, 0.91),
        Eigen::Vector2d(-0.4, 1.3)}) {
    const Eigen::Vector3d at =
        translation * rotation * scale * uv.homogeneous();
    EXPECT_LT((SampleTexture(*b, uv) - SampleTexture(*a, at.head<2>()))
                  .cwiseAbs()
                  .maxCoeff(),
              1e-9);
  }
  GltfDocument other = moved;
  other.json.replace(other.json.find(R"("rotation")"), 10,
                     R"("texCoord":1,"rotation")");
  const StatusOr<GltfTexture> c = LoadBaseColorTexture(other, 0);
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_EQ(c->width, 0);
}

// The unit sphere as a part, its sphere points its own vertices.
TextureBakePart SpherePart() {
  const TriangleMesh sphere = MakeIcosphere(4);
  TextureBakePart part;
  part.sphere_points = sphere.vertices.rowwise().normalized();
  part.faces = sphere.faces;
  return part;
}

TEST(TextureBakeTest, TexturedSphereMatchesItsClosedForm) {
  // Image: red = column, green = row, as sRGB ramps; the sphere's texture
  // coordinates u = 0.5 + 0.45 x, v = 0.5 - 0.45 y (linear in position,
  // so exact on its flat triangles).
  const int n = 64;
  std::vector<uint8_t> rgb(3 * n * n);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      rgb[3 * (y * n + x)] = static_cast<uint8_t>(4 * x + 2);
      rgb[3 * (y * n + x) + 1] = static_cast<uint8_t>(4 * y + 2);
      rgb[3 * (y * n + x) + 2] = 128;
    }
  }
  const StatusOr<GltfTexture> texture =
      LoadBaseColorTexture(DocumentWithImage(Png(n, n, rgb), 33071), 0);
  ASSERT_TRUE(texture.ok());
  TextureBakePart part = SpherePart();
  part.texcoords.resize(3 * part.faces.rows(), 2);
  for (Eigen::Index f = 0; f < part.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = part.sphere_points.row(part.faces(f, k));
      part.texcoords.row(3 * f + k) << 0.5 + 0.45 * p.x(), 0.5 - 0.45 * p.y();
    }
  }
  const StatusOr<BakedAtlas> atlas = BakeCubeAtlas({part}, *texture);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  EXPECT_EQ(atlas->uncovered_fraction, 0.0);
  // 64^2 texels ask for less than the smallest tile.
  EXPECT_GE(atlas->layout.tile, 128);
  const std::vector<uint8_t> texels = Decode(*atlas);
  int worst = 0;
  for (int y = 0; y < atlas->layout.height(); y += 3) {
    for (int x = 0; x < atlas->layout.width(); x += 3) {
      const Eigen::Vector3d d = CubeAtlasTexelAt(atlas->layout, x, y).direction;
      // Closed form: the image's ramps at uv(d), 4 x + 2 at texel x's
      // centre, i.e. 256 u (clamped to the edge texels' centres).
      const double u = std::clamp(0.5 + 0.45 * d.x(), 0.5 / n, 1 - 0.5 / n);
      const double v = std::clamp(0.5 - 0.45 * d.y(), 0.5 / n, 1 - 0.5 / n);
      const double red = 256 * u, green = 256 * v;
      const uint8_t* t = &texels[3 * (y * atlas->layout.width() + x)];
      worst = std::max({worst, static_cast<int>(std::abs(t[0] - red)),
                        static_cast<int>(std::abs(t[1] - green)),
                        std::abs(t[2] - 128)});
    }
  }
  // Bilinear in linear light bends an sRGB ramp by at most ~2/255 between
  // texel centres; the flat triangles move uv by < 1e-3.
  EXPECT_LE(worst, 3);
}

TEST(TextureBakeTest, ColoursAloneMatchTheirClosedFormAndOpenPartsAreFilled) {
  TextureBakePart part = SpherePart();
  // COLOR_0 (linear) = ((x + 1) / 2, (y + 1) / 2, (z + 1) / 2, 1); only the
  // triangles above z = -0.3 (an open part).
  std::vector<int> kept;
  for (Eigen::Index f = 0; f < part.faces.rows(); ++f) {
    double z = 0;
    for (int k = 0; k < 3; ++k) z += part.sphere_points(part.faces(f, k), 2);
    if (z / 3 > -0.3) kept.push_back(static_cast<int>(f));
  }
  Eigen::MatrixX3i faces(kept.size(), 3);
  for (size_t i = 0; i < kept.size(); ++i)
    faces.row(i) = part.faces.row(kept[i]);
  part.faces = faces;
  part.colors.resize(3 * faces.rows(), 4);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = part.sphere_points.row(faces(f, k));
      part.colors.row(3 * f + k) << (p.x() + 1) / 2, (p.y() + 1) / 2,
          (p.z() + 1) / 2, 1;
    }
  }
  const StatusOr<BakedAtlas> atlas = BakeCubeAtlas({part, part}, GltfTexture());
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  EXPECT_EQ(atlas->layout.parts, 2);
  EXPECT_GT(atlas->uncovered_fraction, 0.1);
  const std::vector<uint8_t> texels = Decode(*atlas);
  int worst = 0;
  for (int y = 0; y < atlas->layout.height(); y += 2) {
    for (int x = 0; x < atlas->layout.width(); x += 2) {
      const CubeAtlasTexel texel = CubeAtlasTexelAt(atlas->layout, x, y);
      const Eigen::Vector3d d = texel.direction;
      const uint8_t* t = &texels[3 * (y * atlas->layout.width() + x)];
      if (d.z() < -0.5 && texel.face != 5) {
        // Filled from the nearest texel held in the tile: the rim's colour
        // (z below -0.1: little blue).
        EXPECT_LE(t[2], std::lround(255 * LinearToSrgb((1 - 0.1) / 2)));
        continue;
      }
      if (texel.face == 5) {
        // The -z tile holds no kept triangle: the mean colour of the held
        // texels, blue above the rim's.
        EXPECT_GT(t[2], std::lround(255 * LinearToSrgb((1 + 0.1) / 2)));
        continue;
      }
      if (d.z() < -0.25) continue;  // the rim's triangles
      for (int k = 0; k < 3; ++k) {
        const double want = 255 * LinearToSrgb((d[k] + 1) / 2);
        worst = std::max(worst,
                         static_cast<int>(std::lround(std::abs(t[k] - want))));
      }
    }
  }
  EXPECT_LE(worst, 2);
}

}  // namespace
}  // namespace sdcb
