// What the tessellator needs from a surface: its point and unit normal at
// directions on S^2. The tessellation (core/tessellate/sphere_triangulation.h,
// the pattern of domain triangles) knows nothing about splines; a sampler is
// the evaluator (OpenSubdiv keeps Bfr::Tessellation apart from Bfr::Surface
// the same way).
#ifndef SDCB_CORE_TESSELLATE_SURFACE_SAMPLER_H_
#define SDCB_CORE_TESSELLATE_SURFACE_SAMPLER_H_

#include <Eigen/Core>

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

 private:
  const SphericalSpline& spline_;
};

// Samples a SphericalSpline through its PiecewiseSurface (positions and
// normals; fast) and the spline itself for curvature.
class PiecewiseSplineSampler : public SurfaceSampler {
 public:
  PiecewiseSplineSampler(const SphericalSpline& spline,
                         const PiecewiseSurface& pieces)
      : spline_(spline), pieces_(pieces) {}
  void Sample(const Eigen::MatrixX3d& directions, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override;
  bool SampleCurvature(const Eigen::MatrixX3d& directions,
                       Eigen::VectorXd* gaussian,
                       Eigen::VectorXd* mean) const override {
    return SplineSampler(spline_).SampleCurvature(directions, gaussian, mean);
  }

 private:
  const SphericalSpline& spline_;
  const PiecewiseSurface& pieces_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_SURFACE_SAMPLER_H_
