#include "sdcb/io/sdcb/control_point_quantization.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {
namespace {

// Icosphere subdivisions for measuring max I: at least 6 (40962 points) and
// at least 32 points per knot, at most 8 (655362 points).
int SampleSubdivisions(Eigen::Index knots) {
  int s = 6;
  while (s < 8 && 10 * (int64_t{1} << (2 * s)) + 2 < 32 * int64_t{knots}) ++s;
  return s;
}

// max_p I(p) = sum_i B_i(p) of the raw basis, measured at the vertices of an
// icosphere and at the knots: the x coordinate of the raw-basis surface whose
// control points are all (1, 0, 0).
StatusOr<double> MeasureMaxBasisSum(const SplineModel& model) {
  SplineModel ones = model;
  ones.control_points.setZero();
  ones.control_points.col(0).setOnes();
  StatusOr<SphericalSpline> surface = SurfaceFromModel(ones);
  if (!surface.ok()) return surface.status();
  const TriangleMesh sphere =
      MakeIcosphere(SampleSubdivisions(model.knots.rows()));
  Eigen::MatrixX3d samples(sphere.vertices.rows() + model.knots.rows(), 3);
  samples << sphere.vertices, model.knots;
  const Eigen::MatrixX3d sums = surface->EvaluateMany(samples);
  return sums.col(0).maxCoeff();
}

// The nearest codes on the grid origin + code * step (a zero step: code 0),
// clamped to `bits` bits, the stored points and their largest displacement.
QuantizedControlPoints QuantizeOnGrid(const Eigen::MatrixX3d& points,
                                      const Eigen::Vector3d& origin,
                                      const Eigen::Vector3d& step, int bits) {
  QuantizedControlPoints out;
  ControlPointQuantization& q = out.quantization;
  q.bits = bits;
  q.origin = origin;
  q.step = step;
  const double top = std::ldexp(1.0, bits) - 1.0;
  const Eigen::Index rows = points.rows();
  out.codes.resize(3 * static_cast<size_t>(rows));
  for (int c = 0; c < 3; ++c) {
    for (Eigen::Index i = 0; i < rows; ++i) {
      const double t = step[c] > 0 ? (points(i, c) - origin[c]) / step[c] : 0.0;
      out.codes[c * rows + i] =
          static_cast<uint32_t>(std::clamp(std::round(t), 0.0, top));
    }
  }
  out.values = DequantizeControlPoints(q.origin, q.step, out.codes);
  q.max_displacement = (out.values - points).rowwise().norm().maxCoeff();
  return out;
}

// The control points' lower corner and extent, or why they cannot be
// quantized.
Status CheckQuantizable(const Eigen::MatrixX3d& points, Eigen::RowVector3d* lo,
                        Eigen::RowVector3d* extent) {
  if (points.rows() == 0 || !points.allFinite()) {
    return InvalidArgumentError(
        "cannot quantize: the model has no control points or a non-finite "
        "one");
  }
  *lo = points.colwise().minCoeff();
  *extent = points.colwise().maxCoeff() - *lo;
  if (!extent->allFinite()) {
    return InvalidArgumentError(
        "cannot quantize: the control points' bounding box is too large for "
        "a double");
  }
  return Status::Ok();
}

}  // namespace

Eigen::MatrixX3d DequantizeControlPoints(const Eigen::Vector3d& origin,
                                         const Eigen::Vector3d& step,
                                         const std::vector<uint32_t>& codes) {
  const Eigen::Index rows = static_cast<Eigen::Index>(codes.size() / 3);
  Eigen::MatrixX3d values(rows, 3);
  for (int c = 0; c < 3; ++c) {
    for (Eigen::Index i = 0; i < rows; ++i) {
      const double product = static_cast<double>(codes[c * rows + i]) * step[c];
      values(i, c) = origin[c] + product;
    }
  }
  return values;
}

StatusOr<QuantizedControlPoints> QuantizeControlPoints(const SplineModel& model,
                                                       int bits) {
  if (model.basis_form == BasisForm::kNormalized) {
    return QuantizeControlPoints(model, bits, 1.0, false);
  }
  StatusOr<double> max_sum = MeasureMaxBasisSum(model);
  if (!max_sum.ok()) return max_sum.status();
  return QuantizeControlPoints(model, bits, *max_sum, true);
}

StatusOr<QuantizedControlPoints> QuantizeControlPointsWithin(
    const SplineModel& model, double max_bound) {
  if (!(max_bound > 0) || !std::isfinite(max_bound)) {
    return InvalidArgumentError(
        "cannot quantize within a bound that is not finite and > 0");
  }
  const Eigen::MatrixX3d& points = model.control_points;
  Eigen::RowVector3d lo, extent;
  SDCB_RETURN_IF_ERROR(CheckQuantizable(points, &lo, &extent));
  double max_sum = 1.0;
  if (model.basis_form == BasisForm::kRaw) {
    StatusOr<double> measured = MeasureMaxBasisSum(model);
    if (!measured.ok()) return measured.status();
    max_sum = *measured;
  }
  const bool measured = model.basis_form == BasisForm::kRaw;
  // Rounding moves a point by at most half the cube's diagonal, s sqrt(3)/2;
  // shrink s while rounding in double overshoots.
  double step = 2 * max_bound / max_sum / std::sqrt(3.0);
  for (int attempt = 0; attempt < 64; ++attempt, step *= 1 - 1e-9) {
    const double largest = extent.maxCoeff() / step;
    if (!(largest < std::ldexp(1.0, kMaxQuantizationBits) - 1)) break;
    int bits = kMinQuantizationBits;
    while (std::ldexp(1.0, bits) - 1 < std::round(largest)) ++bits;
    Eigen::Vector3d steps;
    for (int c = 0; c < 3; ++c) steps[c] = extent[c] > 0 ? step : 0.0;
    QuantizedControlPoints q =
        QuantizeOnGrid(points, lo.transpose(), steps, bits);
    q.quantization.max_basis_sum = max_sum;
    q.quantization.basis_sum_measured = measured;
    if (q.quantization.surface_error_bound() <= max_bound) return q;
  }
  return InvalidArgumentError("cannot quantize the control points within " +
                              std::to_string(100 * max_bound) + " % in " +
                              std::to_string(kMaxQuantizationBits) + " bits");
}

StatusOr<QuantizedControlPoints> QuantizeControlPoints(const SplineModel& model,
                                                       int bits,
                                                       double max_basis_sum,
                                                       bool measured) {
  if (bits < kMinQuantizationBits || bits > kMaxQuantizationBits) {
    return InvalidArgumentError(
        "cannot quantize control points to " + std::to_string(bits) +
        " bits; " + std::to_string(kMinQuantizationBits) + ".." +
        std::to_string(kMaxQuantizationBits) + " are supported");
  }
  const Eigen::MatrixX3d& points = model.control_points;
  Eigen::RowVector3d lo, extent;
  SDCB_RETURN_IF_ERROR(CheckQuantizable(points, &lo, &extent));
  const double top = std::ldexp(1.0, bits) - 1.0;  // exact for bits <= 52
  QuantizedControlPoints out =
      QuantizeOnGrid(points, lo.transpose(), (extent / top).transpose(), bits);
  ControlPointQuantization& q = out.quantization;
  q.max_basis_sum = max_basis_sum;
  q.basis_sum_measured = measured;
  return out;
}

}  // namespace sdcb
