// The adaptive fitting driver (paper Algorithm 2): parameterize the mesh on
// the sphere, place knots where the surface bends (round 0) or where the fit
// is worst (later rounds) by a spherical CVT, build the degree-k DCB basis on
// the knots' Delaunay configurations, solve for the control points by
// regularized least squares, and repeat until the RMSE reaches the target.
//
// Errors are in percent of the largest side of the input's bounding box
// (DESIGN.md): the fit works in the normalized frame of
// ComputeNormalizingTransform, where that side is 1.
#ifndef SDCB_CORE_FIT_ADAPTIVE_FIT_H_
#define SDCB_CORE_FIT_ADAPTIVE_FIT_H_

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

struct FitOptions {
  int degree = 4;                  // k, 2..5
  double rmse_percent = 0.05;      // stop when the RMSE is at most this
  int knots_per_round = 100;       // K: new knots per round (paper: 100)
  int initial_knots = 0;           // knots of round 0; 0 = knots_per_round
  int max_rounds = 30;             // rounds at most (round 0 included)
  int max_control_points = 50000;  // stop before exceeding this
  double lambda = 1.0;             // parameterization, eq. (12)
  double alpha = 4.0;              // density exponent (Sec. 4.4)
  double regularization = 1e-6;    // core/fit/least_squares.h
  int threads = 0;                 // 0 = all cores; results do not depend on it
  bool store_parameters = true;    // keep the sphere point of every vertex
  // Fit the mesh's piecewise-linear surface, not only its vertices: the
  // least squares also samples every triangle's centroid (at the normalized
  // sum of its corners' sphere points). Without it, basis functions seen by
  // few vertices make the surface wave between them while the vertex errors
  // stay small. Errors are still reported at the vertices. Intermediate
  // rounds fit the vertices only (they just steer the next knots); the round
  // that reaches the target (or the last) is refitted with the centroids.
  bool face_samples = true;
  // Least-squares weight of a centroid row relative to a vertex row. There
  // are about twice as many triangles as vertices; 0.3 keeps the surface on
  // the mesh between vertices (max centroid error within 1.5x the max vertex
  // error on bunny00, cow, fandisk_large) while it raises the vertex RMSE
  // only slightly over a vertex-only fit (docs/FITTING.md).
  double face_weight = 0.3;
  // Called with a stage name and the finished fraction of the whole fit
  // (estimated), in [0, 1].
  std::function<void(const std::string& stage, double fraction)> progress;
};

// What one round did, beyond the model's RoundStatistics.
struct RoundDetails {
  StageTimings timings;  // this round's seconds per stage (no parameterization)
  double cvt_initial_energy = 0;  // CVT energy of the round's knot placement
  double cvt_final_energy = 0;
  int cvt_iterations = 0;
  double min_knot_separation = 0;  // radians
  // Basis functions identical to one of the previous round, whose values
  // were reused rather than evaluated.
  int reused_basis_functions = 0;
  // Whether this round's solution includes the triangle-centroid rows
  // (FitOptions::face_samples): the returned round always does.
  bool face_samples = false;
};

struct FitResult {
  // The model. Its statistics carry no wall-clock times (all seconds are 0)
  // so that the same input and options give the same model bytes.
  SplineModel model;
  // The statistics with the measured times (for reports and benchmarks).
  FitStatistics statistics;
  // Per input vertex: |x_i - F(u_i)| in percent of the largest side.
  Eigen::VectorXd errors_percent;
  // One entry per round of `statistics.rounds`.
  std::vector<RoundDetails> round_details;
  // True when rmse <= options.rmse_percent was reached.
  bool reached_target = false;
};

// Fits `mesh` (must pass RequireClosedGenusZero: else its kUnsupported
// status). kInvalidArgument for options out of range. The result is the
// same for any thread count.
StatusOr<FitResult> FitSphericalSpline(const TriangleMesh& mesh,
                                       const FitOptions& options = {});

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_ADAPTIVE_FIT_H_
