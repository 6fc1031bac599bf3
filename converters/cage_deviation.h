// How far a subdivision cage's limit surface is from a spherical spline,
// both ways, measured where nothing was fitted (docs/CAGE.md):
//
// - limit -> spline: the limit surface evaluated (OpenSubdiv Bfr) on a
//   lattice of level n in every cage face, n chosen for at least
//   `min_samples` points; each point's distance to the spline by the
//   spline's own closest-point search (core/fit/surface_deviation.h: the
//   nearest point of a dense image of the spline, then Gauss-Newton steps on
//   the exact spline), started also from the spline point the cage face maps
//   the parameter to. Area-weighted over the limit surface.
// - spline -> limit: the spline at the lattice of its knot triangles (at
//   least `min_samples` points); each point's closest point on the limit
//   lattice's triangles gives a face and (u, v), from which Newton steps on
//   the exact limit surface of that face go to the foot point. Area-weighted
//   over the spline.
//
// Every distance is to a point that lies on the exact other surface, so each
// figure is an upper bound of the true distance: pessimistic, never
// flattering.
#ifndef SDCB_CONVERTERS_CAGE_DEVIATION_H_
#define SDCB_CONVERTERS_CAGE_DEVIATION_H_

#include <Eigen/Core>
#include <cstdint>

#include "sdcb/converters/limit_surface.h"
#include "sdcb/core/cage/sphere_cage_topology.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

struct CageDeviationOptions {
  // The length that is 100 % (in the frame of the spline and the cage).
  double length_unit = 1.0;
  // Points on each surface at least.
  int min_samples = 100000;
  // Newton steps of the closest-point search on the limit surface.
  int newton_iterations = 5;
};

struct CageDeviation {
  double limit_to_spline_rms_percent = 0.0;
  double limit_to_spline_max_percent = 0.0;
  double spline_to_limit_rms_percent = 0.0;
  double spline_to_limit_max_percent = 0.0;
  // sqrt of the mean of the two mean squares; the larger maximum.
  double rms_percent = 0.0;
  double max_percent = 0.0;
  // Share of the spline's area where the limit surface faces the other way.
  double folded_area_percent = 0.0;
  int64_t limit_samples = 0;
  int64_t spline_samples = 0;
  int lattice_level = 0;  // per cage face
  // Per cage face: the limit -> spline rms and max (percent) and the
  // face's share of the squared error (area-weighted, sums to the total).
  Eigen::VectorXd face_rms_percent, face_max_percent, face_squared_error;
  // Every limit sample: face, (u, v), the limit point and its distance.
  std::vector<int> limit_sample_face;
  Eigen::MatrixX2d limit_sample_uv;
  Eigen::MatrixX3d limit_sample_points;
  Eigen::VectorXd limit_sample_distance_percent;
  // Every spline sample: the spline point and its distance to the limit.
  Eigen::MatrixX3d spline_sample_points;
  Eigen::VectorXd spline_sample_distance_percent;
};

// `cage`: #V by 3 cage positions of `limit`'s vertices. `sphere` (optional):
// the cage's sphere layout (one face per limit face), whose map gives a
// second start for the closest-point search of every limit sample.
StatusOr<CageDeviation> MeasureCageDeviation(
    const SphericalSpline& spline, const LimitSurface& limit,
    const Eigen::MatrixX3d& cage, const SphereCage* sphere = nullptr,
    const CageDeviationOptions& options = {});

// Newton steps toward the point of face `f` of the limit surface closest to
// `x`, from (*u, *v), staying in the face's parameter domain; updates (*u,
// *v) and returns the distance of the best point found.
double ClosestOnLimitFace(const LimitSurface& limit,
                          const Eigen::MatrixX3d& cage, int f,
                          const Eigen::Vector3d& x, int iterations, double* u,
                          double* v);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAGE_DEVIATION_H_
