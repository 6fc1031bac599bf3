// The options of a fit (FitOptions), their table (FitOptionTable: each
// option's key, range, record and `sdcb fit` flag), their check, and the part
// of them a model records (RecordedFitOptions): every option of
// FitSphericalSpline in one place.
//
// Errors are in percent of the largest side of the input's bounding box
// (docs/FITTING.md).
#ifndef SDCB_CORE_FIT_FIT_OPTIONS_H_
#define SDCB_CORE_FIT_FIT_OPTIONS_H_

#include <functional>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// The named stages of a fit, in the order they run (knot placement to
// measure once per round).
enum class FitStage {
  kParameterization,
  kKnotPlacement,
  kConfigurations,
  kBasis,
  kSolve,
  kMeasure,
  kDone,
};

// "parameterization", "knot placement", "configurations", "basis", "solve",
// "measure", "done".
const char* FitStageName(FitStage stage);

// What the progress callback receives.
struct FitProgress {
  FitStage stage = FitStage::kParameterization;
  int round = 0;  // The round the stage belongs to (0 before the rounds).
  // Estimated finished fraction of the whole fit, in [0, 1]. The
  // parameterization counts as the first kParameterizationShare
  // (core/fit/fit_progress.h); the rounds share the rest equally, the number
  // of rounds being estimated from the error's decay so far
  // (docs/FITTING.md); within a round each stage advances by its typical
  // share of a round's time.
  double fraction = 0.0;
  // Which of FitSphericalSpline's further fits this is: "" for the first,
  // "split" for the one on the split input (FitOptions::retry_map_vertices),
  // "lambda L" or "split, lambda L" for one with the map's lambda L
  // (retry_lambda_factors). Each one's fraction starts again from 0.
  std::string retry;
};

