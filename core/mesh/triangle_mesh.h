// The plain triangle mesh that flows between the layers: vertex positions and
// triangles as index triples, in the order the input file gave them.
#ifndef SDCB_CORE_MESH_TRIANGLE_MESH_H_
#define SDCB_CORE_MESH_TRIANGLE_MESH_H_

#include <Eigen/Core>
#include <cstdint>
#include <optional>

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

// The volume a closed triangle mesh encloses, signed: positive when its
// faces turn counter-clockwise seen from outside (right-hand normals point
// out), negative when they point in. The sum of det[a b c] / 6 over the
// faces (the divergence theorem).
double SignedVolume(const Eigen::MatrixX3d& vertices,
                    const Eigen::MatrixX3i& faces);

// How far a point of the triangle (a, b, c) can be from the nearest of its
// corners, at most: the circumradius of a triangle without an obtuse angle
// (its circumcentre is the farthest point, so this is exact), half the
// longest edge otherwise (an upper bound). 0 for a degenerate triangle of
// one point; half the longest edge for any other degenerate one.
double CoveringRadius(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      const Eigen::Vector3d& c);

// `mesh` with every edge longer than `max_edge_length` split at its
// midpoint, again and again, until none is: a triangle with one such edge
// is cut in two, with three in four, and one with two (a needle, say) has
// those two split all along and the strip between them cut across into
// pieces as wide as it, so that a needle's pieces grow with its length, not
// its length squared. The same surface, point for point; how an edge is
// split depends on the edge alone, so both triangles of an edge split it
// alike and the result is conforming (every edge of a closed mesh stays
// shared by two faces). Rows 0..#V-1 are the input's vertices; the new
// ones follow as they are made (faces in order, each split depth first);
// faces keep their orientation. std::nullopt once the result would have
// more than `max_vertices` vertices. A max_edge_length that is not > 0
// splits nothing.
std::optional<TriangleMesh> SplitToEdgeLength(const TriangleMesh& mesh,
                                              double max_edge_length,
                                              int64_t max_vertices);

// The edge length for which SplitToEdgeLength gives a mesh of surface area
// `area` about `vertices` vertices where its triangles are coarser:
// sqrt(3 area / vertices) (measured at 100,000: 85K to 101K on blobby,
// bunny00, bear, fandisk, retinal and geosphere).
double SplitEdgeLengthFor(double area, int64_t vertices);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_TRIANGLE_MESH_H_
