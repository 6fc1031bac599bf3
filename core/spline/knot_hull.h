// Convex hull of knots on S^2 under the symbolic perturbation of
// core/sphere/perturbed_predicates.h. The perturbed knots are in general and
// convex position, so every knot is a hull vertex and every facet is a
// triangle. Its facets are the 0-facets the configuration search starts from;
// those whose outer side avoids the origin are the degree-0 spherical Delaunay
// configurations (paper Sec. 2).
#ifndef SDCB_CORE_SPLINE_KNOT_HULL_H_
#define SDCB_CORE_SPLINE_KNOT_HULL_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "sdcb/core/common/status.h"

namespace sdcb {

struct KnotHull {
  // Triangles of knot indices, counter-clockwise seen from outside (the
  // perturbed orient3d of any other knot against a facet is -1). Sorted.
  std::vector<std::array<int, 3>> facets;
  // neighbors[i]: knots joined to knot i by a hull edge, ascending.
  std::vector<std::vector<int>> neighbors;
};

// Hull of `knots` (#knots by 3, distinct points on the unit sphere, at least
// 4). Randomized incremental construction with a conflict graph (de Berg et
// al., Computational Geometry, Ch. 11) with a fixed insertion order, so the
// result (unique under the perturbation) is reproducible: O(n log n)
// expected. Returns kInvalidArgument for fewer than 4 knots or knots not in
// convex position: on the sphere up to rounding that needs three or more
// knots within about 1e-8 of each other (pairs 1e-9 apart are fine).
StatusOr<KnotHull> ComputeKnotHull(const Eigen::MatrixX3d& knots);

// Facets (as in KnotHull::facets, in knot indices) of the hull of the knots
// listed in `subset` (at least 4 distinct indices into `knots`), under the
// same perturbation: the same answer as ComputeKnotHull on those knots
// alone with their original indices.
StatusOr<std::vector<std::array<int, 3>>> ComputeKnotSubsetHull(
    const Eigen::MatrixX3d& knots, const std::vector<int>& subset);

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_KNOT_HULL_H_
