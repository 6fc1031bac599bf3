#include "sdcb/core/spline/spherical_spline.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {

StatusOr<SphericalSpline> SphericalSpline::Create(
    DcbBasis basis, Eigen::MatrixX3d control_points, BasisForm form) {
  if (control_points.rows() != basis.size()) {
    return InvalidArgumentError(
        "spherical spline: " + std::to_string(control_points.rows()) +
        " control points for " + std::to_string(basis.size()) +
        " basis functions");
  }
  if (!control_points.allFinite()) {
    return InvalidArgumentError("spherical spline: non-finite control point");
  }
  return SphericalSpline(std::move(basis), std::move(control_points), form);
}

Eigen::Vector3d SphericalSpline::Evaluate(const Eigen::Vector3d& p) const {
  thread_local std::vector<BasisValue> values;  // no allocation per point
  const bool raw = form_ == BasisForm::kRaw;
  // The raw B_i are homogeneous of degree k: evaluate on the sphere.
  basis_.NonzeroValues(raw ? Eigen::Vector3d(p.normalized()) : p, &values);
  // Eq. 6 with eq. 5: F = (sum B_i c_i) / (sum B_i), summed in index order;
  // with eq. 4, F = sum B_i c_i.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double norm = 0.0;
  for (const BasisValue& v : values) {
    sum += v.value * control_points_.row(v.index).transpose();
    norm += v.value;
  }
  return raw ? sum : Eigen::Vector3d(sum / norm);
}

SurfacePoint SphericalSpline::EvaluateDifferential(const Eigen::Vector3d& p,
                                                   JetOrder order) const {
  SurfacePoint out;
  if (order == JetOrder::kValue) {
    out.position = Evaluate(p);
    return out;
  }
  const SurfaceShape shape = Shape(p, order == JetOrder::kHessian);
  out.position = shape.position;
  TangentFrame(p.normalized(), &out.frame_u, &out.frame_v);
  out.du = shape.du;
  out.dv = shape.dv;
  out.normal = shape.normal;
  if (order == JetOrder::kHessian) {
    out.mean_curvature = shape.mean_curvature;
    out.gaussian_curvature = shape.gaussian_curvature;
  }
  return out;
}

SurfaceShape SphericalSpline::EvaluateShape(const Eigen::Vector3d& p) const {
  return Shape(p, true);
}

SurfaceShape SphericalSpline::Shape(const Eigen::Vector3d& p,
                                    bool second) const {
  const bool raw = form_ == BasisForm::kRaw;
  const JetOrder order = second ? JetOrder::kHessian : JetOrder::kGradient;
  // The raw form's jets below assume |p| = 1.
  const Eigen::Vector3d q = raw ? Eigen::Vector3d(p.normalized()) : p;
  thread_local std::vector<int> candidates;  // no allocation per point
  basis_.Candidates(q, &candidates);
  // Numerator N = sum B_i c_i and denominator I = sum B_i with derivatives.
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  Eigen::Matrix3d dn = Eigen::Matrix3d::Zero();  // Row c: grad N_c.
  Eigen::Matrix3d hn[3] = {Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero(),
                           Eigen::Matrix3d::Zero()};
  ScalarJet total;
  for (int i : candidates) {
    const ScalarJet b = basis_.Evaluate(i, q, order);
    if (b.value == 0.0 && b.gradient.isZero(0.0)) continue;
    const Eigen::Vector3d c = control_points_.row(i).transpose();
    n += b.value * c;
    dn += c * b.gradient.transpose();
    total.value += b.value;
    total.gradient += b.gradient;
    if (second) {
      for (int k = 0; k < 3; ++k) hn[k] += c[k] * b.hessian;
      total.hessian += b.hessian;
    }
  }
  if (raw) {
    // D = |x|^k at |q| = 1: value 1, gradient k q, Hessian k I + k(k-2) q q^T.
    const double k = basis_.degree();
    total.value = 1.0;
    total.gradient = k * q;
    total.hessian =
        k * Eigen::Matrix3d::Identity() + k * (k - 2) * q * q.transpose();
  }
  const double inv = 1.0 / total.value;
  const Eigen::Vector3d position = n * inv;
  // Quotient rule for F = N / D.
  Eigen::Matrix3d df;
  for (int k = 0; k < 3; ++k) {
    df.row(k) = (dn.row(k) - position[k] * total.gradient.transpose()) * inv;
  }
  Eigen::Vector3d frame_u, frame_v;
  TangentFrame(p.normalized(), &frame_u, &frame_v);
  const Eigen::Vector3d du = df * frame_u, dv = df * frame_v;
  Eigen::Vector3d fuu = Eigen::Vector3d::Zero(), fuv = fuu, fvv = fuu;
  if (second) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d dfk = df.row(k).transpose();
      const Eigen::Matrix3d hf = (hn[k] - position[k] * total.hessian -
                                  dfk * total.gradient.transpose() -
                                  total.gradient * dfk.transpose()) *
                                 inv;
      fuu[k] = frame_u.dot(hf * frame_u);
      fuv[k] = frame_u.dot(hf * frame_v);
      fvv[k] = frame_v.dot(hf * frame_v);
    }
  }
  return ShapeFromDerivatives(position, du, dv, fuu, fuv, fvv);
}

Eigen::MatrixX3d SphericalSpline::EvaluateMany(
    const Eigen::MatrixX3d& points) const {
  Eigen::MatrixX3d out(points.rows(), 3);
  basis_.ParallelForEachPoint(points, [&](Eigen::Index r) {
    out.row(r) = Evaluate(points.row(r).transpose()).transpose();
  });
  return out;
}

std::vector<SurfacePoint> SphericalSpline::EvaluateDifferentialMany(
    const Eigen::MatrixX3d& points, JetOrder order) const {
  std::vector<SurfacePoint> out(points.rows());
  basis_.ParallelForEachPoint(points, [&](Eigen::Index r) {
    out[r] = EvaluateDifferential(points.row(r).transpose(), order);
  });
  return out;
}

StatusOr<SphericalSpline> SurfaceFromModel(const SplineModel& model) {
  SDCB_ASSIGN_OR_RETURN(DcbBasis basis,
                        DcbBasis::Create(model.knots, model.configurations));
  return SphericalSpline::Create(std::move(basis), model.control_points,
                                 model.basis_form);
}

}  // namespace sdcb
