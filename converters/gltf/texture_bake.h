// Base colours of glTF primitives re-baked onto the sphere: a fitted part's
// surface is parameterized by the unit sphere, so its texture becomes a
// cube-map atlas of that sphere (core/sphere/cube_atlas.h) which every
// tessellation of the part samples at its vertices' sphere points. Per
// atlas texel: its direction, the input triangle whose image on the sphere
// holds it (the fit's map of the part's vertices), that triangle's
// TEXCOORD_0 and COLOR_0 interpolated there, and the base colour texture
// sampled at the texture coordinate (the glTF sampler's wrap modes,
// bilinear in linear light) times the colour. See docs/EXPORT.md ("glTF
// assets written back").
#ifndef SDCB_CONVERTERS_GLTF_TEXTURE_BAKE_H_
#define SDCB_CONVERTERS_GLTF_TEXTURE_BAKE_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sdcb/converters/gltf/gltf_import.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/sphere/cube_atlas.h"

namespace sdcb {

// A decoded image with the sampler that reads it.
struct GltfTexture {
  int width = 0, height = 0;  // 0: no texture
  // width * height RGBA texels, rows top to bottom (v down), in linear
  // light: colour channels decoded from sRGB, alpha as stored, all 0..1.
  std::vector<Eigen::Vector4f> texels;
  // glTF sampler wrap modes: 33071 clamp to edge, 33648 mirrored repeat,
  // 10497 repeat (the default).
  int wrap_s = 10497, wrap_t = 10497;
  // KHR_texture_transform of the texture reference: a texture coordinate uv
  // is read at transform * (u, v, 1) (translation * rotation * scale, the
  // extension's order); the identity without it.
  Eigen::Matrix<double, 2, 3> transform =
      Eigen::Matrix<double, 2, 3>::Identity();
};

// The base colour texture of material `material` of `document` (the image
// of pbrMetallicRoughness.baseColorTexture, decoded from PNG, JPEG, TGA or
// BMP with stb_image, and its sampler), or a GltfTexture of width 0 when the
// material has none, samples a texture coordinate other than TEXCOORD_0
// (KHR_texture_transform's texCoord included), or `material` is -1; a
// KHR_texture_transform on the reference becomes GltfTexture::transform.
// kCorruptFile for
// an image that does not decode; kInvalidInput for an index out of range;
// kUnsupported for an image given by a URI whose file was not read.
StatusOr<GltfTexture> LoadBaseColorTexture(const GltfDocument& document,
                                           int material);

// `texture` (width > 0) at texture coordinate `uv` (u right, v down), taken
// through GltfTexture::transform: bilinear over the four nearest texel
// centres, wrapped by the sampler's modes. Linear RGBA.
Eigen::Vector4d SampleTexture(const GltfTexture& texture,
                              const Eigen::Vector2d& uv);

// sRGB transfer functions (IEC 61966-2-1) on 0..1.
double SrgbToLinear(double c);
double LinearToSrgb(double c);

// One part to bake: its input triangles and where the fit put their
// corners on the sphere.
struct TextureBakePart {
  Eigen::MatrixX3d sphere_points;  // #V by 3 unit vectors
  Eigen::MatrixX3i faces;          // #F by 3 rows into sphere_points
  // Per corner (row 3 f + k is corner k of face f), or 0 rows for none:
  // TEXCOORD_0 as stored, COLOR_0 as RGBA in linear light (0..1).
  Eigen::MatrixX2d texcoords;
  Eigen::MatrixX4d colors;
};

struct TextureBakeOptions {
  // Texels per tile side, before rounding down to a multiple of 4: from the
  // input's texel density (below), at least min_tile, and the image at most
  // max_side on either side.
  int min_tile = 128;
  int max_side = 2048;
};

struct BakedAtlas {
  CubeAtlasLayout layout;  // layout.parts == the number of parts
  std::string png;  // the image (RGB, or RGBA if any texel is not opaque)
  // Atlas texels no input triangle holds (filled from their nearest held
  // texel in the tile), as a fraction of all.
  double uncovered_fraction = 0.0;
};

// Bakes the atlas of `parts` (tile block p for parts[p]): the texture
// (width 0: none, then the colours alone) times the colours (none: white).
// The tile side gives the atlas, at the centre of a cube face, the median
// texels per steradian of the input (the input texture's texels per unit of
// sphere area over the parts' triangles, the median texel's; without a
// texture, 16 texels per input triangle). Deterministic bytes; parallel
// over rows (TBB). kInvalidArgument for no parts, or per-corner rows that
// do not match the faces.
StatusOr<BakedAtlas> BakeCubeAtlas(const std::vector<TextureBakePart>& parts,
                                   const GltfTexture& texture,
                                   const TextureBakeOptions& options = {});

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_TEXTURE_BAKE_H_