struct FitOptions {
  int degree = 4;  // k, 2..5
  // Stop when the two-sided rms distance between the surface and the mesh
  // (dense samples of both, core/measure/surface_deviation.h) is at most this,
  // with no folded area; percent of the largest bounding-box side.
  double rmse_percent = 0.05;
  // ... and the two-sided Hausdorff distance (the same dense samples) at
  // most this. 0 = ten times rmse_percent; negative = no limit. A fit that
  // meets the rms but not this goes on adding rounds (docs/FITTING.md).
  double max_error_percent = 0.0;
  int knots_per_round = 70;  // K: new knots per round (the paper: 100)
  // New knots per round are max(K, knots_growth x the knots so far): past
  // 4 K knots the rounds grow geometrically, so a fit that needs thousands
  // of knots takes tens of rounds, not hundreds of knots at a time over
  // dozens (docs/FITTING.md). 0 = K every round (the paper).
  double knots_growth = 0.25;
  int initial_knots = 0;           // knots of round 0; 0 = knots_per_round
  int max_rounds = 30;             // rounds at most (round 0 included)
  int max_control_points = 50000;  // stop before exceeding this
  double lambda = 1.0;             // parameterization, eq. (12)
  // An input of fewer vertices than this is parameterized and fitted split
  // at edge midpoints (SplitToEdgeLength) until no edge is longer than the
  // spacing of about this many vertices spread evenly over it: the same
  // surface, but where its triangles are coarser than that, the map can
  // spread its distortion over several pieces of each instead of jumping
  // from one triangle to the next, which a smooth spline following the map
  // rounds and folds over (docs/FITTING.md, "Coarse inputs fitted again
  // split"). Not when round 0 tries the corners' knot clusters
  // (keep_features). The statistics, FitResult::vertex_errors_percent and
  // the stored parameters stay per input vertex. 0 = the input's triangles.
  int map_vertices = 0;
  // FitSphericalSpline: a fit with map_vertices 0 of an input of fewer
  // vertices than this is run again, smooth (keep_features off), with
  // map_vertices this and at most as many control points as the first
  // returned, when it misses its target with a folded round and the input
  // does not pass through itself (core/mesh/self_intersections.h: then the
  // mesh is why), or when it reaches the target smooth with more control
  // points than the input has vertices. The better of the two is returned:
  // of two that reach, the one with fewer control points; else one that
  // reaches, else of two folded fits the one folded less, else
  // IsBetterFallback's order. 0 = never.
  int retry_map_vertices = 20000;
  // FitSphericalSpline, after the fits above, for the same inputs: while
  // the fit to return still misses its target with a folded surface and the
  // input does not pass through itself, the input is fitted again with the
  // map's lambda times each of these in turn, the area term weaker: the map
  // then distorts a thin part's area more and its angles less (it stretches
  // it less along its length), and the spline folds less there
  // (docs/FITTING.md, "Thin parts fitted again with a smaller lambda"). On the
  // split input (smooth, as above) when the fit to return has more control
  // points than the input has vertices, else on its own triangles. A fit that
  // reaches its target, or folds less, replaces the one to return. Empty =
  // never.
  std::vector<double> retry_lambda_factors = {0.5, 0.25, 0.15};
  double alpha = 4.0;            // density exponent (Sec. 4.4)
  double regularization = 1e-6;  // core/fit/least_squares.h
  // The basis the control points multiply (docs/FITTING.md compares them).
  BasisForm basis_form = BasisForm::kNormalized;
  // Weight of the bending energy, integral over S^2 of |Hess F|^2 (the
  // chart's second derivatives) divided by 4 pi, against the data term,
  // integral over the mesh of |F(u(x)) - x|^2 divided by the mesh's area
  // (both lengths squared, so the weight is scale-free). Keeps regions with
  // few samples smooth instead of oscillating.
  double fairness = 0.0;
  // Samples of the data term per knot spacing (core/fit/fit_samples.h).
  double samples_per_spacing = 2.0;
  // A round with more than eight mesh vertices per control point (a mesh
  // far denser than its knots) thins its data term to this many cells per
  // knot spacing, one row kept per cell (core/fit/fit_samples.h); 0 = never.
  double thinned_cells_per_spacing = 4.0;
  // When a round meets the RMSE target but its surface folds, up to this
  // many rounds follow that place a quarter of knots_per_round, only where
  // it folds.
  int max_fold_rounds = 5;
  // When the target is missed, the round returned is the most accurate
  // (smallest rms) among those whose surface does not fold, or among all
  // when every round folds; with this set, among all rounds: a fit that
  // folds over a sliver may then be returned instead of a far less
  // accurate one that does not (the shortfall says so either way).
  bool fallback_accepts_folds = false;
  // Surface samples of the error measurement: per knot in every round, and
  // at least this many for the returned model.
  int round_samples_per_knot = 12;
  int final_surface_samples = 100000;
  // ... and the mesh's side of it inside the triangles too, at about this
  // many points (DeviationOptions::mesh_samples); 0 = at the vertices only.
  int final_mesh_samples = 100000;
  // Worker threads of the fit's own TBB arena; 0 = as many as the calling
  // context allows. The results do not depend on it, and the process-wide
  // TBB settings of the program are never changed.
  int threads = 0;
  bool store_parameters = true;  // keep the sphere point of every vertex
  // Edges of the input where its normals turn by more than this (degrees,
  // (0, 180]; 180: none) are detected as sharp features and reported
  // (FitResult::features, core/mesh/feature_curves.h).
  double feature_angle_degrees = 30.0;
  // When every feature curve joins two corners along one great-circle arc
  // (ClustersKeepEveryFeature: a single mesh edge, or a straight chain of
  // them on a solid whose faces all see its centroid, parameterized then by
  // the central projection, core/param/central_projection.h), round 0 first
  // tries a cluster of knots at every corner alone (core/knots/
  // feature_knots.h), one knot along each feature edge, then `degree` of
  // them, which keeps the corners and edges sharp, and keeps the first that
  // meets the target; otherwise the fit goes on from its usual round 0 and
  // parameterization, smooth across them, as it does with this false or
  // without features (feature_angle_degrees 180).
  bool keep_features = true;
  // 0: knots where the placement puts them. Otherwise each new knot is moved
  // to the nearest point of the octahedral grid of this many bits per
  // coordinate (core/sphere/unit_vector_grid.h, kMinUnitVectorGridBits..
  // kMaxUnitVectorGridBits) before the round's configurations and solve, so
  // that a file stores the knots fitted exactly in 2 x bits each (16 bits:
  // within 7.6e-5 radians of the placement, the CVT keeps knots 1e-4 apart).
  // A new knot that would land on another's grid point is dropped.
  int knot_grid_bits = 0;
  // Called at the start of every stage (from the calling thread).
  std::function<void(const FitProgress&)> progress;
};

