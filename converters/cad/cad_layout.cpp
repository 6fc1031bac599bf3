#include "sdcb/converters/cad/cad_layout.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <utility>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/tessellate/feature_pattern.h"

namespace sdcb {
namespace {

// Steps of the search for an order of the feature quads' corners.
constexpr int kMaxOrderSteps = 100000;
// Each quad's map is checked for folds on an n x n lattice.
constexpr int kCheckLattice = 9;

// tan(pi t / 4), exactly +-1 at t = +-1 (so a side's points are the same
// numbers seen from both quads).
double TanQuarter(double t) {
  if (t == 1.0) return 1.0;
  if (t == -1.0) return -1.0;
  return std::tan(0.25 * kPi * t);
}

// Cube face c: its normal axis and sign, and the cube axes of its u and v
// (right-handed with the outward normal).
struct CubeFace {
  int axis, sign, u_axis, v_axis;
};

CubeFace CubeFaceOf(int c) {
  CubeFace f;
  f.axis = c / 2;
  f.sign = c % 2 == 0 ? 1 : -1;
  const int i = (f.axis + 1) % 3, j = (f.axis + 2) % 3;
  f.u_axis = f.sign > 0 ? i : j;
  f.v_axis = f.sign > 0 ? j : i;
  return f;
}

// Whether quad q's map keeps its orientation (the derivatives' cross
// product points out) on a lattice that includes its sides.
bool MapIsOriented(const CadQuadLayout& layout, int q) {
  for (int j = 0; j < kCheckLattice; ++j) {
    for (int i = 0; i < kCheckLattice; ++i) {
      const double u = -1.0 + 2.0 * i / (kCheckLattice - 1);
      const double v = -1.0 + 2.0 * j / (kCheckLattice - 1);
      Eigen::Vector3d du, dv;
      const Eigen::Vector3d p = layout.Point(q, u, v, &du, &dv);
      if (!(du.cross(dv).dot(p) > 0.0)) return false;
    }
  }
  return true;
}

// The increasing direction of a quad's sides: side k runs from corner
// kSideFrom[k] to kSideTo[k].
constexpr int kSideFrom[4] = {0, 1, 3, 0};
constexpr int kSideTo[4] = {1, 2, 2, 3};

// Rotations of the 4-corner cycles (corner 0 of face f is cycle[rotation])
// under which every arc runs the same way in both its faces; empty if the
// search finds none within its budget.
std::vector<int> OrderQuadCorners(
    const std::vector<std::array<int, 4>>& cycles) {
  const int n = static_cast<int>(cycles.size());
  // Direction of every arc: +1 from its smaller corner, -1 from its larger.
  std::map<std::pair<int, int>, int> direction;
  std::vector<int> rotation(n, -1);
  int steps = 0;
  // Applies rotation r to face f, recording the directions it set.
  const auto apply = [&](int f, int r,
                         std::vector<std::pair<int, int>>* set) -> bool {
    for (int k = 0; k < 4; ++k) {
      const int a = cycles[f][(kSideFrom[k] + r) % 4];
      const int b = cycles[f][(kSideTo[k] + r) % 4];
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      const int d = a < b ? 1 : -1;
      auto [it, inserted] = direction.try_emplace(key, d);
      if (inserted) {
        set->push_back(key);
      } else if (it->second != d) {
        return false;
      }
    }
    return true;
  };
  // Depth-first over the faces in order.
  std::function<bool(int)> search = [&](int f) -> bool {
    if (f == n) return true;
    for (int r = 0; r < 4; ++r) {
      if (++steps > kMaxOrderSteps) return false;
      std::vector<std::pair<int, int>> set;
      if (apply(f, r, &set)) {
        rotation[f] = r;
        if (search(f + 1)) return true;
      }
      for (const auto& key : set) direction.erase(key);
    }
    return false;
  };
  if (!search(0)) return {};
  return rotation;
}

}  // namespace

Eigen::Vector3d CubeSpherePoint(int c, double u, double v, Eigen::Vector3d* du,
                                Eigen::Vector3d* dv) {
  const CubeFace f = CubeFaceOf(c);
  const double tu = TanQuarter(u), tv = TanQuarter(v);
  Eigen::Vector3d w;
  w[f.axis] = f.sign;
  w[f.u_axis] = tu;
  w[f.v_axis] = tv;
  const double length = w.norm();
  const Eigen::Vector3d p = w / length;
  const auto derivative = [&](int axis, double t) {
    Eigen::Vector3d dw = Eigen::Vector3d::Zero();
    dw[axis] = 0.25 * kPi * (1.0 + t * t);
    return Eigen::Vector3d((dw - p * p.dot(dw)) / length);
  };
  if (du != nullptr) *du = derivative(f.u_axis, tu);
  if (dv != nullptr) *dv = derivative(f.v_axis, tv);
  return p;
}

bool CadQuadLayout::has_creases() const {
  for (const auto& sides : crease) {
    for (const bool c : sides) {
      if (c) return true;
    }
  }
  return false;
}

const char* CadQuadLayout::name() const {
  return kind == Kind::kCubeSphere ? "cube-sphere" : "feature faces";
}

Eigen::Vector3d CadQuadLayout::Point(int q, double u, double v,
                                     Eigen::Vector3d* du,
                                     Eigen::Vector3d* dv) const {
  if (kind == Kind::kCubeSphere) return CubeSpherePoint(q, u, v, du, dv);
  const std::array<Eigen::Vector3d, 4>& c = corners[q];
  const double tu = TanQuarter(u), tv = TanQuarter(v);
  const double s = 0.5 * (1.0 + tu), r = 0.5 * (1.0 + tv);
  // Term by term, so that on a side the two vanishing terms add exact
  // zeros and both quads of the side compute the same numbers.
  const Eigen::Vector3d w = (1.0 - s) * (1.0 - r) * c[0] +
                            s * (1.0 - r) * c[1] + s * r * c[2] +
                            (1.0 - s) * r * c[3];
  const double length = w.norm();
  const Eigen::Vector3d p = w / length;
  const auto project = [&](const Eigen::Vector3d& dw) {
    return Eigen::Vector3d((dw - p * p.dot(dw)) / length);
  };
  if (du != nullptr) {
    const double ds = 0.125 * kPi * (1.0 + tu * tu);
    *du = project(ds * ((1.0 - r) * (c[1] - c[0]) + r * (c[2] - c[3])));
  }
  if (dv != nullptr) {
    const double dr = 0.125 * kPi * (1.0 + tv * tv);
    *dv = project(dr * ((1.0 - s) * (c[3] - c[0]) + s * (c[2] - c[1])));
  }
  return p;
}

CadQuadLayout CubeSphereLayout(int grid) {
  CadQuadLayout layout;
  layout.kind = CadQuadLayout::Kind::kCubeSphere;
  layout.grid = grid;
  for (int c = 0; c < 6; ++c) {
    const CubeFace f = CubeFaceOf(c);
    std::array<Eigen::Vector3d, 4> corners;
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector3d w;
      w[f.axis] = f.sign;
      w[f.u_axis] = k == 1 || k == 2 ? 1.0 : -1.0;
      w[f.v_axis] = k >= 2 ? 1.0 : -1.0;
      corners[k] = w;
    }
    layout.corners.push_back(corners);
    layout.crease.push_back({false, false, false, false});
  }
  return layout;
}

