// The mesh a fit works on and what every round reads of it: the input (or
// its split, FitOptions::map_vertices) in the normalized frame, its sphere
// parameters u with their k-d tree, its vertex normals and area, and its
// AABB tree for the measurements.
#ifndef SDCB_CORE_FIT_FIT_MESH_H_
#define SDCB_CORE_FIT_FIT_MESH_H_

#include <Eigen/Core>
#include <memory>
#include <optional>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/sphere/point_kd_tree.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

struct FitMesh {
  TriangleMesh mesh;  // in the normalized frame
  // The input's vertices: the first rows of `mesh` (FitOptions::map_vertices).
  Eigen::Index input_vertices = 0;
  Eigen::MatrixX3d u;  // the vertices' sphere parameters
  std::unique_ptr<PointKdTree> parameter_tree;  // of u
  // VertexAreaRatio(mesh, u) once a round has needed it (reset with u).
  std::optional<StatusOr<Eigen::VectorXd>> area_ratio;
  // The mesh's AABB tree, built once for every round's measurement.
  std::optional<MeshDistance> mesh_distance;
  double mesh_area = 0;
  // Per vertex: the unit normal of its triangles' area-weighted sum (the
  // rounds' estimate of the dense measurement).
  Eigen::MatrixX3d vertex_normal;

  // Makes `parameters` the vertices' sphere parameters u.
  void UseParameters(Eigen::MatrixX3d parameters);
  // VertexAreaRatio(mesh, u), computed on the first call after u is set.
  const StatusOr<Eigen::VectorXd>& AreaRatio();
};

// `map_mesh` (whose first `input_vertices` vertices are the input's) in the
// normalized frame of `transform`, with its area and vertex normals; u and
// the trees are the caller's.
FitMesh NormalizedFitMesh(const TriangleMesh& map_mesh,
                          const NormalizingTransform& transform,
                          Eigen::Index input_vertices);

// The mesh FitOptions::map_vertices asks the map and the fit to use: `mesh`
// split (SplitToEdgeLength) for about `map_vertices` vertices, or nullopt
// when that leaves it as it is (or would make it too large).
std::optional<TriangleMesh> SplitForMap(const TriangleMesh& mesh,
                                        int map_vertices);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FIT_MESH_H_
