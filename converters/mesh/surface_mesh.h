// A triangle mesh with per-vertex normals and optional colors: what the
// exporters (mesh_export.h, gltf_export.h) write.
#ifndef SDCB_CONVERTERS_MESH_SURFACE_MESH_H_
#define SDCB_CONVERTERS_MESH_SURFACE_MESH_H_

#include <Eigen/Core>
#include <cstdint>

namespace sdcb {

struct SurfaceMesh {
  Eigen::MatrixX3d positions;  // #V by 3
  Eigen::MatrixX3d normals;    // #V by 3 unit vectors, or 0 rows for none
  Eigen::MatrixX3i faces;      // #F by 3, counter-clockwise from outside
  // #V by 3 RGB colors (0..255), or 0 rows for none.
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3> colors;
  // #V by 2 texture coordinates (glTF's: u right, v down), or 0 rows for
  // none; only the glTF writer stores them (TEXCOORD_0).
  Eigen::MatrixX2d texcoords;
  // #V by 3 unit vectors: each vertex's point on the sphere of the surface
  // it samples (the spline's domain), or 0 rows when not known. Not
  // written: what texture coordinates of a sphere atlas are made from
  // (converters/gltf/gltf_asset.h).
  Eigen::MatrixX3d directions;
};

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_MESH_SURFACE_MESH_H_
