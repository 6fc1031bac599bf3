// The mesh's side of a tessellation's distance: how far points of its flat
// faces are from the surface. The flat point x = flat(w) of a face (a, b, c)
// at barycentric weights w is at most |x - S(u(w))| from the surface, u(w)
// the domain point of the same weights; where the parameterization shears,
// S(u(w)) lies along the surface from x and that reads high. Points above
// `good_enough` then take up to kShearSteps derivative-free steps (w moved by
// the flat triangle's least-squares inverse of S(u(w)) - x: the surface's
// Jacobian in the weights is the flat triangle's to first order), and what
// is still above gets a closest-point search from u(w)
// (core/measure/closest_surface_points.h). Every distance is to a point
// of the surface found, never below the true one. Used by the tessellator's
// verification (core/tessellate/face_verification.h).
#ifndef SDCB_CORE_TESSELLATE_MESH_SIDE_DISTANCE_H_
#define SDCB_CORE_TESSELLATE_MESH_SIDE_DISTANCE_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/tessellate/surface_samples.h"

namespace sdcb {

// Row r: the point of pattern face faces[r] (of samples.pattern, its corners'
// surface points samples.positions) at weights[r]; directions.row(r) its
// domain point u (the weights' combination of the corners' directions,
// normalized) and points.row(r) = S(u), already evaluated. Returns each row's
// distance to the surface; the evaluations it makes are added to
// `*evaluations`.
Eigen::VectorXd FlatToSurfaceDistances(
    const SurfaceSampler& surface, const SurfaceSamples& samples,
    const std::vector<int>& faces, const std::vector<Eigen::Vector3d>& weights,
    const Eigen::MatrixX3d& directions, const Eigen::MatrixX3d& points,
    double good_enough, int64_t* evaluations);

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_MESH_SIDE_DISTANCE_H_
