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
  region = TrimRegion();
}

Status FitMesh::UpdateRegion() {
  if (!trimmed()) return Status::Ok();
  SDCB_ASSIGN_OR_RETURN(region, TrimRegion::Create(Trims()));
  return Status::Ok();
}

std::vector<TrimLoop> FitMesh::Trims() const {
  std::vector<TrimLoop> trims(boundary_loops.size());
  for (size_t l = 0; l < boundary_loops.size(); ++l) {
    const std::vector<int>& loop = boundary_loops[l];
    trims[l].points.resize(static_cast<Eigen::Index>(loop.size()), 3);
    for (size_t i = 0; i < loop.size(); ++i) {
      trims[l].points.row(static_cast<Eigen::Index>(i)) = u.row(loop[i]);
    }
  }
  return trims;
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
  fit.input_faces = fit.mesh.faces.rows();
  return fit;
}

FitMesh NormalizedOpenFitMesh(const FilledMesh& filled,
                              const NormalizingTransform& transform) {
  FitMesh fit =
      NormalizedFitMesh(filled.mesh, transform, filled.input_vertices);
  if (filled.boundary_loops.empty()) return fit;
  fit.input_faces = filled.input_faces;
  fit.boundary_loops = filled.boundary_loops;
  fit.part.emplace();
  fit.part->vertices = fit.mesh.vertices.topRows(filled.input_vertices);
  fit.part->faces = fit.mesh.faces.topRows(filled.input_faces);
  fit.on_boundary.assign(fit.mesh.vertices.rows(), 0);
  for (const std::vector<int>& loop : filled.boundary_loops) {
    for (const int v : loop) fit.on_boundary[v] = 1;
  }
  fit.face_weights = Eigen::VectorXd::Ones(fit.mesh.faces.rows());
  fit.face_weights.tail(fit.mesh.faces.rows() - filled.input_faces)
      .setConstant(kFillWeight);
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
