// How far a subdivision cage's limit surface is from a spherical spline,
// both ways, measured where nothing was fitted (docs/CAGE.md). Both
// surfaces are sampled on one lattice of level n in every cage face (n
// chosen for at least `min_samples` points): the limit surface (OpenSubdiv
// Bfr) at the face's parameters (u, v), the spline at the face's sphere
// points (SphereCage::SpherePoint of the same (u, v)).
//
// - limit -> spline: each limit point's distance to the spline by a
//   closest-point search on the spline
//   (core/measure/closest_surface_points.h) from its sphere point, and where
//   that ends more than 1 % farther than its nearest point on an image of the
//   spline (SplineImage) plus half that image's chord there, or farther than
//   the spline at that point's sphere point, again from that sphere point; the
//   nearer result counts. Area-weighted over the limit surface.
// - spline -> limit: each spline point's nearest point on the limit
//   lattice's triangles gives a face and (u, v), from which Newton steps on
//   the exact limit surface of that face go to the foot point (or the
//   limit point of the sample's own (u, v) is nearer). Area-weighted over
//   the spline.
//
// Every distance is to a point that lies on the exact other surface, so each
// figure is an upper bound of the true distance: pessimistic, never
// flattering.
#ifndef SDCB_CONVERTERS_CAGE_CAGE_DEVIATION_H_
#define SDCB_CONVERTERS_CAGE_CAGE_DEVIATION_H_

#include <Eigen/Core>
#include <cstdint>

#include "sdcb/converters/cage/limit_surface.h"
#include "sdcb/core/cage/sphere_cage_topology.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct CageDeviationOptions {
  // The length that is 100 % (in the frame of the spline and the cage).
  double length_unit = 1.0;
  // Points on each surface at least.
  int min_samples = 100000;
  // Newton steps of the closest-point search on the limit surface, and
  // Gauss-Newton steps of that on the spline.
  int newton_iterations = 5;
  int spline_iterations = 6;
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
  // Limit samples whose search was run again from the spline's lattice
  // image.
  int64_t limit_searches_from_image = 0;
  int lattice_level = 0;  // per cage face
  // Per cage face: the limit -> spline rms and max (percent) and the
  // face's share of the squared error (area-weighted, sums to the total).
  Eigen::VectorXd face_rms_percent, face_max_percent, face_squared_error;
  // Every limit sample: face, (u, v), the limit point and its distance.
  std::vector<int> limit_sample_face;
  Eigen::MatrixX2d limit_sample_uv;
  Eigen::MatrixX3d limit_sample_points;
  Eigen::VectorXd limit_sample_distance_percent;
  // Every spline sample (at the limit samples' faces and (u, v)): the
  // spline point and its distance to the limit.
  Eigen::MatrixX3d spline_sample_points;
  Eigen::VectorXd spline_sample_distance_percent;
};

// The spline's image of an icosphere (core/mesh/icosphere.h) with an AABB
// tree: where closest-point searches on the spline start. It does not
// depend on the cage, so a fit builds it once for all its rounds.
class SplineImage {
 public:
  // `level` 0..9 (10 * 4^level + 2 points).
  static StatusOr<SplineImage> Create(const SurfaceSampler& spline,
                                      int level = 6);
  // The sphere point of the image's point nearest to `x` (barycentric on
  // its triangle), that distance, and the distance between that triangle's
  // centroid and the spline at the centroid's sphere point (how far the
  // image can be from the spline there, sampled).
  Eigen::Vector3d NearestDirection(const Eigen::Vector3d& x, double* distance,
                                   double* chord) const;

 private:
  SplineImage(TriangleMesh sphere, TriangleMesh image, MeshDistance tree,
              Eigen::VectorXd chord)
      : sphere_(std::move(sphere)),
        image_(std::move(image)),
        tree_(std::move(tree)),
        chord_(std::move(chord)) {}
  TriangleMesh sphere_, image_;
  MeshDistance tree_;
  Eigen::VectorXd chord_;  // per triangle
};

// `spline`: the spline (a PiecewiseSplineSampler: positions and unit
// normals). `cage`: #V by 3 cage positions of `limit`'s vertices. `sphere`:
// the cage's sphere layout (one face per limit face). `image`: the spline's
// SplineImage, made here (level 6) if null. Deterministic for any thread
// count.
StatusOr<CageDeviation> MeasureCageDeviation(
    const SurfaceSampler& spline, const LimitSurface& limit,
    const Eigen::MatrixX3d& cage, const SphereCage& sphere,
    const CageDeviationOptions& options = {},
    const SplineImage* image = nullptr);

// Gauss-Newton steps (core/measure/closest_surface_points.h:
// GaussNewtonClosest, steps not shortened) toward the point of face `f` of
// the limit surface closest to `x`, from (*u, *v), staying in the face's
// parameter domain; updates (*u, *v) and returns the distance of the best
// point found.
double ClosestOnLimitFace(const PreparedLimit& limit, int f,
                          const Eigen::Vector3d& x, int iterations, double* u,
                          double* v);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAGE_CAGE_DEVIATION_H_
