#include "sdcb/converters/cad/bicubic_patch.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>

#include "sdcb/converters/cad/gauss_legendre.h"

namespace sdcb {

void CubicBernstein(double t, double b[4], double d[4]) {
  const double s = 1.0 - t;
  b[0] = s * s * s;
  b[1] = 3.0 * t * s * s;
  b[2] = 3.0 * t * t * s;
  b[3] = t * t * t;
  if (d != nullptr) {
    d[0] = -3.0 * s * s;
    d[1] = 3.0 * s * s - 6.0 * t * s;
    d[2] = 6.0 * t * s - 3.0 * t * t;
    d[3] = 3.0 * t * t;
  }
}

Eigen::Vector3d BicubicPatch::Evaluate(double u, double v, Eigen::Vector3d* du,
                                       Eigen::Vector3d* dv) const {
  double bu[4], bv[4], du_basis[4], dv_basis[4];
  CubicBernstein(u, bu, du_basis);
  CubicBernstein(v, bv, dv_basis);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d pu = Eigen::Vector3d::Zero(), pv = Eigen::Vector3d::Zero();
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d& pole = poles[4 * j + i];
      p += bu[i] * bv[j] * pole;
      pu += du_basis[i] * bv[j] * pole;
      pv += bu[i] * dv_basis[j] * pole;
    }
  }
  if (du != nullptr) *du = pu;
  if (dv != nullptr) *dv = pv;
  return p;
}

PatchSetMeasures MeasurePatchSet(const std::vector<BicubicPatch>& patches) {
  static const GaussLegendre<5> volume_rule;
  static const GaussLegendre<8> area_rule;
  // Per patch, then summed in patch order (deterministic).
  std::vector<PatchSetMeasures> each(patches.size());
  tbb::parallel_for(size_t{0}, patches.size(), [&](size_t p) {
    const BicubicPatch& patch = patches[p];
    PatchSetMeasures& m = each[p];
    for (int j = 0; j < 5; ++j) {
      for (int i = 0; i < 5; ++i) {
        Eigen::Vector3d du, dv;
        const Eigen::Vector3d x =
            patch.Evaluate(volume_rule.x[i], volume_rule.x[j], &du, &dv);
        m.volume += volume_rule.w[i] * volume_rule.w[j] * x.dot(du.cross(dv));
      }
    }
    m.volume /= 3.0;
    for (int j = 0; j < 8; ++j) {
      for (int i = 0; i < 8; ++i) {
        Eigen::Vector3d du, dv;
        patch.Evaluate(area_rule.x[i], area_rule.x[j], &du, &dv);
        m.area += area_rule.w[i] * area_rule.w[j] * du.cross(dv).norm();
      }
    }
  });
  PatchSetMeasures total;
  for (const PatchSetMeasures& m : each) {
    total.volume += m.volume;
    total.area += m.area;
  }
  return total;
}

Eigen::Vector2d QuadEdgeParameter(int k, double t) {
  switch (k) {
    case 0:
      return {t, 0.0};
    case 1:
      return {1.0, t};
    case 2:
      return {1.0 - t, 1.0};
    default:
      return {0.0, 1.0 - t};
  }
}

}  // namespace sdcb
