// Per-vertex principal curvatures and curvedness of a triangle mesh: the
// feature measure of the first knot-placement round (paper Sec. 4.4:
// rho = kappa^alpha with curvedness kappa = |k1| + |k2|).
//
// Estimator: CGAL's Monge_via_jet_fitting (osculating jets, Cazals & Pouget)
// of a degree-`jet_degree` height function over a neighbourhood of each
// vertex: the nearest vertices (Euclidean distance) reachable along mesh
// edges, grown until there are enough points AND they span a 2-D patch (on
// CAD meshes with long thin triangles, e.g. fandisk, topological rings are
// thin strips, which makes the fitting frame meaningless). Vertices where no
// acceptable fit exists get the average of their neighbours (never NaN).
#ifndef SDCB_CORE_MESH_CURVATURE_H_
#define SDCB_CORE_MESH_CURVATURE_H_

#include <Eigen/Core>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct CurvatureOptions {
  // Degree d of the fitted jet z = J(x, y), 1 < d <= 4. d = 2 is the most
  // robust (needs >= 6 points); d = 3, 4 are more accurate on smooth dense
  // meshes but amplify noise.
  int jet_degree = 2;
  // The neighbourhood grows (nearest first, along mesh edges) until it
  // holds at least this many vertices (the vertex included) and spans a
  // patch. Must be >= (d+1)(d+2)/2.
  int min_points = 16;
  // Never grow beyond this many vertices; a vertex whose neighbourhood
  // still spans no patch becomes a fallback vertex.
  int max_points = 400;
  // A neighbourhood is accepted only if, projected onto the tangent plane of
  // the area-weighted vertex normal, its smaller principal variance is at
  // least this fraction of the larger one (the points span a 2-D patch, not
  // a thin strip). In (0, 1).
  double min_spread_ratio = 0.02;
  // A fit whose least-squares system (CGAL's preconditioned Vandermonde
  // matrix) has a larger condition number is rejected and the neighbourhood
  // grows further.
  double max_condition_number = 1e4;
};

struct PrincipalCurvatures {
  // #V values each, in 1/(mesh length unit). k_max >= k_min. Signed so that
  // a convex region of an outward-oriented (counter-clockwise) closed mesh
  // is positive: a sphere of radius r gives k_max = k_min = 1/r.
  Eigen::VectorXd k_max;
  Eigen::VectorXd k_min;
  // Vertices without an acceptable jet fit (no triangle, zero vertex
  // normal, degenerate neighbourhood, non-finite result), filled from their
  // neighbours.
  int fallback_vertices = 0;
};

// Principal curvatures of every vertex. `mesh` needs valid indices (else
// kInvalidInput) and finite coordinates (else kInvalidInput); it need not be
// closed. Parallel over vertices (TBB); the result does not depend on the
// number of threads.
StatusOr<PrincipalCurvatures> EstimatePrincipalCurvatures(
    const TriangleMesh& mesh, const CurvatureOptions& options = {});

// Curvedness kappa = |k1| + |k2| per vertex (#V values, 1/length, >= 0,
// finite). Scaling the mesh by s scales kappa by 1/s.
StatusOr<Eigen::VectorXd> Curvedness(const TriangleMesh& mesh,
                                     const CurvatureOptions& options = {});

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_CURVATURE_H_
