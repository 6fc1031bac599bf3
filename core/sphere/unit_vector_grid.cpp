#include "sdcb/core/sphere/unit_vector_grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sdcb {
namespace {

double Top(int bits) { return std::ldexp(1.0, bits) - 1.0; }

double SignOf(double x) { return x < 0 ? -1.0 : 1.0; }

}  // namespace

Eigen::Vector3d DecodeUnitVector(const UnitVectorCode& code, int bits) {
  const double top = Top(bits);
  const double u = (2.0 * code.a - top) / top;
  const double v = (2.0 * code.b - top) / top;
  double x = u, y = v;
  const double z = 1.0 - std::abs(u) - std::abs(v);
  if (z < 0) {
    x = (1.0 - std::abs(v)) * SignOf(u);
    y = (1.0 - std::abs(u)) * SignOf(v);
  }
  // + 0.0 turns -0 into +0: codes on the fold's edges that name the same
  // point give the same bits.
  x += 0.0;
  y += 0.0;
  const double norm = std::sqrt(std::fma(x, x, std::fma(y, y, z * z)));
  return Eigen::Vector3d(x / norm, y / norm, (z + 0.0) / norm);
}

UnitVectorCode EncodeUnitVector(const Eigen::Vector3d& direction, int bits) {
  const double l1 = direction.cwiseAbs().sum();
  double u = direction.x() / l1, v = direction.y() / l1;
  if (direction.z() < 0) {
    const double fu = (1.0 - std::abs(v)) * SignOf(u);
    const double fv = (1.0 - std::abs(u)) * SignOf(v);
    u = fu;
    v = fv;
  }
  const double top = Top(bits);
  auto grid = [&](double t) {
    return static_cast<uint32_t>(
        std::clamp(std::round((t + 1.0) * 0.5 * top), 0.0, top));
  };
  return {grid(u), grid(v)};
}

bool IsOnUnitVectorGrid(const Eigen::Vector3d& v, int bits,
                        UnitVectorCode* code) {
  if (!v.allFinite() || v.isZero()) return false;
  const UnitVectorCode c = EncodeUnitVector(v, bits);
  const Eigen::Vector3d decoded = DecodeUnitVector(c, bits);
  // Bit for bit (== would take -0 for +0).
  if (std::memcmp(decoded.data(), v.data(), sizeof(double) * 3) != 0) {
    return false;
  }
  if (code != nullptr) *code = c;
  return true;
}

}  // namespace sdcb