std::optional<CadQuadLayout> FeatureQuadLayout(const KnotFeatureArcs& arcs) {
  if (arcs.arcs.empty()) return std::nullopt;
  StatusOr<FeatureQuadMesh> quads =
      FeatureQuads(arcs.corner_directions, arcs.arcs, /*split=*/false);
  if (!quads.ok()) return std::nullopt;
  // Quads as they are need their corners ordered; cut ones start at a
  // feature corner, so every arc half runs from its corner and every inner
  // side from its midpoint, in both quads.
  std::vector<int> rotation(quads->quads.size(), 0);
  if (!quads->split) {
    rotation = OrderQuadCorners(quads->quads);
    if (rotation.empty()) {
      quads = FeatureQuads(arcs.corner_directions, arcs.arcs, /*split=*/true);
      if (!quads.ok()) return std::nullopt;
      rotation.assign(quads->quads.size(), 0);
    }
  }
  CadQuadLayout layout;
  layout.kind = CadQuadLayout::Kind::kFeatureFaces;
  layout.grid = 1;
  for (size_t q = 0; q < quads->quads.size(); ++q) {
    std::array<int, 4> c;
    for (int k = 0; k < 4; ++k) c[k] = quads->quads[q][(k + rotation[q]) % 4];
    std::array<Eigen::Vector3d, 4> corners;
    std::array<bool, 4> crease;
    for (int k = 0; k < 4; ++k) {
      corners[k] = quads->points.row(c[k]).transpose();
      const int a = c[kSideFrom[k]], b = c[kSideTo[k]];
      crease[k] = std::binary_search(
          quads->creases.begin(), quads->creases.end(),
          std::array<int, 2>{std::min(a, b), std::max(a, b)});
    }
    layout.corners.push_back(corners);
    layout.crease.push_back(crease);
  }
  for (int q = 0; q < layout.num_quads(); ++q) {
    if (!MapIsOriented(layout, q)) return std::nullopt;
  }
  return layout;
}

}  // namespace sdcb
