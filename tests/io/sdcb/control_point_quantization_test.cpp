// Tests io/sdcb/control_point_quantization.* and the quantized `.sdcb` file:
// the surface of the stored (quantized) control points, evaluated at many
// random points, stays within the stated bound of the surface of the exact
// ones, and the bound is not absurdly loose. Oracle: the two surfaces evaluated
// by SphericalSpline, and the displacement of each control point computed here.
#include "sdcb/io/sdcb/control_point_quantization.h"

#include <gtest/gtest.h>

#include <random>

#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/spline_model_fixture.h"

namespace sdcb {
namespace {

// Degree-3 model on `knots` random knots with control points in
// [-0.6, 0.6]^3 (configurations from the brute-force oracle).
SplineModel RandomModel(int knots, BasisForm form) {
  SplineModel m = testing::MakeTestModel(3, knots, 0, 17);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  for (Eigen::Index i = 0; i < m.control_points.rows(); ++i) {
    for (int c = 0; c < 3; ++c) m.control_points(i, c) = u(rng);
  }
  m.basis_form = form;
  return m;
}

struct Deviation {
  double max_surface = 0;    // max over the samples of |F'(p) - F(p)|
  double max_basis_sum = 0;  // max over the samples of sum_i b_i(p)
};

// Evaluates both models at `samples` random directions.
Deviation MeasureDeviation(const SplineModel& exact, const SplineModel& stored,
                           int samples) {
  const Eigen::MatrixX3d p = testing::RandomUnitVectors(samples, 99);
  StatusOr<SphericalSpline> f = SurfaceFromModel(exact);
  StatusOr<SphericalSpline> g = SurfaceFromModel(stored);
  EXPECT_TRUE(f.ok() && g.ok());
  Deviation d;
  d.max_surface =
      (g->EvaluateMany(p) - f->EvaluateMany(p)).rowwise().norm().maxCoeff();
  SplineModel ones = exact;
  ones.control_points.setOnes();
  StatusOr<SphericalSpline> sum = SurfaceFromModel(ones);
  EXPECT_TRUE(sum.ok());
  d.max_basis_sum = sum->EvaluateMany(p).col(0).maxCoeff();
  return d;
}

TEST(ControlPointQuantizationTest, StatedDisplacementIsTheTrueOne) {
  const SplineModel model = RandomModel(30, BasisForm::kNormalized);
  for (int bits : {1, 4, 8, 16, 24, 32}) {
    const StatusOr<QuantizedControlPoints> q =
        QuantizeControlPoints(model, bits);
    ASSERT_TRUE(q.ok()) << q.status().message();
    const ControlPointQuantization& g = q->quantization;
    const double top = std::ldexp(1.0, bits) - 1;
    double largest = 0;
    for (Eigen::Index i = 0; i < model.control_points.rows(); ++i) {
      for (int c = 0; c < 3; ++c) {
        const uint32_t code = q->codes[c * model.control_points.rows() + i];
        EXPECT_LE(code, top);
        EXPECT_EQ(q->values(i, c), g.origin[c] + code * g.step[c]);
      }
      largest = std::max(
          largest, (q->values.row(i) - model.control_points.row(i)).norm());
    }
    EXPECT_EQ(g.max_displacement, largest) << bits;
    // Rounding to the nearest grid point: at most half the cell diagonal.
    EXPECT_LE(g.max_displacement, 0.5 * g.step.norm() * (1 + 1e-9) + 1e-16);
    EXPECT_EQ(g.max_basis_sum, 1.0);
    EXPECT_FALSE(g.basis_sum_measured);
    EXPECT_EQ(g.surface_error_bound(), g.max_displacement);
  }
}

TEST(ControlPointQuantizationTest, NormalizedSurfaceStaysWithinTheBound) {
  const SplineModel model = RandomModel(60, BasisForm::kNormalized);
  for (int bits : {8, 12, 16}) {
    SdcbFileInfo info;
    const StatusOr<std::string> file =
        SerializeSdcb(model, {false, bits}, &info);
    ASSERT_TRUE(file.ok()) << file.status().message();
    const StatusOr<SplineModel> stored = ParseSdcb(*file);
    ASSERT_TRUE(stored.ok()) << stored.status().message();
    const double bound = info.quantization.surface_error_bound();
    const Deviation d = MeasureDeviation(model, *stored, 20000);
    EXPECT_NEAR(d.max_basis_sum, 1.0, 1e-12);
    // Within the bound (up to the rounding of two evaluations)...
    EXPECT_LE(d.max_surface, bound + 1e-13) << bits;
    // ... and the bound is not loose: the worst sample moves by most of it
    // (measured: 0.70, 0.66, 0.82 of it for 8, 12, 16 bits).
    EXPECT_GE(d.max_surface, 0.3 * bound) << bits;
  }
}

TEST(ControlPointQuantizationTest, RawSurfaceStaysWithinTheMeasuredBound) {
  const SplineModel model = RandomModel(60, BasisForm::kRaw);
  const StatusOr<QuantizedControlPoints> q = QuantizeControlPoints(model, 12);
  ASSERT_TRUE(q.ok()) << q.status().message();
  const ControlPointQuantization& g = q->quantization;
  EXPECT_TRUE(g.basis_sum_measured);
  SplineModel stored = model;
  stored.control_points = q->values;
  const Deviation d = MeasureDeviation(model, stored, 20000);
  // I = sum B_i is not 1 for the raw basis; the measured maximum (icosphere
  // samples) must hold at 20000 other points too.
  EXPECT_GT(std::abs(g.max_basis_sum - 1.0), 1e-3);
  EXPECT_LE(d.max_basis_sum, g.max_basis_sum * (1 + 1e-6));
  EXPECT_GE(d.max_basis_sum, g.max_basis_sum * 0.99);
  EXPECT_LE(d.max_surface, g.surface_error_bound() + 1e-13);
  // Measured: the worst sample moves by 0.54 of the bound (max I = 2.2).
  EXPECT_GE(d.max_surface, 0.2 * g.surface_error_bound());
  // The file states the same bound.
  SdcbFileInfo info;
  const StatusOr<std::string> file = SerializeSdcb(model, {false, 12}, &info);
  ASSERT_TRUE(file.ok());
  SdcbFileInfo read;
  ASSERT_TRUE(ParseSdcb(*file, &read).ok());
  EXPECT_EQ(read.quantization.max_basis_sum, g.max_basis_sum);
  EXPECT_EQ(read.quantization.surface_error_bound(), g.surface_error_bound());
  EXPECT_TRUE(read.quantization.basis_sum_measured);
}

TEST(ControlPointQuantizationTest, FlatAxisIsExact) {
  SplineModel model = RandomModel(20, BasisForm::kNormalized);
  model.control_points.col(1).setConstant(0.25);
  const StatusOr<QuantizedControlPoints> q = QuantizeControlPoints(model, 8);
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q->quantization.step[1], 0.0);
  EXPECT_TRUE((q->values.col(1).array() == 0.25).all());
}

TEST(ControlPointQuantizationTest, RefusesWhatItCannotQuantize) {
  SplineModel model = RandomModel(20, BasisForm::kNormalized);
  for (int bits : {0, -3, 33}) {
    EXPECT_EQ(QuantizeControlPoints(model, bits).status().code(),
              StatusCode::kInvalidArgument);
  }
  model.control_points(0, 0) = 1e308;
  model.control_points(1, 0) = -1e308;
  EXPECT_EQ(QuantizeControlPoints(model, 8).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
