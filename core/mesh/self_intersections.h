// Self-intersections of a triangle mesh: pairs of triangles that meet other
// than in the edge or vertex they share (the rule of CGAL's
// Polygon_mesh_processing::self_intersections, which the tests compare
// against; here on any triangle soup, with the box pairs tested in
// parallel and counted against a budget in the same pass). A
// closed genus-0 mesh can still pass through itself (a flattened
// tetrahedron, a crumpled sphere); its spherical parameterization then
// exists, but the spline surface copies the overlap.
#ifndef SDCB_CORE_MESH_SELF_INTERSECTIONS_H_
#define SDCB_CORE_MESH_SELF_INTERSECTIONS_H_

#include <cstdint>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct SelfIntersectionOptions {
  // The test compares triangles whose bounding boxes overlap. Triangles
  // fanned around one vertex of very high valence all overlap there, so
  // the number of such pairs can grow with the square of the valence; the
  // test is skipped (checked = false) when it exceeds
  //   max_pairs_per_face * #F + max_extra_pairs.
  int64_t max_pairs_per_face = 100;
  int64_t max_extra_pairs = 2'000'000;
};

struct SelfIntersectionReport {
  // False when the test was not run: too many overlapping boxes.
  bool checked = false;
  // Why checked is false, as a phrase.
  std::string skipped_because;
  // Pairs of non-degenerate triangles that intersect beyond their shared
  // edge or vertex (degenerate triangles are counted by the topology
  // report, not here).
  int64_t intersecting_pairs = 0;
};

// Runs the test; fails only for indices out of range (kInvalidInput).
StatusOr<SelfIntersectionReport> FindSelfIntersections(
    const TriangleMesh& mesh, const SelfIntersectionOptions& options = {});

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_SELF_INTERSECTIONS_H_
