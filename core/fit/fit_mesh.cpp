#include "sdcb/core/fit/fit_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <utility>

#include "sdcb/core/param/parameterization_distortion.h"

namespace sdcb {

void FitMesh::UseParameters(Eigen::MatrixX3d parameters) {
  u = std::move(parameters);
  parameter_tree = std::make_unique<PointKdTree>(u);
  area_ratio.reset();
}

const StatusOr<Eigen::VectorXd>& FitMesh::AreaRatio() {
  if (!area_ratio) area_ratio = VertexAreaRatio(mesh, u);
  return *area_ratio;
}

FitMesh NormalizedFitMesh(const TriangleMesh& map_mesh,
                          const NormalizingTransform& transform,
                          Eigen::Index input_vertices) {
  FitMesh fit;
  fit.mesh.faces = map_mesh.faces;
  fit.mesh.vertices = transform.ToNormalized(map_mesh.vertices);
  fit.input_vertices = input_vertices;
  for (Eigen::Index f = 0; f < fit.mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = fit.mesh.vertices.row(fit.mesh.faces(f, 0));
    const Eigen::Vector3d b = fit.mesh.vertices.row(fit.mesh.faces(f, 1));
    const Eigen::Vector3d c = fit.mesh.vertices.row(fit.mesh.faces(f, 2));
    fit.mesh_area += 0.5 * (b - a).cross(c - a).norm();
  }
  fit.vertex_normal = VertexNormals(fit.mesh);
  return fit;
}

std::optional<TriangleMesh> SplitForMap(const TriangleMesh& mesh,
                                        int map_vertices) {
  if (mesh.num_vertices() >= map_vertices) return std::nullopt;
  std::optional<TriangleMesh> split = SplitToEdgeLength(
      mesh, SplitEdgeLengthFor(VertexAreas(mesh).sum(), map_vertices),
      std::max<int64_t>(mesh.num_vertices(), 4 * int64_t{map_vertices}));
  if (!split || split->num_vertices() == mesh.num_vertices()) {
    return std::nullopt;
  }
  return split;
}

}  // namespace sdcb
