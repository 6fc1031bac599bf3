#include "sdcb/core/fit/feature_round.h"

#include <optional>
#include <utility>

#include "sdcb/core/knots/feature_knots.h"
#include "sdcb/core/param/central_projection.h"

namespace sdcb {

void FeatureRound::Plan(const MeshFeatures& features, FitMesh* fit) {
  if (!FeatureCurvesJoinCorners(features)) return;
  std::optional<Eigen::MatrixX3d> central = CentralProjection(fit->mesh);
  if (!ClustersKeepEveryFeature(features, central ? *central : fit->u)) return;
  if (central) {
    default_u_ = std::move(fit->u);
    fit->UseParameters(std::move(*central));
  }
  knots_per_edge_ = 1;
  knots_ = CornerKnotClusters(features, fit->u);
}

void FeatureRound::Drop(const MeshFeatures& features, int degree,
                        FitMesh* fit) {
  if (knots_per_edge_ < degree) {
    knots_per_edge_ = degree;
    knots_ = CornerKnotClusters(features, fit->u, kCornerClusterGap,
                                knots_per_edge_);
  } else {
    knots_.resize(0, 3);
    if (default_u_.rows() > 0) {
      fit->UseParameters(std::move(default_u_));
      default_u_.resize(0, 3);
    }
  }
}

KnotPlacement FeatureKnotPlacement(const Eigen::MatrixX3d& knots) {
  KnotPlacement placement;
  placement.knots = knots;
  placement.min_separation = kCornerClusterGap;
  return placement;
}

Eigen::MatrixX3d FeatureCorners(const MeshFeatures& features,
                                const Eigen::MatrixX3d& u) {
  const std::vector<int>& corners = features.corners;
  Eigen::MatrixX3d out(corners.size(), 3);
  for (size_t c = 0; c < corners.size(); ++c) out.row(c) = u.row(corners[c]);
  return out;
}

}  // namespace sdcb
