// A texture atlas of the unit sphere (a cube map): each part gets six square
// tiles, one per cube face, each covering the gnomonic coordinates
// [-e, e]^2 of its face with e = CubeAtlasLayout::extent > 1, so that a
// triangle that straddles a cube edge, which takes one face for all its
// corners, still samples valid texels; the tiles of several parts (the
// parts of one glTF primitive) are stacked in one image. Baking fills the
// texels (converters/gltf/texture_bake.h); a tessellation of the sphere gets
// its texture coordinates from CubeAtlasTexcoords.
//
// Cube face f = 2 k + (x_k < 0) of a direction x, k the axis of its largest
// |x_k|; its gnomonic coordinates on face f (axis k) are
// (a, b) = (x_{k+1}, x_{k+2}) / |x_k| (indices mod 3). In the image, tile
// (part p, face f) is column f mod 3 and row 2 p + f / 3 of tiles; a runs
// right and b down inside it. Texture coordinates are glTF's: u right, v
// down, (0, 0) the top-left corner of the image, texel (x, y) (column x,
// row y) centred at ((x + 0.5) / width, (y + 0.5) / height).
#ifndef SDCB_CORE_SPHERE_CUBE_ATLAS_H_
#define SDCB_CORE_SPHERE_CUBE_ATLAS_H_

#include <Eigen/Core>
#include <vector>

namespace sdcb {

struct CubeAtlasLayout {
  int parts = 1;         // blocks of six tiles, stacked downward
  int tile = 256;        // texels per tile side
  double extent = 1.25;  // e: a tile covers gnomonic [-e, e]^2
  int width() const { return 3 * tile; }
  int height() const { return 2 * tile * parts; }
};

// The cube face of `d` (any nonzero vector): 2 k + (d_k < 0), k the first
// axis of largest |d_k|.
int CubeFaceOf(const Eigen::Vector3d& d);

// The gnomonic coordinates of `d` on `face`. `d` must lie in the open
// hemisphere of the face's axis (else the result is not finite or is the
// antipode's).
Eigen::Vector2d GnomonicOnFace(const Eigen::Vector3d& d, int face);

// The unit vector at gnomonic `ab` of `face` (any finite ab).
Eigen::Vector3d DirectionOnFace(int face, const Eigen::Vector2d& ab);

// Texture coordinates of gnomonic `ab` of `face` in the tile of `part`.
Eigen::Vector2d CubeAtlasUv(const CubeAtlasLayout& layout, int part, int face,
                            const Eigen::Vector2d& ab);

// What texel (x, y) of the image shows: the part and face of its tile and
// the unit vector at its centre.
struct CubeAtlasTexel {
  int part = 0;
  int face = 0;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
};
CubeAtlasTexel CubeAtlasTexelAt(const CubeAtlasLayout& layout, int x, int y);

// A tessellation of the sphere with atlas texture coordinates: each
// triangle takes the cube face (among those of its corners, with every
// corner in the face's open hemisphere) that keeps the largest gnomonic
// coordinate of its corners smallest (ties: the lower face), and a vertex
// is split once per face its triangles take.
struct CubeAtlasMesh {
  Eigen::MatrixX2d texcoords;  // #V' by 2
  std::vector<int> vertex;     // per output vertex, its input row
  Eigen::MatrixX3i faces;      // #F by 3 output vertices, input order
  // Output vertices whose coordinates on their face are beyond the extent
  // (clamped to the tile's edge, so their triangles sample the wrong
  // texels). None for a tessellation whose triangles span less than about
  // five degrees (near a cube corner, coordinates grow by about three per
  // radian).
  int corners_beyond_extent = 0;
};

// `directions`: #V by 3 unit vectors (a tessellation's vertices on the
// sphere), `faces`: #F by 3 rows into them; `part` < layout.parts.
CubeAtlasMesh CubeAtlasTexcoords(const CubeAtlasLayout& layout, int part,
                                 const Eigen::MatrixX3d& directions,
                                 const Eigen::MatrixX3i& faces);

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_CUBE_ATLAS_H_
