#include "sdcb/core/fit/fit_options.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>

#include "sdcb/core/sphere/unit_vector_grid.h"

namespace sdcb {
namespace {

// The default Hausdorff target, in multiples of the rms target: on CGAL's
// meshes a fit that reaches its rms has a Hausdorff distance 2 to 9 times it
// and more at sharp feature lines (fandisk 15x, fandisk_large 16x;
// docs/FITTING.md).
constexpr double kDefaultMaxErrorRatio = 10.0;

// "0.05", "1e-06", "inf".
std::string Number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

constexpr double kInf = std::numeric_limits<double>::infinity();

// Ranges of CheckFitOptions.
FitOptionRange Closed(double lo, double hi) { return {lo, hi, false, false}; }
FitOptionRange AtLeast(double lo) { return {lo, kInf, false, true}; }
FitOptionRange Positive() { return {0, kInf, true, true}; }

// One table entry of a field of type T, built by chained calls.
template <typename T>
class Entry {
 public:
  Entry(const char* key, T FitOptions::*field, FitOptionRange range = {}) {
    d_.key = key;
    d_.field = field;
    d_.range = range;
  }
  // Recorded in the model as `recorded` (a field of the same type).
  Entry& Record(T RecordedFitOptions::*recorded) {
    d_.recorded = recorded;
    return *this;
  }
  // ... in every record since format version 1.
  Entry& RecordSinceVersion1(T RecordedFitOptions::*recorded) {
    d_.required_in_record = true;
    return Record(recorded);
  }
  // The flag --`flag` `value_name`, accepting [lo, hi].
  Entry& Flag(const char* flag, const char* value_name, double lo, double hi,
              const char* help) {
    d_.flag = flag;
    d_.value_name = value_name;
    d_.flag_lo = lo;
    d_.flag_hi = hi;
    d_.help = help;
    return *this;
  }
  // The flag --`flag` without a value: the option is whether it is given.
  Entry& Switch(const char* flag, const char* help) {
    static_assert(std::is_same_v<T, bool>, "a switch sets a bool");
    d_.flag = flag;
    d_.help = help;
    return *this;
  }
  Entry& DefaultText(const char* text) {
    d_.default_text = text;
    return *this;
  }
  Entry& Auto(int FitOptions::*clears) {
    d_.auto_clears = clears;
    return *this;
  }
  operator FitOptionDescriptor() const { return d_; }  // NOLINT

