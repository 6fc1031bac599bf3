// The mesh a fit works on and what every round reads of it: the input (or
// its split, FitOptions::map_vertices) in the normalized frame, its sphere
// parameters u with their k-d tree, its vertex normals and area, and its
// AABB tree for the measurements.
#ifndef SDCB_CORE_FIT_FIT_MESH_H_
#define SDCB_CORE_FIT_FIT_MESH_H_

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/hole_filling.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/sphere/point_kd_tree.h"
#include "sdcb/core/sphere/trim_region.h"
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
  // The AABB tree of the surface the errors are measured against, built
  // once for every round's measurement: of measured(), or of the input's
  // own triangles when `mesh` is its split (the same surface).
  std::optional<MeshDistance> mesh_distance;
  double mesh_area = 0;
  // Per vertex: the unit normal of its triangles' area-weighted sum (the
  // rounds' estimate of the dense measurement).
  Eigen::MatrixX3d vertex_normal;

  // An open part (core/mesh/hole_filling.h): `mesh` is the part with its
  // holes filled, its first input_faces faces the part's own. The errors
  // are measured against `part` (those faces, and the input's vertices) in
  // the region the trims keep; the fill's faces weigh kFillWeight in the
  // data term (face_weights), so that they only keep the spline smooth.
  // A closed part: input_faces = all, no loops, region empty.
  Eigen::Index input_faces = 0;
  std::vector<std::vector<int>> boundary_loops;  // rows of `mesh`
  std::optional<TriangleMesh> part;              // open parts: the part alone
  Eigen::VectorXd face_weights;   // open parts: per face of `mesh`
  std::vector<char> on_boundary;  // open parts: per vertex of `mesh`
  TrimRegion region;              // the loops' images under u

  bool trimmed() const { return !boundary_loops.empty(); }
  // The mesh the errors are measured against: `part` for an open part,
  // else `mesh`.
  const TriangleMesh& measured() const { return part ? *part : mesh; }
  // The loops at their vertices' sphere parameters (kept region on the
  // left).
  std::vector<TrimLoop> Trims() const;

  // Makes `parameters` the vertices' sphere parameters u (the region is
  // then empty until UpdateRegion).
  void UseParameters(Eigen::MatrixX3d parameters);
  // Sets `region` to the trims' at u; a failure means the map folded a
  // boundary loop.
  Status UpdateRegion();
  // VertexAreaRatio(mesh, u), computed on the first call after u is set.
  const StatusOr<Eigen::VectorXd>& AreaRatio();
};

// `map_mesh` (whose first `input_vertices` vertices are the input's) in the
// normalized frame of `transform`, with its area and vertex normals; u and
// the trees are the caller's.
FitMesh NormalizedFitMesh(const TriangleMesh& map_mesh,
                          const NormalizingTransform& transform,
                          Eigen::Index input_vertices);

// The data term's weight of a fill triangle's area, relative to the part's
// own: enough to hold the spline near the fair fill (no wild bulges where
// nothing is measured), too little to bend it off the part along the
// boundary.
constexpr double kFillWeight = 0.05;

// The data term's weight of an open part's boundary vertex, relative to its
// area (core/fit/round_problem.cpp).
constexpr double kBoundaryWeight = 30.0;

// The open part `filled` (core/mesh/hole_filling.h) in the normalized frame
// of `transform`: NormalizedFitMesh of its closed mesh, with the part, its
// loops and the fill's face weights set.
FitMesh NormalizedOpenFitMesh(const FilledMesh& filled,
                              const NormalizingTransform& transform);

// The mesh FitOptions::map_vertices asks the map and the fit to use: `mesh`
// split (SplitToEdgeLength) for about `map_vertices` vertices, or nullopt
// when that leaves it as it is (or would make it too large).
std::optional<TriangleMesh> SplitForMap(const TriangleMesh& mesh,
                                        int map_vertices);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FIT_MESH_H_
