// Per-vertex colors for value maps (`sdcb export --colors error|curvature`).
#ifndef SDCB_CONVERTERS_MESH_COLOR_RAMP_H_
#define SDCB_CONVERTERS_MESH_COLOR_RAMP_H_

#include <Eigen/Core>
#include <cstdint>

namespace sdcb {

// `values` mapped linearly from [lo, hi] onto a blue - white - red ramp
// (diverging, white at the middle) or a white - red ramp (sequential);
// values outside are clamped, NaN is grey.
Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3> ColorRamp(
    const Eigen::VectorXd& values, double lo, double hi, bool diverging);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_MESH_COLOR_RAMP_H_
