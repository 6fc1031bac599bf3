#include "sdcb/converters/mesh/color_ramp.h"

#include <algorithm>
#include <cmath>

namespace sdcb {

Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3> ColorRamp(
    const Eigen::VectorXd& values, double lo, double hi, bool diverging) {
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3> out(values.size(), 3);
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (!std::isfinite(v)) {
      out.row(i) << 128, 128, 128;
      continue;
    }
    const double t = hi > lo ? std::clamp((v - lo) / (hi - lo), 0.0, 1.0) : 0.5;
    double r, g, b;
    if (diverging) {
      // Blue (t = 0) -> white (t = 1/2) -> red (t = 1).
      const double s = 2.0 * t - 1.0;
      r = s < 0 ? 1.0 + s : 1.0;
      b = s > 0 ? 1.0 - s : 1.0;
      g = 1.0 - std::abs(s);
    } else {
      r = 1.0;
      g = b = 1.0 - t;
    }
    out.row(i) << static_cast<std::uint8_t>(std::lround(255 * r)),
        static_cast<std::uint8_t>(std::lround(255 * g)),
        static_cast<std::uint8_t>(std::lround(255 * b));
  }
  return out;
}

}  // namespace sdcb
