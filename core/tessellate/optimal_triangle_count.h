// The asymptotic optimum number of triangles of an interpolating
// triangulation of a surface within distance eps (Pottmann et al. 2000,
// D'Azevedo & Simpson 1989; docs/EXPORT.md derives both constants):
//   N_opt(eps) = (1 / eps) [ 2 / (3 sqrt 3) * int_{K > 0} sqrt(K) dA
//                          + 1 / (2 sqrt 5) * int_{K < 0} sqrt(|K|) dA ].
// Convex parts: equilateral triangles in the metric of the second
// fundamental form, error at the circumcentre (a sphere of radius R gives
// 8 pi R / (3 sqrt 3 eps) ~ 4.84 R / eps). Saddle parts: the error of
// linear interpolation of (x^2 - y^2) / 2 peaks on the edges, |d^T H d| / 8
// for an edge d; the largest triangle with all three at most eps has area
// 2 sqrt(5) eps (edges (s, 0), (-s/2, +-sqrt(5) s / 2) with s^2 = 8 eps).
#ifndef SDCB_CORE_TESSELLATE_OPTIMAL_TRIANGLE_COUNT_H_
#define SDCB_CORE_TESSELLATE_OPTIMAL_TRIANGLE_COUNT_H_

#include <Eigen/Core>

#include "sdcb/core/common/status.h"
#include "sdcb/core/measure/surface_sampler.h"

namespace sdcb {

// 2 / (3 sqrt 3) and 1 / (2 sqrt 5).
inline constexpr double kConvexTriangleConstant = 0.38490017945975052;
inline constexpr double kSaddleTriangleConstant = 0.22360679774997896;

struct CurvatureIntegrals {
  double convex = 0.0;  // int_{K > 0} sqrt(K) dA (length units)
  double saddle = 0.0;  // int_{K < 0} sqrt(|K|) dA
  double area = 0.0;    // int dA
};

// Quadrature over a triangulation of the domain (#V by 3 unit vectors,
// #F by 3 faces): each face is split into 4^levels sub-triangles; each
// contributes the area of its flat image triangle times sqrt(|K|) at its
// centroid's direction. Points where K is NaN (singular) contribute area
// only. kInvalidArgument if the sampler has no curvature.
StatusOr<CurvatureIntegrals> IntegrateCurvature(
    const SurfaceSampler& surface, const Eigen::MatrixX3d& directions,
    const Eigen::MatrixX3i& faces, int levels);

// The integrals of the whole surface, independent of any tessellation of
// it: the icosahedral pattern of `level` (20 * 4^level faces, level in
// [0, 8]) as the quadrature, positions at its vertices and sqrt(|K|) at its
// faces' centroids. At the default level 6 (81,920 faces) the bunny's N_opt
// is within 0.1 % of level 7's and of a 1.3M-face pattern's; on an adaptive
// tessellation the same rule is biased low (5 to 8 % on the bunny at 0.1
// and 0.01 %: its large faces lie where the integrand is small and
// uneven). kInvalidArgument if the sampler has no curvature.
StatusOr<CurvatureIntegrals> IntegrateCurvatureOverSurface(
    const SurfaceSampler& surface, int level = 6);

// N_opt(eps) from the integrals; eps > 0 in the same length unit.
double OptimalTriangleCount(const CurvatureIntegrals& integrals, double eps);

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_OPTIMAL_TRIANGLE_COUNT_H_
