// Lossy storage of a model's control points on a uniform grid (the `.sdcb`
// QCTL chunk, docs/FORMAT.md), and the bound it gives on how far the surface
// moves.
//
// The bound. The stored surface is F'(p) = sum_i b_i(p) c'_i with
// |c'_i - c_i| <= D (D = max_displacement), so
//   |F'(p) - F(p)| = |sum_i b_i(p) (c'_i - c_i)| <= D * sum_i |b_i(p)|.
// - BasisForm::kNormalized: b_i = Bbar_i >= 0 with sum 1 (paper eq. 5), so
//   the surface moves by at most D everywhere: a true bound.
// - BasisForm::kRaw: b_i = B_i >= 0 with sum I(p) != 1 (eq. 4), so the bound
//   is D * max_p I(p). max I is MEASURED: the largest I at the vertices of an
//   icosphere (>= 40962 points, >= 32 per knot) and at the knots; between
//   samples I may exceed it by a small relative amount (I is smooth at the
//   scale of the knot spacing, which the samples resolve).
// Lengths are in the model's normalized frame, where the input's largest
// bounding-box side is 1, so 100 * length is percent of that side.
#ifndef SDCB_IO_SDCB_CONTROL_POINT_QUANTIZATION_H_
#define SDCB_IO_SDCB_CONTROL_POINT_QUANTIZATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// Bits per coordinate the quantizer accepts.
constexpr int kMinQuantizationBits = 1;
constexpr int kMaxQuantizationBits = 32;

struct ControlPointQuantization {
  // 0: control points stored exactly (the other fields are 0). Otherwise
  // kMinQuantizationBits..kMaxQuantizationBits bits per coordinate.
  int bits = 0;
  // The grid: coordinate c of a stored control point is
  // origin[c] + code * step[c] (IEEE double: one product, one sum), with the
  // integer code in [0, 2^bits - 1]. origin = lower corner of the control
  // points' bounding box, step = its extent / (2^bits - 1) (0 for a flat
  // axis), or for QuantizeControlPointsWithin the same step on every axis.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d step = Eigen::Vector3d::Zero();
  // D = max_i |c'_i - c_i|, the largest Euclidean distance between a fitted
  // and its stored control point (at most half the cell's diagonal).
  double max_displacement = 0.0;
  // max_p sum_i b_i(p): exactly 1 for the normalized basis; measured for the
  // raw basis (see above), and then basis_sum_measured is true.
  double max_basis_sum = 0.0;
  bool basis_sum_measured = false;

  bool lossless() const { return bits == 0; }
  // max_p |F'(p) - F(p)| <= this, normalized frame.
  double surface_error_bound() const {
    return max_displacement * max_basis_sum;
  }
  double surface_error_bound_percent() const {
    return 100.0 * surface_error_bound();
  }
};

struct QuantizedControlPoints {
  ControlPointQuantization quantization;
  // 3 * #control points grid codes, by coordinate: the x codes of all
  // control points in order, then the y codes, then the z codes.
  std::vector<uint32_t> codes;
  // #control points by 3: the stored control points c'_i (what a reader of
  // the file reconstructs).
  Eigen::MatrixX3d values;
};

// Quantizes model.control_points to `bits` bits per coordinate and states
// the bound above. Fails with kInvalidArgument for `bits` outside
// kMinQuantizationBits..kMaxQuantizationBits, a non-finite control point or a
// bounding box whose extent overflows a double; for a kRaw model, also if the
// surface cannot be built (SurfaceFromModel). Cost: linear in the control
// points; for kRaw plus one evaluation of the basis at the samples.
StatusOr<QuantizedControlPoints> QuantizeControlPoints(const SplineModel& model,
                                                       int bits);
// The same with max_p I(p) given (`max_basis_sum`, `measured` as in
// ControlPointQuantization): no evaluation of the basis.
StatusOr<QuantizedControlPoints> QuantizeControlPoints(const SplineModel& model,
                                                       int bits,
                                                       double max_basis_sum,
                                                       bool measured);

// The coarsest grid of cubic cells (the same step s on every axis that is
// not flat, origin the lower corner) whose surface_error_bound() is at most
// `max_bound` (normalized frame, > 0): s = 2 max_bound / (S sqrt(3)), since
// rounding moves a point by at most half the cube's diagonal; bits = the
// fewest that hold the largest code. kInvalidArgument as
// QuantizeControlPoints, or if that needs more than kMaxQuantizationBits.
// For kRaw the basis sum is measured once. Cost: linear in the control
// points.
StatusOr<QuantizedControlPoints> QuantizeControlPointsWithin(
    const SplineModel& model, double max_bound);

// c'_i from a grid and codes (laid out as QuantizedControlPoints::codes);
// codes.size() must be a multiple of 3.
Eigen::MatrixX3d DequantizeControlPoints(const Eigen::Vector3d& origin,
                                         const Eigen::Vector3d& step,
                                         const std::vector<uint32_t>& codes);

}  // namespace sdcb

#endif  // SDCB_IO_SDCB_CONTROL_POINT_QUANTIZATION_H_
