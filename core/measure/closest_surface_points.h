// Closest points of a surface to points in space: the one home of the
// searches, by Gauss-Newton steps on |S(u) - x|^2 over a two-parameter
// chart.
//
// - GaussNewtonClosest: the step kernel over any chart with first
//   derivatives (the chart and its parameters live with the caller): the
//   spline's tangent chart (ClosestSurfacePoint) and the cage's limit-surface
//   faces (converters/cage/cage_deviation.h: ClosestOnLimitFace).
// - ClosestSurfacePoint: one point, from one sphere point, with the
//   sampler's own derivatives (SurfaceSampler::EvaluateJet); the fit's and
//   compare's measurement (core/measure/surface_deviation.h).
// - ClosestSurfacePoints: many points at once, the Jacobian by finite
//   differences (step 1e-6 along a tangent frame) so that every evaluation
//   is a batch of SurfaceSampler::Sample; the tessellator's verification (the
//   mesh's side of each face, core/tessellate/mesh_side_distance.h) and the
//   exporters' independent measurements
//   (converters/mesh/tessellation_deviation.h,
//   converters/cage/cage_deviation.h).
//
// Every distance returned is to a point of the surface found, so never below
// the true distance.
#ifndef SDCB_CORE_MEASURE_CLOSEST_SURFACE_POINTS_H_
#define SDCB_CORE_MEASURE_CLOSEST_SURFACE_POINTS_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>

#include "sdcb/core/measure/surface_sampler.h"

namespace sdcb {

// A point of a surface in a two-parameter chart and its first derivatives.
struct ChartPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d du = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
};

// Gauss-Newton steps toward the point of a surface closest to `x`, from
// `current`: up to `iterations` steps -(J^T J)^-1 J^T (S - x), J = [du dv],
// each shortened to at most `max_step` (in the chart's units; 0: not
// shortened) and halved (up to 4 times) until it brings the point nearer;
// the search stops where no step does, where J^T J is singular
// (|det| <= 1e-300) or at distance 0. The caller holds the parameters:
// `try_step(step, &point)` evaluates the surface at the current parameters
// moved by `step` into `point`; `accept()` makes that candidate the current
// one. Returns the smallest |S - x| met.
double GaussNewtonClosest(
    const Eigen::Vector3d& x, ChartPoint current, int iterations,
    double max_step,
    const std::function<void(const Eigen::Vector2d&, ChartPoint*)>& try_step,
    const std::function<void()>& accept);

// The distance from `x` to `surface`, searched from the unit vector `start`
// by GaussNewtonClosest in the tangent chart of SurfaceSampler::EvaluateJet
// (the chart moves with the point; steps of at most 0.2 radians: the chart
// is only good near its point). Returns the smallest |S(u) - x| met (an
// upper bound of the true distance); `*found` (if not null) is that u.
double ClosestSurfacePoint(const SurfaceSampler& surface,
                           const Eigen::Vector3d& x,
                           const Eigen::Vector3d& start, int iterations,
                           Eigen::Vector3d* found = nullptr);

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
