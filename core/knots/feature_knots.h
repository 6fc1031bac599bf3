// Knots that keep the input's sharp corners and edges (docs/FITTING.md,
// "Creases from knots"). A spherical DCB-spline of degree k is C^(k+1-m)
// across a great circle that carries m knots of every configuration whose
// support crosses it: a crease (C0) needs k + 1 of them. A mesh edge's
// sphere image is a great-circle arc (the fit maps a triangle's points by
// the central projection of its flat sphere triangle), and so is a straight
// chain of edges under the central projection from a point of the solid. A
// cluster of knots at every feature corner, the corner's image and knots a
// hair along each of its feature curves, puts knots on the great circle of
// every feature arc between two corners: one knot per curve end gives a
// circle four, enough where the circle also holds the opposite edge's
// clusters (a cube whose faces' triangles map consistently, its
// parameterization the central projection, is reproduced with flat faces
// and sharp edges by these knots alone, degrees 2 to 4); k knots per end give
// a circle 2k + 2, enough for an arc alone on its circle (the tetrahedron).
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

// Whether every feature curve joins two corners: there are corners, and no
// curve is closed or ends elsewhere (what the clusters need, whatever the
// parameterization).
bool FeatureCurvesJoinCorners(const MeshFeatures& features);

// Whether the clusters can keep every feature under the parameterization
// `sphere` (#V by 3 unit vectors): FeatureCurvesJoinCorners, and every
// curve's vertices lie on the great circle through its two ends (within
// 1e-8 radians) between them, in order. A single edge always does; a chain
// of edges does when it is straight and the map is a central projection.
bool ClustersKeepEveryFeature(const MeshFeatures& features,
                              const Eigen::MatrixX3d& sphere);

// The clusters of `features`' corners: for every corner (in the order of
// features.corners) its sphere point and, for every feature edge at it (in
// the order of features.edges), `knots_per_edge` points gap, 2 gap, 4 gap,
// ... radians from it along the great circle toward the other end of the
// curve the edge begins. `sphere`: #V by 3 unit vectors, the vertices'
// parameters. Empty when there are no corners.
Eigen::MatrixX3d CornerKnotClusters(const MeshFeatures& features,
                                    const Eigen::MatrixX3d& sphere,
                                    double gap = kCornerClusterGap,
                                    int knots_per_edge = 1);

// The feature arcs a spline's knots hold: corners (knot rows) and the arcs
// between them. An arc joins corners a and b when each has a knot `gap`
// radians from it (within 2 %) and all four lie on one great circle in the
// order a, a's knot, b's knot, b, with no other corner between: what
// CornerKnotClusters makes for a feature arc. Empty when the knots hold none.
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
