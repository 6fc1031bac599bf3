// The spherical DCB-spline surface (paper eq. 6):
//   F(p) = sum_i Bbar_i(p) c_i,   p in S^2, c_i in R^3,
// with the normalized basis of eq. 5 (BasisForm::kNormalized), or
//   F(p) = sum_i B_i(p) c_i
// with the raw basis of eq. 4 (BasisForm::kRaw). Evaluation of position,
// tangent derivatives, unit normal, mean and Gaussian curvature at one point
// or, in parallel (TBB), at many; results do not depend on the thread count.
//
// Derivatives: B_i and I are homogeneous of degree k, so F = (sum B_i c_i)/D
// with D = I (normalized) or D = |x|^k (raw) extends to R^3 \ {0}
// homogeneous of degree 0, F(x) = F(x / |x|). At a
// point p with the orthonormal tangent frame (e_u, e_v) (e_u x e_v = p) the
// chart phi(u, v) = F(p + u e_u + v e_v) parameterizes the surface near F(p),
// and its partial derivatives are the "tangent derivatives" reported here
// (first derivatives equal those along geodesics from p).
#ifndef SDCB_CORE_SPLINE_SPHERICAL_SPLINE_H_
#define SDCB_CORE_SPLINE_SPHERICAL_SPLINE_H_

#include <Eigen/Core>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/spline_model.h"
#include "sdcb/core/spline/surface_shape.h"

namespace sdcb {

// Differential geometry of F at one parameter point.
struct SurfacePoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // F(p)
  // Orthonormal tangent frame of S^2 at p, e_u x e_v = p.
  Eigen::Vector3d frame_u = Eigen::Vector3d::Zero();
  Eigen::Vector3d frame_v = Eigen::Vector3d::Zero();
  // dF/du, dF/dv of the chart phi (see above).
  Eigen::Vector3d du = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  // Unit normal (du x dv) / |du x dv|: outward when F preserves the sphere's
  // orientation. Zero if du, dv are dependent (singular point).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  // Mean curvature H (a sphere of radius R with outward normal has H = 1/R)
  // and Gaussian curvature K; computed with JetOrder::kHessian only, NaN at
  // a singular point.
  double mean_curvature = 0.0;
  double gaussian_curvature = 0.0;
};

class SphericalSpline {
 public:
  // `control_points`: basis.size() by 3, one per basis function, in the
  // order of the configuration sets. Fails with kInvalidArgument on a size
  // mismatch or non-finite control points.
  static StatusOr<SphericalSpline> Create(
      DcbBasis basis, Eigen::MatrixX3d control_points,
      BasisForm form = BasisForm::kNormalized);

  int degree() const { return basis_.degree(); }
  const Eigen::MatrixX3d& knots() const { return basis_.knots(); }
  const DcbBasis& basis() const { return basis_; }
  const Eigen::MatrixX3d& control_points() const { return control_points_; }
  BasisForm basis_form() const { return form_; }

  // F(p) for a unit vector p.
  Eigen::Vector3d Evaluate(const Eigen::Vector3d& p) const;
  // Position and, with kGradient, frame/du/dv/normal; with kHessian, also
  // the curvatures.
  SurfacePoint EvaluateDifferential(const Eigen::Vector3d& p,
                                    JetOrder order = JetOrder::kHessian) const;
  // The shape at p (surface_shape.h) in the chart of SurfacePoint:
  // phi(u, v) = F(p + u e_u + v e_v), (e_u, e_v) = TangentFrame(p / |p|).
  SurfaceShape EvaluateShape(const Eigen::Vector3d& p) const;

  // F at each row of `points` (#P by 3 unit vectors); #P by 3.
  Eigen::MatrixX3d EvaluateMany(const Eigen::MatrixX3d& points) const;
  // EvaluateDifferential at each row of `points`.
  std::vector<SurfacePoint> EvaluateDifferentialMany(
      const Eigen::MatrixX3d& points,
      JetOrder order = JetOrder::kHessian) const;

 private:
  // EvaluateShape; without `second`, its second form and curvatures are
  // those of zero second derivatives.
  SurfaceShape Shape(const Eigen::Vector3d& p, bool second) const;
  SphericalSpline(DcbBasis basis, Eigen::MatrixX3d control_points,
                  BasisForm form)
      : basis_(std::move(basis)),
        control_points_(std::move(control_points)),
        form_(form) {}

  DcbBasis basis_;
  Eigen::MatrixX3d control_points_;
  BasisForm form_ = BasisForm::kNormalized;
};

// The surface of a model in its normalized frame (SplineModel::transform
// maps it back to input coordinates): its basis built from the model's knots
// and configurations, its control points and basis form.
StatusOr<SphericalSpline> SurfaceFromModel(const SplineModel& model);

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_SPHERICAL_SPLINE_H_
