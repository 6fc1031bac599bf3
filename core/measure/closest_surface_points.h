// Closest points of a surface over S^2 (a SurfaceSampler: the spline through
// its fast evaluator) to points in space, by Gauss-Newton steps on
// |S(u) - x|^2 over the sphere's tangent plane at u, the Jacobian by
// finite differences (step 1e-6 along a tangent frame). Used by the
// tessellator's verification (the mesh's side of each face,
// core/tessellate/face_verification.h) and the exporters' independent
// measurements (converters/tessellation_deviation.h,
// converters/cage_deviation.h).
#ifndef SDCB_CORE_MEASURE_CLOSEST_SURFACE_POINTS_H_
#define SDCB_CORE_MEASURE_CLOSEST_SURFACE_POINTS_H_

#include <Eigen/Core>
#include <cstdint>

#include "sdcb/core/measure/surface_sampler.h"

namespace sdcb {

// For every row x of `points` (#P by 3), from the unit vector in the same
// row of `*directions` (the start): up to `iterations` Gauss-Newton steps,
// each shortened to at most 0.5 radians and halved (up to 4 times) while it
// does not bring S(u) nearer to x; a point stops where no step does, or
// after a step shorter than 1e-7 radians (converged). Returns
// the smallest |x - S(u)| met, the distance to a point of the surface, so
// never below the true distance; `*directions` holds where it was met.
// A point also stops once its distance is at most `good_enough` (a caller
// that needs only to know that much). Deterministic; the evaluations are
// batched, and added to `*evaluations` if given.
Eigen::VectorXd ClosestSurfacePoints(const SurfaceSampler& surface,
                                     const Eigen::MatrixX3d& points,
                                     int iterations,
                                     Eigen::MatrixX3d* directions,
                                     int64_t* evaluations = nullptr,
                                     double good_enough = 0.0);

}  // namespace sdcb

#endif  // SDCB_CORE_MEASURE_CLOSEST_SURFACE_POINTS_H_
