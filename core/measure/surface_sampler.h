// What the tessellator needs from a surface: its point and unit normal at
// directions on S^2. The tessellation (core/tessellate/sphere_triangulation.h,
// the pattern of domain triangles) knows nothing about splines; a sampler is
// the evaluator (OpenSubdiv keeps Bfr::Tessellation apart from Bfr::Surface
// the same way).
#ifndef SDCB_CORE_MEASURE_SURFACE_SAMPLER_H_
#define SDCB_CORE_MEASURE_SURFACE_SAMPLER_H_

#include <Eigen/Core>
#include <vector>

#include "sdcb/core/spline/surface_shape.h"

namespace sdcb {

class SphericalSpline;
class PiecewiseSurface;

class SurfaceSampler {
 public:
  virtual ~SurfaceSampler() = default;
  // `directions`: #P by 3 unit vectors. Fills `positions` (#P by 3, the
  // surface point S(p)) and, if not null, `normals` (#P by 3 unit normals,
  // zero rows where the surface is singular). Thread-safe; the result of
  // a row depends on that row only.
  virtual void Sample(const Eigen::MatrixX3d& directions,
                      Eigen::MatrixX3d* positions,
                      Eigen::MatrixX3d* normals) const = 0;
  // Gaussian and mean curvature (1/length^2, 1/length; H > 0 where the
  // surface bends away from its normal like a sphere with outward normals)
  // at each direction, NaN where singular. Returns false if this sampler
  // cannot compute curvature.
  virtual bool SampleCurvature(const Eigen::MatrixX3d& directions,
                               Eigen::VectorXd* gaussian,
                               Eigen::VectorXd* mean) const {
    return false;
  }
  // The shape (core/spline/surface_shape.h: position, normal, tangents,
  // fundamental forms, curvatures) at each direction, in the chart of the
  // tangent frame TangentFrame(direction). Returns false if this sampler
  // cannot compute it.
  virtual bool SampleShape(const Eigen::MatrixX3d& directions,
                           std::vector<SurfaceShape>* shapes) const {
    return false;
  }
};

// Samples a SphericalSpline through EvaluateDifferentialMany (the reference
// evaluator; slow, exact).
class SplineSampler : public SurfaceSampler {
 public:
  explicit SplineSampler(const SphericalSpline& spline) : spline_(spline) {}
  void Sample(const Eigen::MatrixX3d& directions, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override;
  bool SampleCurvature(const Eigen::MatrixX3d& directions,
                       Eigen::VectorXd* gaussian,
                       Eigen::VectorXd* mean) const override;
  bool SampleShape(const Eigen::MatrixX3d& directions,
                   std::vector<SurfaceShape>* shapes) const override;

 private:
  const SphericalSpline& spline_;
};

// Samples a SphericalSpline through its PiecewiseSurface: positions,
// normals, curvature and shape from the per-piece polynomials (fast; equal
// to SplineSampler's to rounding).
class PiecewiseSplineSampler : public SurfaceSampler {
 public:
  // `spline`: the spline `pieces` was made from (which holds it).
  PiecewiseSplineSampler(const SphericalSpline& spline,
                         const PiecewiseSurface& pieces)
      : pieces_(pieces) {}
  void Sample(const Eigen::MatrixX3d& directions, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override;
  bool SampleCurvature(const Eigen::MatrixX3d& directions,
                       Eigen::VectorXd* gaussian,
                       Eigen::VectorXd* mean) const override;
  bool SampleShape(const Eigen::MatrixX3d& directions,
                   std::vector<SurfaceShape>* shapes) const override;

 private:
  const PiecewiseSurface& pieces_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_MEASURE_SURFACE_SAMPLER_H_
