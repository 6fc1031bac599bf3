// Knots that keep the input's sharp corners and edges (docs/FITTING.md,
// "Creases from knots"). A spherical DCB-spline of degree k is C^(k+1-m)
// across a great circle that carries m knots of every configuration whose
// support crosses it. A mesh edge's sphere image is a great-circle arc (the
// fit maps a triangle's points by the central projection of its flat sphere
// triangle), so a cluster of knots at every feature corner, the corner's
// image and one knot a hair along each of its feature edges, puts four
// knots on the great circle of every feature edge between two corners: a
// cube whose faces' triangles map consistently (its parameterization the
// central projection) is reproduced with flat faces and sharp edges by
// these knots alone (degrees 2 to 4).
#ifndef SDCB_CORE_KNOTS_FEATURE_KNOTS_H_
#define SDCB_CORE_KNOTS_FEATURE_KNOTS_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "sdcb/core/mesh/feature_curves.h"

namespace sdcb {

// The distance (radians) from a corner's knot to the knots of its cluster:
// twice the knot placement's smallest separation (CvtOptions::min_separation,
// 1e-4), far below the knot spacing a fit reaches.
inline constexpr double kCornerClusterGap = 2e-4;

// Whether the clusters can keep every feature: there are corners, and every
// feature curve is a single mesh edge between two of them (its sphere image
// one great-circle arc whose circle the two clusters give four knots). A
// curve through other vertices bends on the sphere at each of them.
bool ClustersKeepEveryFeature(const MeshFeatures& features);

// The clusters of `features`' corners: for every corner (in the order of
// features.corners) its sphere point and, for every feature edge at it (in
// the order of features.edges), the point `gap` radians from it along the
// great circle toward the edge's other end. `sphere`: #V by 3 unit vectors,
// the vertices' parameters. Empty when there are no corners.
Eigen::MatrixX3d CornerKnotClusters(const MeshFeatures& features,
                                    const Eigen::MatrixX3d& sphere,
                                    double gap = kCornerClusterGap);

// The feature arcs a spline's knots hold: corners (knot rows) and the arcs
// between them. An arc joins corners a and b when each has a knot `gap`
// radians from it (within 2 %) and all four lie on one great circle in the
// order a, a's knot, b's knot, b, with no other knot between: what
// CornerKnotClusters makes for a feature edge. Empty when the knots hold none.
// Deterministic.
struct KnotFeatureArcs {
  std::vector<int> corners;              // knot rows, ascending
  Eigen::MatrixX3d corner_directions;    // their knots, unit length
  std::vector<std::array<int, 2>> arcs;  // indices into corners, a < b
};
KnotFeatureArcs FeatureArcsOfKnots(const Eigen::MatrixX3d& knots,
                                   double gap = kCornerClusterGap);

}  // namespace sdcb

#endif  // SDCB_CORE_KNOTS_FEATURE_KNOTS_H_
