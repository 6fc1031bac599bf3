#include "sdcb/core/knots/feature_knots.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"

namespace sdcb {

bool FeatureCurvesJoinCorners(const MeshFeatures& features) {
  if (features.corners.empty()) return false;
  const auto is_corner = [&](int v) {
    return std::binary_search(features.corners.begin(), features.corners.end(),
                              v);
  };
  for (const FeatureCurve& curve : features.curves) {
    if (curve.closed || curve.vertices.size() < 2 ||
        !is_corner(curve.vertices.front()) ||
        !is_corner(curve.vertices.back())) {
      return false;
    }
  }
  return true;
}

bool ClustersKeepEveryFeature(const MeshFeatures& features,
                              const Eigen::MatrixX3d& sphere) {
  if (!FeatureCurvesJoinCorners(features)) return false;
  constexpr double kOffArc = 1e-8;  // radians
  for (const FeatureCurve& curve : features.curves) {
    const Eigen::Vector3d a = sphere.row(curve.vertices.front());
    const Eigen::Vector3d b = sphere.row(curve.vertices.back());
    const Eigen::Vector3d normal = a.cross(b);
    if (!(normal.norm() > 0)) return false;
    const Eigen::Vector3d pole = normal.normalized();
    const Eigen::Vector3d along = pole.cross(a);
    const auto phase = [&](const Eigen::Vector3d& x) {
      return std::atan2(x.dot(along), x.dot(a));
    };
    double last = 0.0;
    for (size_t i = 1; i < curve.vertices.size(); ++i) {
      const Eigen::Vector3d x = sphere.row(curve.vertices[i]);
      const double t = phase(x);
      if (std::abs(pole.dot(x)) > kOffArc || !(t > last)) return false;
      last = t;
    }
  }
  return true;
}

Eigen::MatrixX3d CornerKnotClusters(const MeshFeatures& features,
                                    const Eigen::MatrixX3d& sphere, double gap,
                                    int knots_per_edge) {
  // The far end of the curve that begins with the edge (end, next).
  std::map<std::pair<int, int>, int> far_end;
  for (const FeatureCurve& curve : features.curves) {
    const std::vector<int>& v = curve.vertices;
    if (curve.closed || v.size() < 2) continue;
    far_end[{v.front(), v[1]}] = v.back();
    far_end[{v.back(), v[v.size() - 2]}] = v.front();
  }
  std::vector<Eigen::Vector3d> knots;
  for (const int corner : features.corners) {
    const Eigen::Vector3d a = sphere.row(corner).transpose();
    knots.push_back(a);
    for (const std::array<int, 2>& edge : features.edges) {
      if (edge[0] != corner && edge[1] != corner) continue;
      const int next = edge[0] == corner ? edge[1] : edge[0];
      const auto it = far_end.find({corner, next});
      const Eigen::Vector3d b =
          sphere.row(it != far_end.end() ? it->second : next).transpose();
      // The unit tangent at a of the great circle toward b.
      const Eigen::Vector3d toward = b - a.dot(b) * a;
      if (!(toward.norm() > 0)) continue;
      double at = gap;
      for (int k = 0; k < knots_per_edge; ++k, at *= 2.0) {
        knots.push_back(std::cos(at) * a + std::sin(at) * toward.normalized());
      }
    }
  }
  Eigen::MatrixX3d out(knots.size(), 3);
  for (size_t i = 0; i < knots.size(); ++i) {
    out.row(static_cast<Eigen::Index>(i)) = knots[i].transpose();
  }
  return out;
}

KnotFeatureArcs FeatureArcsOfKnots(const Eigen::MatrixX3d& knots, double gap) {
  const int n = static_cast<int>(knots.rows());
  const auto angle = [&](int a, int b) {
    const Eigen::Vector3d x = knots.row(a), y = knots.row(b);
    return std::atan2(x.cross(y).norm(), x.dot(y));
  };
  // Pairs of knots about `gap` apart, both ways: knots sorted by
  // z, each compared with those within the gap in z.
  std::vector<int> by_z(n);
  for (int i = 0; i < n; ++i) by_z[i] = i;
  std::sort(by_z.begin(), by_z.end(), [&](int a, int b) {
    return knots(a, 2) < knots(b, 2) || (knots(a, 2) == knots(b, 2) && a < b);
  });
  const double lo = 0.98 * gap, hi = 1.02 * gap;
  std::vector<std::array<int, 2>> pairs;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const int a = by_z[i], b = by_z[j];
      if (knots(b, 2) - knots(a, 2) > hi) break;
      const double d = angle(a, b);
      if (d >= lo && d <= hi) {
        pairs.push_back({a, b});
        pairs.push_back({b, a});
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  // Corners: at least three knots at the gap (a corner of a solid ends three
  // or more edges), each with fewer such knots of its own (a knot beside a
  // corner has the corner, and its siblings only where two feature edges
  // meet at 60 degrees or less).
  std::vector<int> degree(n, 0);
  for (const auto& pair : pairs) ++degree[pair[0]];
  std::vector<char> corner(n, 0);
  for (int k = 0; k < n; ++k) corner[k] = degree[k] >= 3;
  for (const auto& [a, b] : pairs) {
    if (degree[b] >= degree[a]) corner[a] = 0;
  }
  pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                             [&](const std::array<int, 2>& pair) {
                               return !corner[pair[0]];
                             }),
              pairs.end());
  // Pairs (a, a') and (b, b') on one great circle in the order a, a', b', b.
  constexpr double kOffCircle = 1e-7;    // radians
  std::vector<std::array<int, 2>> arcs;  // knot rows, a < b
  for (const auto& [a, a_knot] : pairs) {
    const Eigen::Vector3d pa = knots.row(a), pk = knots.row(a_knot);
    const Eigen::Vector3d pole = pa.cross(pk).normalized();
    for (const auto& [b, b_knot] : pairs) {
      if (b <= a || b == a_knot || b_knot == a) continue;
      const Eigen::Vector3d pb = knots.row(b), pl = knots.row(b_knot);
      if (std::abs(pole.dot(pb)) > kOffCircle ||
          std::abs(pole.dot(pl)) > kOffCircle) {
        continue;
      }
      // Along the circle from a toward a's knot: a's knot, b's knot, b,
      // within half a turn.
      const Eigen::Vector3d along = pole.cross(pa);
      const auto phase = [&](const Eigen::Vector3d& x) {
        return std::atan2(x.dot(along), x.dot(pa));
      };
      const double tk = phase(pk), tl = phase(pl), tb = phase(pb);
      if (!(tk > 0 && tk < tl && tl < tb && tb < kPi)) continue;
      // No corner between the two: the arc is one feature curve (the
      // knots between are the clusters' further knots along it).
      bool between = false;
      for (int k = 0; k < n && !between; ++k) {
        const Eigen::Vector3d x = knots.row(k);
        if (!corner[k] || std::abs(pole.dot(x)) > kOffCircle) continue;
        const double t = phase(x);
        between = t > 0 && t < tb && k != a && k != b;
      }
      if (!between) arcs.push_back({a, b});
    }
  }
  std::sort(arcs.begin(), arcs.end());
  arcs.erase(std::unique(arcs.begin(), arcs.end()), arcs.end());
  KnotFeatureArcs out;
  for (const auto& arc : arcs) {
    out.corners.push_back(arc[0]);
    out.corners.push_back(arc[1]);
  }
  std::sort(out.corners.begin(), out.corners.end());
  out.corners.erase(std::unique(out.corners.begin(), out.corners.end()),
                    out.corners.end());
  const auto index = [&](int knot) {
    return static_cast<int>(
        std::lower_bound(out.corners.begin(), out.corners.end(), knot) -
        out.corners.begin());
  };
  for (const auto& arc : arcs)
    out.arcs.push_back({index(arc[0]), index(arc[1])});
  out.corner_directions.resize(out.corners.size(), 3);
  for (size_t c = 0; c < out.corners.size(); ++c) {
    out.corner_directions.row(c) = knots.row(out.corners[c]).normalized();
  }
  return out;
}

}  // namespace sdcb
