// Round 0 on the feature corners' knot clusters (core/knots/feature_knots.h):
// with FitOptions::keep_features, a solid whose feature curves join its
// corners tries those knots alone first, none placed by the density; on a
// solid whose faces all see its centroid, with the central projection as
// its parameterization (each face one projective map). A round that misses
// the target is tried once more with `degree` knots along each feature edge
// (an arc alone on its great circle needs k + 1 knots there for a crease:
// the tetrahedron), then dropped for an ordinary round 0 on the optimized
// parameterization.
#ifndef SDCB_CORE_FIT_FEATURE_ROUND_H_
#define SDCB_CORE_FIT_FEATURE_ROUND_H_

#include <Eigen/Core>

#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/fit_mesh.h"
#include "sdcb/core/knots/spherical_cvt.h"
#include "sdcb/core/mesh/feature_curves.h"

namespace sdcb {

class FeatureRound {
 public:
  // Plans the round on `features` (FitOptions::keep_features) when the
  // clusters keep every feature; may switch `fit` to the central
  // projection.
  void Plan(const MeshFeatures& features, FitMesh* fit);

  // Whether the next round is on the clusters.
  bool pending() const { return knots_.rows() > 0; }
  // The clusters' knots (empty unless pending()).
  const Eigen::MatrixX3d& knots() const { return knots_; }

  // After a round on the clusters that missed the target or could not be
  // built: the clusters with `degree` knots along each feature edge when
  // the round had one, else no round on them, and `fit` back on the
  // optimized parameterization.
  void Drop(const MeshFeatures& features, int degree, FitMesh* fit);

 private:
  Eigen::MatrixX3d knots_;
  int knots_per_edge_ = 0;
  // The optimized parameterization while the round uses the central
  // projection (empty otherwise).
  Eigen::MatrixX3d default_u_;
};

// The round's knot placement: the clusters' knots alone.
KnotPlacement FeatureKnotPlacement(const Eigen::MatrixX3d& knots);

// The sphere points (rows of `u`) of the feature corners.
Eigen::MatrixX3d FeatureCorners(const MeshFeatures& features,
                                const Eigen::MatrixX3d& u);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FEATURE_ROUND_H_
