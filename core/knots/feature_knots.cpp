#include "sdcb/core/knots/feature_knots.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sdcb {

bool ClustersKeepEveryFeature(const MeshFeatures& features) {
  if (features.corners.empty()) return false;
  for (const FeatureCurve& curve : features.curves) {
    if (curve.closed || curve.vertices.size() != 2) return false;
    for (const int end : curve.vertices) {
      if (!std::binary_search(features.corners.begin(), features.corners.end(),
                              end)) {
        return false;
      }
    }
  }
  return true;
}

Eigen::MatrixX3d CornerKnotClusters(const MeshFeatures& features,
                                    const Eigen::MatrixX3d& sphere,
                                    double gap) {
  std::vector<Eigen::Vector3d> knots;
  for (const int corner : features.corners) {
    const Eigen::Vector3d a = sphere.row(corner).transpose();
    knots.push_back(a);
    for (const std::array<int, 2>& edge : features.edges) {
      if (edge[0] != corner && edge[1] != corner) continue;
      const Eigen::Vector3d b =
          sphere.row(edge[0] == corner ? edge[1] : edge[0]).transpose();
      // The unit tangent at a of the great circle toward b.
      const Eigen::Vector3d toward = b - a.dot(b) * a;
      if (!(toward.norm() > 0)) continue;
      knots.push_back(std::cos(gap) * a + std::sin(gap) * toward.normalized());
    }
  }
  Eigen::MatrixX3d out(knots.size(), 3);
  for (size_t i = 0; i < knots.size(); ++i) {
    out.row(static_cast<Eigen::Index>(i)) = knots[i].transpose();
  }
  return out;
}

}  // namespace sdcb
