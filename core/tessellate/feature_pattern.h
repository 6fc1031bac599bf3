// The tessellator's starting pattern when the surface has creases along
// great-circle arcs between corners (a spline whose knots keep sharp
// features, core/knots/feature_knots.h): a triangulation of the sphere whose
// edges include every arc, with the arcs marked
// (SphereTriangulation::SetFeatures) so that refinement splits them at
// their midpoints and no simplification crosses them. Every face of the
// result then lies on one side of every crease: a flat part of the surface
// is covered by a few flat triangles instead of bands of small ones along
// creases its faces would straddle.
#ifndef SDCB_CORE_TESSELLATE_FEATURE_PATTERN_H_
#define SDCB_CORE_TESSELLATE_FEATURE_PATTERN_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/tessellate/sphere_triangulation.h"

namespace sdcb {

// `corners`: #C by 3 unit vectors; `arcs`: pairs of corner indices, each the
// shorter great-circle arc between them. The arcs' graph must cut the
// sphere into faces each within an open hemisphere and bounded by a simple
// cycle (as the edges of a convex solid projected from its centre do);
// kInvalidArgument otherwise (a corner on no arc, arcs that cross, a face
// not simple, a face too wide).

// The faces the arcs cut the sphere into: each a cycle of corners,
// counter-clockwise seen from outside.
StatusOr<std::vector<std::vector<int>>> FeatureFaces(
    const Eigen::MatrixX3d& corners,
    const std::vector<std::array<int, 2>>& arcs);

// The tessellator's pattern: each face triangulated by ear clipping in its
// gnomonic chart. The vertices are the corners, in order.
StatusOr<SphereTriangulation> FeatureAlignedPattern(
    const Eigen::MatrixX3d& corners,
    const std::vector<std::array<int, 2>>& arcs);

// The faces as quads, for quad layouts (the CAD network's, Catmull-Clark
// cages): the faces themselves when all are quads and `split` is false;
// otherwise every face of n corners cut into n quads, the i-th of them its
// i-th corner, the midpoint of the arc to the next corner, the face's
// centre (its chart's) and the midpoint of the arc from the previous one.
struct FeatureQuadMesh {
  // Unit vectors: the corners (in order), then the arcs' midpoints, then
  // the faces' centres.
  Eigen::MatrixX3d points;
  // Rows of `points`, counter-clockwise seen from outside, each starting at
  // a corner.
  std::vector<std::array<int, 4>> quads;
  // The quads' sides on the arcs (pairs of rows of `points`, a < b).
  std::vector<std::array<int, 2>> creases;
  bool split = false;
};
StatusOr<FeatureQuadMesh> FeatureQuads(
    const Eigen::MatrixX3d& corners,
    const std::vector<std::array<int, 2>>& arcs, bool split);

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_FEATURE_PATTERN_H_
