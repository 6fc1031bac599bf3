// The tessellator's starting pattern for a trimmed surface (a part whose
// kept region is bounded by trim loops, core/sphere/trim_region.h): a
// triangulation of the sphere whose edges include every trim side as a
// chain, with the sides marked as feature arcs
// (SphereTriangulation::SetFeatures) so that refinement splits them on
// their arcs and no simplification crosses them. After the tessellation,
// KeptFaceSlots picks the faces of the kept region: the result's boundary is
// then exactly the trim loops.
#ifndef SDCB_CORE_TESSELLATE_TRIM_PATTERN_H_
#define SDCB_CORE_TESSELLATE_TRIM_PATTERN_H_

#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/sphere/trim_region.h"
#include "sdcb/core/tessellate/sphere_triangulation.h"

namespace sdcb {

// The spherical Delaunay triangulation (the convex hull,
// core/spline/knot_hull.h) of the trim points and of the vertices of a
// once-subdivided icosahedron that lie farther than 0.15 rad from every trim
// side, with each side missing from it split at the midpoints of its arc
// until it is a chain of edges (a conforming triangulation).
//
// `loops`: at least one, each at least 3 unit rows, none equal or antipodal
// to the next (kInvalidArgument otherwise). The vertices are the trim points
// (loop after loop, in order), then the kept icosahedron vertices, then the
// midpoints. Feature arc s is the s-th side over all loops, its ends in the
// loop's direction (the kept region on its left), the trim points corners.
// kInvalidInput (one sentence) when trim points lie so close together that
// a side cannot be made an edge (another trim within ~1e-7 of it, three
// points within ~1e-8 of each other), or the loops need too many points.
StatusOr<SphereTriangulation> TrimmedPattern(
    const std::vector<TrimLoop>& loops);

// Per face slot of `pattern` (a TrimmedPattern, refined and simplified with
// its feature arcs kept), 1 if the face lies in the kept region: faces on
// the left of an arc's edge are kept, those on its right are not, and the
// decision spreads across edges that are on no arc. Dead slots get 0.
// kInvalidInput when one region touches arcs from both sides (loops that
// cross, or not oriented as trim_region.h says).
StatusOr<std::vector<char>> KeptFaceSlots(const SphereTriangulation& pattern);

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_TRIM_PATTERN_H_
