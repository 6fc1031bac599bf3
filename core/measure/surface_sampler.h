// The one evaluator interface of a surface over S^2: its point, unit normal,
// first derivatives, curvature and shape at directions, in batches or one
// direction at a time. The tessellator, the fit's and compare's measurement
// (core/measure/surface_deviation.h), the closest-point searches
// (core/measure/closest_surface_points.h) and the exporters' checks all
// evaluate the spline through it. The tessellation
// (core/tessellate/sphere_triangulation.h, the pattern of domain triangles)
// knows nothing about splines; a sampler is the evaluator (OpenSubdiv keeps
// Bfr::Tessellation apart from Bfr::Surface the same way).
#ifndef SDCB_CORE_MEASURE_SURFACE_SAMPLER_H_
#define SDCB_CORE_MEASURE_SURFACE_SAMPLER_H_

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/core/spline/surface_shape.h"

namespace sdcb {

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

  // One direction at a time, for searches that step point by point inside
  // a parallel loop (no batch to share). `direction`: a unit vector.
  // S(direction); by default a batch of one through Sample.
  virtual Eigen::Vector3d Evaluate(const Eigen::Vector3d& direction) const;
  // The unit normal there (zero where singular); by default through Sample.
  virtual Eigen::Vector3d EvaluateNormal(
      const Eigen::Vector3d& direction) const;
  // S with its first derivatives in the chart phi(u, v) = S(p + u e_u +
  // v e_v) of SurfacePoint (e_u, e_v = TangentFrame(direction)) and the
  // unit normal; curvatures are not set. By default from SampleShape; where
  // that is not available, the point alone (zero derivatives: a search
  // cannot step from it).
  virtual SurfacePoint EvaluateJet(const Eigen::Vector3d& direction) const;
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
  // SphericalSpline::Evaluate and EvaluateDifferential (JetOrder::kGradient).
  Eigen::Vector3d Evaluate(const Eigen::Vector3d& direction) const override;
  Eigen::Vector3d EvaluateNormal(
      const Eigen::Vector3d& direction) const override;
  SurfacePoint EvaluateJet(const Eigen::Vector3d& direction) const override;

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
  // PiecewiseSurface::Evaluate, EvaluateWithNormal and EvaluateShape.
  Eigen::Vector3d Evaluate(const Eigen::Vector3d& direction) const override;
  Eigen::Vector3d EvaluateNormal(
      const Eigen::Vector3d& direction) const override;
  SurfacePoint EvaluateJet(const Eigen::Vector3d& direction) const override;

 private:
  const PiecewiseSurface& pieces_;
};

// A sampler of `spline` (which must outlive it) that holds what it
// evaluates with: with `polynomials`, a PiecewiseSurface built here and
// evaluated as PiecewiseSplineSampler does (several times faster per point
// once a region is built; worth it when there are many points per control
// point); else the basis, as SplineSampler.
std::unique_ptr<SurfaceSampler> MakeSplineSampler(const SphericalSpline& spline,
                                                  bool polynomials);

}  // namespace sdcb

#endif  // SDCB_CORE_MEASURE_SURFACE_SAMPLER_H_
