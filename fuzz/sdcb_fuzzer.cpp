// libFuzzer harness: the .sdcb model reader (ParseSdcbModel, every format
// version) followed by what `sdcb eval` and the converters do with each
// part: build the surface and evaluate positions, derivatives and
// curvatures at fixed directions (the axes, a generic direction and the
// first knot, which lies on knot lines), then map them to input
// coordinates; a kept part's mesh (KEPT chunk, meshoptimizer's codecs) must
// pass ValidateModelPart. The one-spline reader (ParseSdcb) must agree: it
// reads exactly the models of one untrimmed fitted part. Any sanitizer report
// is a finding; non-finite values are not (a model may overflow: the CLI
// refuses to write them).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sdcb/core/spline/model.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/sdcb/sdcb_file.h"

namespace {

void EvaluatePart(const sdcb::SplineModel& model) {
  const sdcb::StatusOr<sdcb::SphericalSpline> surface =
      sdcb::SurfaceFromModel(model);
  if (!surface.ok()) return;
  Eigen::MatrixX3d directions(8, 3);
  directions << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0.48,
      -0.6, 0.64, 0, 0, 0;
  directions.row(7) = model.knots.row(0);
  const Eigen::MatrixX3d positions = surface->EvaluateMany(directions);
  const Eigen::MatrixX3d in_input = model.transform.ToInput(positions);
  const double tolerance =
      1e-9 * model.control_points.cwiseAbs().maxCoeff() + 1e-300;
  for (Eigen::Index i = 0; i < directions.rows(); ++i) {
    const sdcb::SurfacePoint jet =
        surface->EvaluateDifferential(directions.row(i).transpose());
    // The two evaluation paths round differently but must agree to the
    // rounding of a convex combination of the control points; a
    // non-finite value (overflow) is not compared.
    for (int k = 0; k < 3; ++k) {
      const double a = jet.position[k], b = positions(i, k);
      if (std::isfinite(a) && std::isfinite(b) && std::abs(a - b) > tolerance) {
        __builtin_trap();
      }
    }
  }
  (void)in_input;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const sdcb::StatusOr<sdcb::Model> model = sdcb::ParseSdcbModel(bytes);
  if (!model.ok()) {
    if (model.status().message().empty()) __builtin_trap();
    return 0;
  }
  if (model->parts.empty()) __builtin_trap();
  for (const sdcb::ModelPart& part : model->parts) {
    if (part.kept) {
      if (!sdcb::ValidateModelPart(part).ok()) __builtin_trap();
    } else {
      EvaluatePart(part.spline);
    }
  }
  // The one-spline reader reads exactly the one-part untrimmed fitted models.
  const sdcb::StatusOr<sdcb::SplineModel> spline = sdcb::ParseSdcb(bytes);
  const bool one = model->parts.size() == 1 && !model->parts[0].trimmed() &&
                   model->parts[0].fitted();
  if (spline.ok() != one) __builtin_trap();
  if (!spline.ok() &&
      spline.status().code() != sdcb::StatusCode::kUnsupported) {
    __builtin_trap();
  }
  return 0;
}
