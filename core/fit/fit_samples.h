// The samples of the fit's data term (docs/FITTING.md): a quadrature of
//   integral over the mesh M of |F(u(x)) - x|^2 dA,
// the squared distance between the spline at a point's sphere parameter and
// the point, over the mesh's piecewise-linear surface (not only its
// vertices). u maps a mesh triangle onto its spherical triangle by
// normalized barycentric combination of the corners' sphere points.
//
// A triangle whose spherical image is small against the local knot spacing
// is integrated by the vertex rule (a third of its area to each corner). A
// larger one is split by longest-edge bisection until no edge of a piece's
// spherical image is longer than the spacing (of the knot nearest to the
// piece) over FitSampleOptions::samples_per_spacing, each piece integrated by
// the rule that gives its corners 1/12 and its centroid 3/4 of its area (exact
// for quadratics). So every part of the sphere, and every basis support, holds
// samples about that dense, slivers included, without an m x m lattice.
#ifndef SDCB_CORE_FIT_FIT_SAMPLES_H_
#define SDCB_CORE_FIT_FIT_SAMPLES_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct FitSampleOptions {
  // Samples per knot spacing along a spherical triangle's longest edge.
  double samples_per_spacing = 2.0;
  // Bisection depth at most (2^depth pieces per triangle at most).
  int max_depth = 14;
  // Pieces over all split triangles at most (0: no limit). Past it, long
  // needle triangles (a CAD fan's) are each cut along their whole length,
  // n needles sampling the same region n times over: the pieces' quadrature
  // points are then pooled in cells of the sample spacing (a tangent grid
  // of the nearest knot), one row per cell at the weighted means of its
  // points and targets, so the rows stay a few per knot, as dense as the
  // knots ask everywhere; needles narrower than half the sample spacing are
  // cut into a few strips at a staggered phase instead of along their whole
  // length (their neighbours' strips fill the cells between).
  int64_t max_pieces = 0;
  // A mesh far denser than its knots asks for far more rows than the knots
  // can use (every vertex is a row; the points inside split triangles are
  // already at the knots' density): with more than `thin_above_vertices`
  // vertices (0: never), the rows are thinned to the knots' density. Each row
  // falls into a cell of a tangent grid at its nearest knot,
  // `thinned_cells_per_spacing` cells per that knot's spacing, split further by
  // the direction of the mesh's normal (a crease's two sides stay apart); each
  // cell keeps the one of its rows nearest (on the sphere) to the cells'
  // weighted centroid, with the cell's summed weight. The kept rows are points
  // of the mesh with their own sphere points (no averaging, which would pull
  // targets inside a curved surface), the weights still add up to the area, and
  // the rows are a few per control point however dense the mesh. Skipped when
  // it would keep more than `thin_keep_at_most` of the rows.
  int64_t thin_above_vertices = 0;
  double thinned_cells_per_spacing = 4.0;
  double thin_keep_at_most = 0.7;
  // Per mesh face, a factor on its area in every weight (null: 1 for all):
  // the fill of an open part's holes weighs little, so that it only keeps
  // the spline smooth there (core/fit/fit_mesh.h). Must outlive the call.
  const Eigen::VectorXd* face_weights = nullptr;
};

struct FitSamples {
  // Rows: the mesh vertices first (row v = vertex v), then the points inside
  // split triangles. Sphere points (unit vectors), target points (the mesh's
  // frame), quadrature weights (mesh area), and for the rows after the
  // vertices the mesh triangle each point lies in.
  //
  // Thinned (FitSampleOptions::thin_above_vertices): num_vertices is 0, every
  // row is a cell's kept row; row_vertex[r] is the mesh vertex row r is, or
  // -1 for a point inside triangle[r] (which is -1 for a vertex),
  // row_normal its unit mesh normal (the vertex's, VertexNormals, or the
  // triangle's), and vertex_row[v] the row kept for mesh vertex v's cell.
  Eigen::MatrixX3d points;
  Eigen::MatrixX3d targets;
  Eigen::VectorXd weights;
  std::vector<int> triangle;  // size points.rows() - num_vertices
  Eigen::Index num_vertices = 0;
  bool thinned = false;
  std::vector<int> row_vertex;      // thinned: per row
  Eigen::MatrixX3d row_normal;      // thinned: per row
  std::vector<int> vertex_row;      // thinned: per mesh vertex
  Eigen::Index unthinned_rows = 0;  // rows before thinning
  int split_triangles = 0;          // triangles split into pieces
  // The samples per spacing used (options.samples_per_spacing).
  double samples_per_spacing = 0.0;
  // Pieces and needle strips pooled into cells when the pieces exceeded
  // max_pieces; 0 otherwise.
  int64_t merged_pieces = 0;
};

// `mesh`: the mesh (any frame); `sphere`: #V by 3 sphere points of its
// vertices (a bijective parameterization); `knots`: #K by 3 unit vectors,
// the knots the samples must resolve; `vertex_normals`: VertexNormals(mesh)
// if the caller has them (thinning needs them), else null. Deterministic.
FitSamples BuildFitSamples(const TriangleMesh& mesh,
                           const Eigen::MatrixX3d& sphere,
                           const Eigen::MatrixX3d& knots,
                           const FitSampleOptions& options = {},
                           const Eigen::MatrixX3d* vertex_normals = nullptr);

// Appends rows beside every edge of `edges` (mesh vertex pairs), inside
// each triangle along it: at `along` points evenly along the edge and, for
// each, at sphere distances of about `offsets` radians from the edge's arc
// (barycentric weight of the opposite corner over that corner's distance to
// the arc). Each row weighs `weight`. Basis functions whose supports are the
// thin slivers between a feature arc and a knot a hair beside it
// (core/knots/feature_knots.h) see no other sample.
void AppendEdgeBandSamples(const TriangleMesh& mesh,
                           const Eigen::MatrixX3d& sphere,
                           const std::vector<std::array<int, 2>>& edges,
                           const std::vector<double>& offsets, int along,
                           double weight, FitSamples* samples);

// For every knot, the distance to its nearest other knot (chord length);
// +inf for a single knot.
Eigen::VectorXd KnotSpacing(const Eigen::MatrixX3d& knots);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FIT_SAMPLES_H_
