// The fitted spherical DCB-spline as plain data: everything the `.sdcb` file
// stores (io/sdcb/sdcb_file.h) and everything an evaluator needs, without any
// file I/O, so that core/ code (the fitting driver, the surface type) and io/
// share one definition.
//
// Frames: the fit works in a NORMALIZED frame in which the input mesh's
// bounding box is centred at the origin and its largest side is 1 (the
// paper's "unit cube", Sec. 5; errors in percent refer to this frame).
// `NormalizingTransform` maps between it and the input's coordinates.
#ifndef SDCB_CORE_SPLINE_SPLINE_MODEL_H_
#define SDCB_CORE_SPLINE_SPLINE_MODEL_H_

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/delaunay_configurations.h"

namespace sdcb {

// normalized = (input - translation) / scale;
// input = scale * normalized + translation.
struct NormalizingTransform {
  // Largest side of the input's bounding box, in input units; > 0.
  double scale = 1.0;
  // Centre of the input's bounding box, in input coordinates.
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  // `normalized`: #P by 3 points in the normalized frame. Returns them in
  // input coordinates (row-wise scale * p + translation).
  Eigen::MatrixX3d ToInput(const Eigen::MatrixX3d& normalized) const;
  // `input`: #P by 3 points in input coordinates. Returns them normalized.
  Eigen::MatrixX3d ToNormalized(const Eigen::MatrixX3d& input) const;
};

// One refinement round of the adaptive fit (paper Sec. 4.4, Table 2). Errors
// are in percent of the largest bounding-box side.
struct RoundStatistics {
  int round = 0;           // 0 for the initial knots.
  int knots = 0;           // Number of knots after the round.
  int control_points = 0;  // Number of basis functions after the round.
  // The distance between the surface and the input mesh, as
  // FitStatistics::error_measure says: two-sided and dense for models of this
  // code, at the input vertices only for models of format version 1.
  double rmse_percent = 0.0;
  double max_error_percent = 0.0;
  // |x_i - F(u_i)| at the input vertices x_i and their sphere parameters u_i
  // (the paper's measure).
  double vertex_rmse_percent = 0.0;
  double vertex_max_error_percent = 0.0;
  // Share of the surface's area whose normal opposes the mesh's, percent.
  double folded_area_percent = 0.0;
  // An open part's: the two-sided distance between the trimmed surface's
  // boundary and the part's, percent; -1 for a closed part.
  double boundary_error_percent = -1.0;
};

// What rmse_percent / max_error_percent of RoundStatistics measure.
enum class ErrorMeasure {
  // |x_i - F(u_i)| at the input vertices (format version 1 models).
  kVertices = 0,
  // The two-sided distance between the surface and the input mesh, measured
  // at dense samples of both (core/measure/surface_deviation.h).
  kDenseTwoSided = 1,
};

// Every option of the fit that made a model and changes its bytes
// (core/fit/fit_options.h documents each; its FitOptionTable says which are
// recorded and under which key), recorded so that a model can be reproduced
// by SplineFitter. Options a model's file does not record read as 0 / false
// (format version 1 recorded only degree, rmse_percent, knots_per_round,
// max_rounds and lambda).
struct RecordedFitOptions {
  int degree = 0;
  double rmse_percent = 0.0;  // Target RMSE, percent of the largest side.
  // Target Hausdorff distance as applied (the default resolved); 0 in files
  // written before it existed, negative = none.
  double max_error_percent = 0.0;
  int knots_per_round = 0;
  double knots_growth = 0.0;
  int initial_knots = 0;
  int max_rounds = 0;
  int max_control_points = 0;
  double lambda = 0.0;  // Parameterization area weight, paper eq. (12).
  double alpha = 0.0;   // Knot density exponent (Sec. 4.4).
  double regularization = 0.0;
  double fairness = 0.0;
  double samples_per_spacing = 0.0;
  int max_fold_rounds = 0;
  int round_samples_per_knot = 0;
  int final_surface_samples = 0;
  bool fallback_accepts_folds = false;
  double thinned_cells_per_spacing = 0.0;  // 0: the rows were never thinned
  // Mesh samples of the final measurement (DeviationOptions::mesh_samples);
  // 0 in files written while it measured the mesh at its vertices only.
  int final_mesh_samples = 0;
  // Bits of the octahedral grid the knots were snapped to; 0: not snapped.
  int knot_grid_bits = 0;
  // FitOptions::map_vertices of the fit (0: the input's own triangles).
  int map_vertices = 0;
  // FitOptions::feature_angle_degrees and keep_features of the fit; 0 and
  // false in files written before they were recorded (keep_features means
  // something only when feature_angle_degrees is > 0).
  double feature_angle_degrees = 0.0;
  bool keep_features = false;
};

// How the fit went, without wall-clock times (they would make the model's
// bytes differ between runs; FitResult carries them).
struct FitStatistics {
  std::vector<RoundStatistics> rounds;
  RoundStatistics final_result;  // "final" in JSON: the returned model.
  RecordedFitOptions options;
  ErrorMeasure error_measure = ErrorMeasure::kDenseTwoSided;
  bool reached_target = false;
};

// What the model was fitted to, so a model can be matched to its mesh.
struct SourceMeshInfo {
  int64_t num_vertices = 0;
  int64_t num_faces = 0;
  uint64_t hash = 0;      // HashTriangleMesh() of the source mesh.
  std::string file_name;  // As given on the command line; UTF-8, may be "".
};

// The basis of the surface F(p) = sum_i b_i(p) c_i.
enum class BasisForm {
  // b_i = Bbar_i = B_i / I, eq. 5: a partition of unity (the paper's).
  kNormalized = 0,
  // b_i = B_i, eq. 4: higher approximation order (docs/BASIS.md).
  kRaw = 1,
};

struct SplineModel {
  int degree = 0;  // Degree k of the DCB-spline, 0..5.
  // #knots by 3 knot positions, unit vectors on S^2.
  Eigen::MatrixX3d knots;
  // Degree-k configurations grouped by unordered set: one ConfigurationSet
  // (its k + 3 knots and its boundary triples X_B) per basis function.
  DelaunayConfigurations configurations;
  // #sets by 3: row i is the control point c_i of configurations.sets[i], in
  // the NORMALIZED frame: F(p) = sum_i Bbar_i(p) c_i (paper eq. 5).
  Eigen::MatrixX3d control_points;
  NormalizingTransform transform;
  FitStatistics statistics;
  SourceMeshInfo source;
  // Which basis the control points multiply (eq. 5 normalized, or eq. 4).
  BasisForm basis_form = BasisForm::kNormalized;
  // Optional: #source vertices by 3, the sphere point (unit vector) of each
  // input vertex (the spherical parameterization, Sec. 4.3). Empty (0 rows)
  // when not stored.
  Eigen::MatrixX3d parameters;
};

// Largest supported degree (the paper uses 3..5).
constexpr int kMaxSplineDegree = 5;

// The transform of the normalized frame: translation = centre of the
// bounding box of `mesh.vertices`, scale = its largest side. Fails with
// kInvalidInput for a mesh without vertices, with a non-finite coordinate, or
// whose vertices all coincide (largest side 0).
StatusOr<NormalizingTransform> ComputeNormalizingTransform(
    const TriangleMesh& mesh);

// 64-bit FNV-1a over bytes (offset basis 0xcbf29ce484222325, prime
// 0x100000001b3).
uint64_t Fnv1a64(const void* data, size_t size);

// FNV-1a 64 (above) over this little-endian byte sequence:
//   u64 #vertices, u64 #faces,
//   per vertex in order: the IEEE-754 bit patterns of x, y, z as u64,
//   per face in order: its three indices as two's-complement u32.
// Equal meshes hash equally; any change of one bit of one coordinate (e.g.
// 0.0 vs -0.0) or of one index changes the byte sequence. See docs/FORMAT.md.
uint64_t HashTriangleMesh(const TriangleMesh& mesh);

// Checks every invariant of a model; returns kInvalidArgument naming the
// first violation: degree in 0..5 and equal to configurations.degree; at
// least degree + 4 knots, all finite and unit; at least one set; each set has
// degree + 3 strictly ascending knot indices in range, at least one and at
// most C(k+3, 3) strictly ascending boundary triples (sorted, no duplicates),
// each a subset of its set; sets strictly ascending by knot list; one finite
// control point per set; scale finite and > 0, translation finite; all
// statistics finite, counts non-negative; source counts non-negative;
// parameters empty or one finite unit vector per source vertex.
Status ValidateSplineModel(const SplineModel& model);

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_SPLINE_MODEL_H_