// The fields of FitOptions as data, one entry each (FitOptionTable): the
// key that names it in the model's record and JSON, its valid range, whether
// the model records it, and its `sdcb fit` flag with the flag's range and
// help sentence. CheckFitOptions, RecordFitOptions, the record's JSON
// (io/report/fit_statistics_json.h), the flags of `sdcb fit` and their usage
// text (tools/fit_command.cpp) all iterate it; docs/CLI.md documents every flag
// (tests/core/fit/fit_options_test.cpp checks).
//
// The one field out of it is `progress` (a callback, no value).
using FitOptionField =
    std::variant<int FitOptions::*, double FitOptions::*, bool FitOptions::*,
                 std::vector<double> FitOptions::*, BasisForm FitOptions::*>;
// The field of RecordedFitOptions of the same type, or none.
using RecordedFitOptionField =
    std::variant<std::monostate, int RecordedFitOptions::*,
                 double RecordedFitOptions::*, bool RecordedFitOptions::*>;

// Values in [lo, hi] (open at an end when lo_open / hi_open), finite, and
// for an integer whole; `zero_too`: 0 as well ("0 = off"). A list's every
// element, an enum's underlying value. Bools have no range.
struct FitOptionRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = true;
  bool hi_open = true;
  bool zero_too = false;

  bool Contains(double value) const;
  // "[2, 5]", "(0, inf)", "0 or [2, 26]".
  std::string Describe() const;
};

struct FitOptionDescriptor {
  // The FitOptions field's name, and the key of its value in the record's
  // JSON ("options" of the .sdcb STAT chunk and of `fit --json`).
  const char* key = "";
  FitOptionField field;
  FitOptionRange range;  // what CheckFitOptions accepts
  // Recorded in the model (every option that changes a model's bytes and is
  // not stored otherwise), or std::monostate.
  RecordedFitOptionField recorded;
  // The record of format version 1 has this key already: a file without it
  // is refused, where a newer key missing reads as 0 / false.
  bool required_in_record = false;
  // The `sdcb fit` flag without its dashes ("rmse"), or nullptr: not a flag.
  const char* flag = nullptr;
  // What the flag takes ("PCT", "N|auto"); nullptr for a flag without a
  // value, which sets a bool option to whether it is given (so
  // --store-parameters: off unless given, whatever FitOptions' default).
  const char* value_name = nullptr;
  // The values the flag accepts (closed range, tools/cli.h Args::GetInt /
  // GetDouble), within `range`.
  double flag_lo = 0;
  double flag_hi = 0;
  // The flag also takes "auto", meaning the default of both this option and
  // `auto_clears`; a number given sets this option and sets `auto_clears`
  // (an int option) to 0.
  int FitOptions::*auto_clears = nullptr;
  // The help sentence of the usage text, and the default it names when not
  // the field's own default ("10 x rmse"); nullptr: the field's default.
  const char* help = "";
  const char* default_text = nullptr;
};

// Every field of FitOptions but `progress`, in the order of the struct.
const std::vector<FitOptionDescriptor>& FitOptionTable();

// The field's value as a double (bool: 0 / 1, enum: its underlying value;
// a list has none: NaN).
double FitOptionValue(const FitOptions& options, const FitOptionDescriptor& d);

// kInvalidArgument naming the first option out of its range (table order).
Status CheckFitOptions(const FitOptions& options);

// The options of `options` that change a model's bytes: the table's recorded
// fields, max_error_percent as applied (MaxErrorTarget).
RecordedFitOptions RecordFitOptions(const FitOptions& options);

// The Hausdorff target a fit applies: options.max_error_percent, or ten
// times the rms target when that is 0; negative = none.
double MaxErrorTarget(const FitOptions& options);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FIT_OPTIONS_H_