 private:
  FitOptionDescriptor d_;
};

template <typename T>
void CopyRecorded(const FitOptions& o, const FitOptionDescriptor& d,
                  RecordedFitOptions* r) {
  const auto* field = std::get_if<T FitOptions::*>(&d.field);
  const auto* recorded = std::get_if<T RecordedFitOptions::*>(&d.recorded);
  if (field != nullptr && recorded != nullptr) {
    T& value = r->**recorded;
    value = o.**field;
  }
}

}  // namespace

const std::vector<FitOptionDescriptor>& FitOptionTable() {
  using F = FitOptions;
  using R = RecordedFitOptions;
  static const std::vector<FitOptionDescriptor> table = {
      Entry("degree", &F::degree, Closed(2, kMaxSplineDegree))
          .RecordSinceVersion1(&R::degree)
          .Flag("degree", "K", 2, kMaxSplineDegree, "spline degree"),
      Entry("rmse_percent", &F::rmse_percent, Positive())
          .RecordSinceVersion1(&R::rmse_percent)
          .Flag("rmse", "PCT", 1e-6, 100,
                "stop when the two-sided rms distance between the surface "
                "and the mesh is at most this and nothing folds"),
      // Recorded as applied (RecordFitOptions).
      Entry("max_error_percent", &F::max_error_percent)
          .Record(&R::max_error_percent)
          .Flag("max-error", "PCT", 0, 1000,
                "also stop only when the two-sided Hausdorff distance is at "
                "most this")
          .DefaultText("0: 10 x rmse"),
      Entry("knots_per_round", &F::knots_per_round, AtLeast(1))
          .RecordSinceVersion1(&R::knots_per_round)
          .Flag("knots-per-round", "N", 1, 100000, "new knots per round"),
      Entry("knots_growth", &F::knots_growth, Closed(0, 10))
          .Record(&R::knots_growth)
          .Flag("knots-growth", "G", 0, 10,
                "a round adds max(N, G x the knots so far); 0: N every "
                "round"),
      Entry("initial_knots", &F::initial_knots, AtLeast(0))
          .Record(&R::initial_knots),
      Entry("max_rounds", &F::max_rounds, AtLeast(1))
          .RecordSinceVersion1(&R::max_rounds)
          .Flag("max-rounds", "R", 1, 1000,
                "rounds at most (round 0 included)"),
      Entry("max_control_points", &F::max_control_points, AtLeast(1))
          .Record(&R::max_control_points)
          .Flag("max-control-points", "M", 10, 10000000,
                "stop before a round would exceed this"),
      Entry("lambda", &F::lambda, Positive())
          .RecordSinceVersion1(&R::lambda)
          .Flag("lambda", "L", 1e-3, 1e3,
                "the map's trade-off of angle for area distortion, eq. (12)"),
      Entry("map_vertices", &F::map_vertices, AtLeast(0))
          .Record(&R::map_vertices)
          .Flag("map-vertices", "N|auto", 0, 10000000,
                "an input of fewer vertices is fitted split to about N (the "
                "same surface); auto: fitted again so, to 20000, when the fit "
                "on its triangles folds or needs more control points than it "
                "has vertices, then with lambda x 0.5, 0.25, 0.15 while it "
                "still folds; 0: one fit, never split")
          .Auto(&F::retry_map_vertices)
          .DefaultText("auto"),
      // Not recorded: the record holds the map_vertices and lambda of the
      // fit that made the model, which the retries set.
      Entry("retry_map_vertices", &F::retry_map_vertices, AtLeast(0)),
      Entry("retry_lambda_factors", &F::retry_lambda_factors, Positive()),
      Entry("alpha", &F::alpha, Positive()).Record(&R::alpha),
      Entry("regularization", &F::regularization, Positive())
          .Record(&R::regularization)
          .Flag("regularization", "R", 1e-12, 1e3,
                "weight of the least-squares prior term"),
      // Not recorded here: the model stores it (SplineModel::basis_form).
      Entry("basis_form", &F::basis_form,
            Closed(static_cast<int>(BasisForm::kNormalized),
                   static_cast<int>(BasisForm::kRaw))),
      Entry("fairness", &F::fairness, AtLeast(0)).Record(&R::fairness),
      Entry("samples_per_spacing", &F::samples_per_spacing, Positive())
          .Record(&R::samples_per_spacing),
      Entry("thinned_cells_per_spacing", &F::thinned_cells_per_spacing,
            AtLeast(0))
          .Record(&R::thinned_cells_per_spacing),
      Entry("max_fold_rounds", &F::max_fold_rounds, AtLeast(0))
          .Record(&R::max_fold_rounds),
      Entry("fallback_accepts_folds", &F::fallback_accepts_folds)
          .Record(&R::fallback_accepts_folds)
          .Switch("accept-folds",
                  "a missed target returns the most accurate round even if "
                  "it folds"),
      Entry("round_samples_per_knot", &F::round_samples_per_knot, AtLeast(1))
          .Record(&R::round_samples_per_knot),
      Entry("final_surface_samples", &F::final_surface_samples, AtLeast(1))
          .Record(&R::final_surface_samples),
      Entry("final_mesh_samples", &F::final_mesh_samples, AtLeast(0))
          .Record(&R::final_mesh_samples),
      // Not recorded: the results do not depend on it.
      Entry("threads", &F::threads, AtLeast(0))
          .Flag("threads", "T", 0, 1024,
                "worker threads; the result does not depend on them")
          .DefaultText("0: all"),
      // Not recorded: the model holds the parameters or not.
      Entry("store_parameters", &F::store_parameters)
          .Switch("store-parameters",
                  "keep each vertex's sphere point in the model"),
      Entry("feature_angle_degrees", &F::feature_angle_degrees,
            {0, 180, true, false})
          .Record(&R::feature_angle_degrees)
          .Flag("feature-angle", "DEG", 1e-3, 180,
                "the input's sharp edges, curves and corners, reported and "
                "kept sharp where every feature is one edge between corners "
                "(knot clusters at the corners); 180 finds none"),
      Entry("keep_features", &F::keep_features).Record(&R::keep_features),
      Entry(
          "knot_grid_bits", &F::knot_grid_bits,
          {kMinUnitVectorGridBits, kMaxUnitVectorGridBits, false, false, true})
          .Record(&R::knot_grid_bits)
          .Flag("knot-grid", "BITS", 0, kMaxUnitVectorGridBits,
                "snap the knots to the octahedral grid of BITS bits; 0: off")
          .DefaultText("16 with --quantize, else 0"),
  };
  return table;
}

Status CheckFitOptions(const FitOptions& o) {
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    if (const auto* list =
            std::get_if<std::vector<double> FitOptions::*>(&d.field)) {
      for (double v : o.**list) {
        if (!d.range.Contains(v)) {
          return InvalidArgumentError(std::string("every element of ") + d.key +
                                      " must be in " + d.range.Describe() +
                                      ", got " + Number(v));
        }
      }
      continue;
    }
    if (std::holds_alternative<bool FitOptions::*>(d.field)) continue;
    const double v = FitOptionValue(o, d);
    if (!d.range.Contains(v)) {
      return InvalidArgumentError(std::string(d.key) + " must be in " +
                                  d.range.Describe() + ", got " + Number(v));
    }
  }
  // The lambdas of the retries, each > 0 as the map needs.
  for (double factor : o.retry_lambda_factors) {
    if (!(o.lambda * factor > 0)) {
      return InvalidArgumentError(
          "lambda times every retry lambda factor must be > 0");
    }
  }
  return Status::Ok();
}

