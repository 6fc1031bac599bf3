// Sharp features of a triangle mesh: the edges where the surface turns by
// more than a given angle (the angle between the normals of the two
// triangles that share the edge), chained into feature curves, and the
// corners where curves meet or turn sharply.
//
// - A feature edge is an edge with exactly two triangles whose unit normals
//   are more than `angle_degrees` apart (degenerate triangles, without a
//   normal, make no feature).
// - A corner is a vertex with three or more feature edges, or with exactly
//   two whose directions (in, out) turn by more than `angle_degrees`.
// - A curve is a maximal chain of feature edges whose inner vertices are
//   neither corners nor ends (vertices with one feature edge): it runs from
//   a corner or an end to a corner or an end, or it is a closed loop through
//   vertices that are neither.
// The fit reports them (`features` in `sdcb fit --json`).
#ifndef SDCB_CORE_MESH_FEATURE_CURVES_H_
#define SDCB_CORE_MESH_FEATURE_CURVES_H_

#include <array>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct FeatureCurve {
  // The vertices along the curve, in order; a closed curve does not repeat
  // its first vertex at the end.
  std::vector<int> vertices;
  bool closed = false;
};

struct MeshFeatures {
  double angle_degrees = 180.0;           // the angle they were detected at
  std::vector<std::array<int, 2>> edges;  // (a, b) with a < b, sorted
  std::vector<FeatureCurve> curves;
  std::vector<int> corners;  // sorted
};

// The features of `mesh` at `angle_degrees` in (0, 180]; 180 finds none.
// kInvalidArgument for an angle outside that range, kInvalidInput for a
// face index out of range. Deterministic: the open curves first, in the
// order of their first vertex and then of its neighbours, then the closed
// ones in the order of their smallest edge.
StatusOr<MeshFeatures> DetectFeatures(const TriangleMesh& mesh,
                                      double angle_degrees);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_FEATURE_CURVES_H_
