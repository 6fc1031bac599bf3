// The plain triangle mesh that flows between the layers: vertex positions and
// triangles as index triples, in the order the input file gave them.
#ifndef SDCB_CORE_MESH_TRIANGLE_MESH_H_
#define SDCB_CORE_MESH_TRIANGLE_MESH_H_

#include <Eigen/Core>

#include "sdcb/core/common/status.h"

namespace sdcb {

struct TriangleMesh {
  // #V by 3 vertex positions, in the input's coordinates and order.
  Eigen::MatrixX3d vertices;
  // #F by 3 vertex indices (0-based) into `vertices`, counter-clockwise seen
  // from outside for a consistently oriented closed mesh.
  Eigen::MatrixX3i faces;

  int num_vertices() const { return static_cast<int>(vertices.rows()); }
  int num_faces() const { return static_cast<int>(faces.rows()); }
};

// kInvalidInput naming the first face that refers to a vertex out of range.
Status CheckFaceIndices(const TriangleMesh& mesh);

// Per vertex: a third of the area of each incident triangle (summed in face
// order).
Eigen::VectorXd VertexAreas(const TriangleMesh& mesh);

// Per vertex: the unit vector of the sum of its triangles' area-weighted
// normals (right-hand rule over the corner order); zero where that sum is.
Eigen::MatrixX3d VertexNormals(const TriangleMesh& mesh);

// `mesh` with every triangle split 1-to-4 at its edges' midpoints, `levels`
// times: the same surface, point for point. Rows 0..#V-1 are the input's
// vertices; each new vertex follows in the order its edge is first met in
// face order, and an edge shared by two faces gets one midpoint.
TriangleMesh MidpointSubdivided(const TriangleMesh& mesh, int levels);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_TRIANGLE_MESH_H_