const char* FitStageName(FitStage stage) {
  switch (stage) {
    case FitStage::kParameterization:
      return "parameterization";
    case FitStage::kKnotPlacement:
      return "knot placement";
    case FitStage::kConfigurations:
      return "configurations";
    case FitStage::kBasis:
      return "basis";
    case FitStage::kSolve:
      return "solve";
    case FitStage::kMeasure:
      return "measure";
    case FitStage::kDone:
      return "done";
  }
  return "?";
}

double MaxErrorTarget(const FitOptions& o) {
  return o.max_error_percent == 0 ? kDefaultMaxErrorRatio * o.rmse_percent
                                  : o.max_error_percent;
}

bool FitOptionRange::Contains(double v) const {
  if (zero_too && v == 0) return true;
  return std::isfinite(v) && (lo_open ? v > lo : v >= lo) &&
         (hi_open ? v < hi : v <= hi);
}

std::string FitOptionRange::Describe() const {
  if (std::isinf(lo) && std::isinf(hi)) return "finite";
  return std::string(zero_too ? "0 or " : "") + (lo_open ? "(" : "[") +
         Number(lo) + ", " + Number(hi) + (hi_open ? ")" : "]");
}

double FitOptionValue(const FitOptions& o, const FitOptionDescriptor& d) {
  struct Visitor {
    const FitOptions& o;
    double operator()(int FitOptions::*f) const { return o.*f; }
    double operator()(double FitOptions::*f) const { return o.*f; }
    double operator()(bool FitOptions::*f) const { return o.*f ? 1 : 0; }
    double operator()(std::vector<double> FitOptions::*) const {
      return std::numeric_limits<double>::quiet_NaN();
    }
    double operator()(BasisForm FitOptions::*f) const {
      return static_cast<int>(o.*f);
    }
  };
  return std::visit(Visitor{o}, d.field);
}

RecordedFitOptions RecordFitOptions(const FitOptions& o) {
  RecordedFitOptions r;
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    CopyRecorded<int>(o, d, &r);
    CopyRecorded<double>(o, d, &r);
    CopyRecorded<bool>(o, d, &r);
  }
  // As applied: the default resolved.
  r.max_error_percent = MaxErrorTarget(o);
  return r;
}

}  // namespace sdcb
