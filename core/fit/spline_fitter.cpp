#include "sdcb/core/fit/spline_fitter.h"

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <locale>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "sdcb/core/fit/fit_samples.h"
#include "sdcb/core/fit/fold_progress.h"
#include "sdcb/core/fit/fold_repair.h"
#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/knots/feature_knots.h"
#include "sdcb/core/knots/spherical_cvt.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/mesh/curvature.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/mesh/self_intersections.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/param/central_projection.h"
#include "sdcb/core/param/parameterization_distortion.h"
#include "sdcb/core/param/spherical_parameterization.h"
#include "sdcb/core/sphere/point_kd_tree.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/sphere/unit_vector_grid.h"
#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/design_matrix.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {
namespace {

// Adds the seconds of the stages a round runs (knot placement to measure)
// of `from` to `to`; the parameterization and the total are the caller's.
void AddRoundStages(const StageTimings& from, StageTimings* to) {
  to->knot_placement += from.knot_placement;
  to->configurations += from.configurations;
  to->basis += from.basis;
  to->solve += from.solve;
  to->measure += from.measure;
}

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start_)
        .count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// Progress model (FitProgress::fraction). The parameterization takes about
// this share of a typical fit (bunny00: 1.9 s of 4.4 s; smaller meshes less).
constexpr double kParameterizationShare = 0.3;
// Where each stage starts within a round, as a share of the round's time
// (bunny00, degree 4).
constexpr double kRoundStageStart[] = {
    0.0,   // knot placement
    0.2,   // configurations
    0.25,  // basis
    0.55,  // solve
    0.75,  // measure
};
// Rounds before a fit may stop because its error falls too slowly.
constexpr int kMinRoundsBeforeRateStop = 5;
// Data-term pieces of split triangles per control point at most
// (FitSampleOptions::max_pieces).
constexpr int64_t kMaxPiecesPerControlPoint = 128;
// Mesh vertices per control point above which the data term is thinned to
// the knots' density (FitOptions::thinned_cells_per_spacing). A coarse
// mesh's rows are mostly points inside its split triangles, already at the
// knots' density; thinning them too made the rounds' own measurement (at
// the fitted rows) read up to 4.6 times below the dense one on CGAL's coarse
// meshes (the mesh -> surface half is measured at their few vertices).
constexpr int64_t kThinAboveVerticesPerControlPoint = 8;
// Moves the placement's new knots onto the octahedral grid
// (FitOptions::knot_grid_bits); the fixed ones are on it already. A new knot
// that lands on another knot's grid point is dropped.
void SnapNewKnots(int bits, KnotPlacement* placement) {
  Eigen::MatrixX3d& knots = placement->knots;
  for (Eigen::Index i = placement->num_fixed; i < knots.rows(); ++i) {
    const Eigen::Vector3d k = knots.row(i);
    knots.row(i) = DecodeUnitVector(EncodeUnitVector(k, bits), bits);
  }
  KnotSeparation separation = MinimumKnotSeparation(knots);
  while (knots.rows() > 1 && !(separation.angle > 0)) {
    // Fixed knots are distinct: the later of the pair is a new one.
    const Eigen::Index drop = separation.second;
    knots.block(drop, 0, knots.rows() - drop - 1, 3) =
        knots.bottomRows(knots.rows() - drop - 1).eval();
    knots.conservativeResize(knots.rows() - 1, 3);
    separation = MinimumKnotSeparation(knots);
  }
  placement->min_separation = separation.angle;
}

// The fewest knots a round adds: rounds that only remove folds, and rounds
// halved because the knots had no room for more.
constexpr int kMinFoldKnots = 10;
// The floors of the density (fractions of its maximum) with which a round is
// placed again when the basis on its knots has a hole (RunRound).
constexpr double kHoleRetryFloors[] = {0.01, 1.0};
// The share of the knots a power law through the last two rounds puts at the
// rms target that a round adds when that is less than a whole round: the
// rms falls faster than that law says (bunny00, --rmse 0.067: the law
// through 200 and 300 knots has exponent 1.24; 300 to 369 knots fell with
// 1.66), so the whole difference overshoots the target (0.0613 % at 369
// knots; 0.0646 % at 360 with 0.7).
constexpr double kLastRoundShare = 0.7;
// Fold rounds stop early when, after this many, the folded area has not
// shrunk to kFoldShrink of what it was when they began (measured on CGAL's
// meshes: where folds went away they had halved by then; where they stayed,
// 0.2 % on the cow and camel, they had shrunk by 10 % at most).
constexpr int kFoldRoundsToShrink = 2;
constexpr double kFoldShrink = 0.5;
// Rounds assumed before two rounds show the error's decay.
constexpr int kInitialRoundGuess = 5;
// The feature round's rows beside every feature edge (AppendEdgeBandSamples):
// at these multiples of the cluster gap off the edge's arc, on both sides,
// and at this many points along it.
constexpr double kFeatureBandOffsets[] = {0.005, 0.015, 0.05, 0.15, 0.5, 1.5};
constexpr int kFeatureBandRowsAlong = 32;

// For every basis function, the sample nearest to the normalized mean of its
// knots: the prior of basis functions that no sample sees.
Eigen::MatrixX3d NearestSamplePrior(const DcbBasis& basis,
                                    const PointKdTree& tree,
                                    const Eigen::MatrixX3d& targets) {
  Eigen::MatrixX3d prior(basis.size(), 3);
  for (int i = 0; i < basis.size(); ++i) {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    for (int k : basis.configuration_set(i).knots) {
      center += basis.knots().row(k).transpose();
    }
    const PointKdTree::Neighbor n = tree.Nearest(center.normalized());
    prior.row(i) = targets.row(n.index >= 0 ? n.index : 0);
  }
  return prior;
}

// Every basis support is half-open, so a knot can lie outside all of them:
// I = 0 exactly there and > 0 all around it (hand.off's round 0 with the
// density exponent 12), and the surface there is 0 / 0. The measurements'
// lattices hold the knots, so such a basis is refused as one with a hole
// (kInvalidInput), and the round places its knots again.
Status CheckKnotsCovered(const DcbBasis& basis) {
  const Eigen::MatrixX3d& knots = basis.knots();
  std::vector<char> covered(knots.rows(), 0);
  basis.ParallelForEachPoint(knots, [&](Eigen::Index r) {
    covered[r] = basis.Normalization(knots.row(r).transpose()) > 0.0;
  });
  for (Eigen::Index r = 0; r < knots.rows(); ++r) {
    if (covered[r]) continue;
    return InvalidInputError("the degree-" + std::to_string(basis.degree()) +
                             " basis of these " + std::to_string(knots.rows()) +
                             " knots leaves knot " + std::to_string(r) +
                             " outside every support: I = sum B_i = 0 there");
  }
  return Status();
}

// Stacks row-major sparse matrices, each row of part j scaled by
// scales[j][row].
DesignMatrix StackScaledRows(
    const std::vector<std::pair<const DesignMatrix*, const Eigen::VectorXd*>>&
        parts) {
  Eigen::Index rows = 0, nonzeros = 0, cols = 0;
  for (const auto& [m, s] : parts) {
    rows += m->rows();
    nonzeros += m->nonZeros();
    cols = m->cols();
  }
  DesignMatrix out(rows, cols);
  out.resizeNonZeros(nonzeros);
  Eigen::Index at = 0, row = 0;
  for (const auto& [m, s] : parts) {
    for (Eigen::Index r = 0; r < m->rows(); ++r, ++row) {
      out.outerIndexPtr()[row] = static_cast<int>(at);
      const double scale = (*s)[r];
      for (DesignMatrix::InnerIterator it(*m, r); it; ++it, ++at) {
        out.innerIndexPtr()[at] = static_cast<int>(it.col());
        out.valuePtr()[at] = scale * it.value();
      }
    }
  }
  out.outerIndexPtr()[row] = static_cast<int>(at);
  return out;
}

// The bending energy's quadrature: three points per knot triangle (the
// degree-2 planar rule at barycentric (2/3, 1/6, 1/6) and permutations,
// mapped onto the sphere), each weighted a third of the spherical area.
struct BendingQuadrature {
  Eigen::MatrixX3d points;
  Eigen::VectorXd weights;
};

// Spherical area of the triangle (a, b, c) (unit vectors): the solid angle
// 2 atan(|det| / (1 + a.b + b.c + c.a)).
double SphericalArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& c) {
  return 2.0 * std::atan2(std::abs(a.dot(b.cross(c))),
                          1.0 + a.dot(b) + b.dot(c) + c.dot(a));
}

BendingQuadrature MakeBendingQuadrature(const Eigen::MatrixX3d& knots,
                                        const DelaunayConfigurations& tri) {
  const Eigen::Index n = static_cast<Eigen::Index>(tri.sets.size());
  BendingQuadrature q;
  q.points.resize(3 * n, 3);
  q.weights.resize(3 * n);
  for (Eigen::Index t = 0; t < n; ++t) {
    const std::vector<int>& k = tri.sets[t].knots;
    const Eigen::Vector3d v[3] = {knots.row(k[0]), knots.row(k[1]),
                                  knots.row(k[2])};
    const double area = SphericalArea(v[0], v[1], v[2]);
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d p = (4.0 * v[j] + v[(j + 1) % 3] + v[(j + 2) % 3])
                                    .normalized();  // (2/3, 1/6, 1/6)
      q.points.row(3 * t + j) = p.transpose();
      q.weights[3 * t + j] = area / 3.0;
    }
  }
  return q;
}

// The mesh FitOptions::map_vertices asks the map and the fit to use: `mesh`
// split (SplitToEdgeLength) for about `map_vertices` vertices, or nullopt
// when that leaves it as it is (or would make it too large).
std::optional<TriangleMesh> SplitForMap(const TriangleMesh& mesh,
                                        int map_vertices) {
  if (mesh.num_vertices() >= map_vertices) return std::nullopt;
  std::optional<TriangleMesh> split = SplitToEdgeLength(
      mesh, SplitEdgeLengthFor(VertexAreas(mesh).sum(), map_vertices),
      std::max<int64_t>(mesh.num_vertices(), 4 * int64_t{map_vertices}));
  if (!split || split->num_vertices() == mesh.num_vertices()) {
    return std::nullopt;
  }
  return split;
}

// A number with four significant digits, for messages.
std::string ShortNumber(double value) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << std::setprecision(4) << value;
  return out.str();
}

}  // namespace

bool IsBetterFallback(const RoundStatistics& a, const RoundStatistics& b,
                      bool accept_folds) {
  if (!accept_folds &&
      (a.folded_area_percent == 0) != (b.folded_area_percent == 0)) {
    return a.folded_area_percent == 0;
  }
  return a.rmse_percent < b.rmse_percent;
}

// Everything a fit keeps between rounds.
struct SplineFitter::State {
  FitOptions options;
  // The fit's own arena: parallel work runs inside it, so the fit uses at
  // most options.threads threads without touching process-wide TBB limits.
  std::unique_ptr<tbb::task_arena> arena;
  Stopwatch clock;  // since Create

  TriangleMesh mesh;  // in the normalized frame
  // The input's vertices: the first rows of `mesh` (FitOptions::map_vertices).
  Eigen::Index input_vertices = 0;
  Eigen::MatrixX3d u;  // the vertices' sphere parameters
  // The feature corners' knot clusters (core/knots/feature_knots.h): the
  // knots of the first round 0 while not empty, dropped with that round when
  // it does not meet the target; their knots along each feature edge.
  Eigen::MatrixX3d feature_knots;
  int feature_knots_per_edge = 0;
  // The optimized parameterization while that round uses the central
  // projection (empty otherwise).
  Eigen::MatrixX3d default_u;
  double mesh_area = 0;
  // Per vertex: the unit normal of its triangles' area-weighted sum (the
  // rounds' estimate of the dense measurement).
  Eigen::MatrixX3d vertex_normal;
  std::unique_ptr<PointKdTree> parameter_tree;
  // VertexAreaRatio(mesh, u) once a round has needed it (reset with u).
  std::optional<StatusOr<Eigen::VectorXd>> area_ratio;
  // The mesh's AABB tree, built once for every round's measurement.
  std::optional<MeshDistance> mesh_distance;
  SphericalDensity density;  // of the next round's knots

  FitResult result;
  // A round kept to be returned if the target is missed.
  struct Candidate {
    SplineModel model;
    Eigen::VectorXd vertex_errors;  // per input vertex
    bool vertex_errors_exact = true;
  };
  // The round with the smallest rms among those without folds in their
  // round's measurement (IsBetterFallback), and among all rounds.
  std::optional<Candidate> best;
  std::optional<Candidate> most_accurate;
  // Whether the latest round's vertex errors are |F(u_i) - x_i| at every
  // vertex, not a thinned round's cell values.
  bool vertex_errors_exact = true;
  bool finished = false;
  int estimated_rounds = kInitialRoundGuess;
  // The next round places knots only where the surface folds.
  bool fold_round = false;
  int fold_rounds = 0;
  int fold_rounds_in_a_row = 0;
  double folds_when_fold_rounds_began = 0.0;
  // Whether the folds shrink as knots are added.
  FoldProgress fold_progress;

  template <typename F>
  auto InArena(F&& f) {
    return arena->execute(std::forward<F>(f));
  }

  // `within`: the finished share of the stage (parameterization) or of the
  // round (round stages).
  void Report(FitStage stage, int round, double within) {
    if (!options.progress) return;
    FitProgress p;
    p.stage = stage;
    p.round = round;
    if (stage == FitStage::kParameterization) {
      p.fraction = kParameterizationShare * within;
    } else if (stage == FitStage::kDone) {
      p.fraction = 1.0;
    } else {
      const double rounds = std::max(estimated_rounds, round + 1);
      p.fraction = kParameterizationShare +
                   (1.0 - kParameterizationShare) * (round + within) / rounds;
    }
    p.fraction = std::clamp(p.fraction, 0.0, 1.0);
    options.progress(p);
  }

  // The sphere points of the feature corners.
  Eigen::MatrixX3d FeatureCorners() const {
    const std::vector<int>& corners = result.features.corners;
    Eigen::MatrixX3d out(corners.size(), 3);
    for (size_t c = 0; c < corners.size(); ++c) out.row(c) = u.row(corners[c]);
    return out;
  }

  // Round 0 on the feature corners' clusters (core/knots/feature_knots.h):
  // those knots alone, none placed by the density.
  static StatusOr<KnotPlacement> FeatureKnotPlacement(
      const Eigen::MatrixX3d& knots) {
    KnotPlacement placement;
    placement.knots = knots;
    placement.min_separation = kCornerClusterGap;
    return placement;
  }

  // Makes `parameters` the vertices' sphere parameters u.
  void UseParameters(Eigen::MatrixX3d parameters) {
    u = std::move(parameters);
    parameter_tree = std::make_unique<PointKdTree>(u);
    area_ratio.reset();
  }

  // Forgets a round 0 on the feature clusters that missed the target, as if
  // it had not run (its seconds stay in the stage timings): the next round
  // tries the clusters with `degree` knots along each feature edge when
  // this one had one (an arc alone on its great circle needs k + 1 knots
  // there for a crease: the tetrahedron), and is otherwise an ordinary
  // round 0.
  void DropFeatureRound() {
    if (feature_knots_per_edge < options.degree) {
      feature_knots_per_edge = options.degree;
      feature_knots = CornerKnotClusters(result.features, u, kCornerClusterGap,
                                         feature_knots_per_edge);
    } else {
      feature_knots.resize(0, 3);
      if (default_u.rows() > 0) {
        UseParameters(std::move(default_u));
        default_u.resize(0, 3);
      }
    }
    SplineModel& model = result.model;
    model.knots.resize(0, 3);
    model.configurations = DelaunayConfigurations();
    model.control_points.resize(0, 3);
    model.statistics.rounds.clear();
    model.statistics.final_result = RoundStatistics();
    result.round_details.clear();
    best.reset();
    most_accurate.reset();
    vertex_errors_exact = true;
  }

  // The stopping test, on a final (dense, closest-point) measurement.
  bool MeetsTarget(double rms, double hausdorff, double folded) const {
    const double max_error = MaxErrorTarget(options);
    return rms <= options.rmse_percent && folded == 0 &&
           (max_error < 0 || hausdorff <= max_error);
  }

  bool Better(const RoundStatistics& a, const RoundStatistics& b) const {
    return IsBetterFallback(a, b, options.fallback_accepts_folds);
  }

  // Ends the fit. A fit that missed its target returns its best round (see
  // IsBetterFallback), measured again as a reached one is: densely, with the
  // closest points (the rounds' own measurements are coarser and see about a
  // third of the small folds). A round kept for having no folds in its
  // round's measurement that folds when measured densely has no claim over
  // a more accurate round: the most accurate is measured too, and returned
  // when its rms is smaller.
  Status Finish(bool reached, std::string shortfall) {
    finished = true;
    result.model.statistics.reached_target = reached;
    if (reached) return Status::Ok();
    result.shortfall = std::move(shortfall);
    const int last = result.model.statistics.final_result.round;
    if (best && Better(best->model.statistics.final_result,
                       result.model.statistics.final_result)) {
      Return(*best);
    }
    const bool kept_unfolded =
        result.model.statistics.final_result.folded_area_percent == 0;
    SDCB_RETURN_IF_ERROR(MeasureReturned());
    if (result.model.statistics.reached_target) return Status::Ok();
    const RoundStatistics kept = result.model.statistics.final_result;
    std::string why =
        kept_unfolded && !options.fallback_accepts_folds
            ? "the most accurate without folds in its round's measurement"
            : "the most accurate";
    if (kept_unfolded && kept.folded_area_percent > 0 && most_accurate &&
        most_accurate->model.statistics.final_result.round != kept.round) {
      const Candidate other = ReturnedCandidate();
      Return(*most_accurate);
      SDCB_RETURN_IF_ERROR(MeasureReturned());
      if (result.model.statistics.reached_target) return Status::Ok();
      if (result.model.statistics.final_result.rmse_percent <
          kept.rmse_percent) {
        why = "the most accurate (round " + std::to_string(kept.round) +
              ", without folds in its round's measurement, folds " +
              ShortNumber(kept.folded_area_percent) +
              " % of its area when measured densely)";
      } else {
        Return(other);
      }
    }
    const RoundStatistics& returned = result.model.statistics.final_result;
    if (returned.round != last) {
      result.shortfall += "; returned round " + std::to_string(returned.round) +
                          " instead, " + why;
    }
    result.shortfall +=
        " (returned surface, measured densely: rms " +
        ShortNumber(returned.rmse_percent) + " %, max " +
        ShortNumber(returned.max_error_percent) + " %" +
        (returned.folded_area_percent > 0
             ? ", folded " + ShortNumber(returned.folded_area_percent) +
                   " % of its area"
             : std::string()) +
        ")";
    return Status::Ok();
  }

  // The returned round as a candidate (its model with the fit's statistics).
  Candidate ReturnedCandidate() const {
    return {result.model, result.vertex_errors_percent, vertex_errors_exact};
  }

  // Returns `c`'s round: its model and vertex errors, with the statistics of
  // the fit (every round) and `c`'s round as the final one.
  void Return(const Candidate& c) {
    FitStatistics stats = std::move(result.model.statistics);
    result.model = c.model;
    stats.final_result = c.model.statistics.final_result;
    result.model.statistics = std::move(stats);
    result.vertex_errors_percent = c.vertex_errors;
    vertex_errors_exact = c.vertex_errors_exact;
  }

  // The returned round measured as a reached one is (its final statistics
  // become the dense measurement's); reached when that meets the target.
  Status MeasureReturned() {
    RoundStatistics& kept = result.model.statistics.final_result;
    const Stopwatch clock;
    SDCB_ASSIGN_OR_RETURN(const SphericalSpline surface,
                          SurfaceFromModel(result.model));
    // A thinned round's vertex errors were its cells': F(u_i) at every
    // vertex now, for the paper's measure and as candidates.
    Eigen::MatrixX3d vertex_points;
    if (!vertex_errors_exact) {
      vertex_points = surface.EvaluateMany(u);
      result.vertex_errors_percent = 100.0 * (vertex_points - mesh.vertices)
                                                 .topRows(input_vertices)
                                                 .rowwise()
                                                 .norm();
      const Eigen::VectorXd& e = result.vertex_errors_percent;
      kept.vertex_rmse_percent =
          std::sqrt(e.squaredNorm() / std::max<Eigen::Index>(e.size(), 1));
      kept.vertex_max_error_percent = e.size() > 0 ? e.maxCoeff() : 0;
      vertex_errors_exact = true;
    }
    SDCB_ASSIGN_OR_RETURN(
        const SurfaceDeviation dense,
        Measure(surface, vertex_points.rows() > 0 ? &vertex_points : nullptr,
                true));
    result.timings.measure += clock.Seconds();
    kept.rmse_percent = dense.rms_percent;
    kept.max_error_percent = dense.hausdorff_percent;
    kept.folded_area_percent = dense.folded_area_percent;
    // The rounds' mesh -> surface bound (the parametric residual) can keep a
    // round from the final measurement that it would pass (the 8-vertex
    // beam: its rounds said 0.31 % rms, densely it is 0.022 %). Measured as
    // a reached round is, it has reached.
    if (MeetsTarget(kept.rmse_percent, kept.max_error_percent,
                    kept.folded_area_percent)) {
      result.model.statistics.reached_target = true;
      result.shortfall.clear();
    }
    return Status::Ok();
  }

  Status RunRound();

 private:
  struct Problem;
  StatusOr<Problem> BuildProblem(bool feature_round,
                                 const Eigen::MatrixX3d& knots,
                                 const DelaunayConfigurations& configurations,
                                 const DelaunayConfigurations& knot_triangles,
                                 RoundDetails* details) const;
  // The least squares' rows (the data term's and the bending energy's),
  // scaled by the square roots of their weights.
  DesignMatrix StackedDesign(const Problem& problem) const;
  StatusOr<Eigen::MatrixX3d> Solve(const Problem& problem) const;
  // RepairFolds (core/fit/fold_repair.h) on the round's solution, at the
  // lattice of the final measurement, its steps allowed the Hausdorff target
  // as distance; `basis` is the round's (moved from the problem into the
  // round's surface).
  StatusOr<FoldRepairResult> RepairRoundFolds(
      const Problem& problem, const DcbBasis& basis,
      Eigen::MatrixX3d* control_points) const;
  // `final_measurement` false: the surface -> mesh half only (a round bounds
  // the other half at its data rows). `vertex_points`: F(u_i) per vertex,
  // candidates of the final measurement's closest points, or null.
  StatusOr<SurfaceDeviation> Measure(const SphericalSpline& surface,
                                     const Eigen::MatrixX3d* vertex_points,
                                     bool final_measurement) const;
  // The round's rms with the mesh -> surface half estimated by the residuals'
  // components along the mesh's normals (the distance to first order,
  // without the tangential part by which the parametric bound overstates
  // it), at mesh samples of the given normals and area weights.
  static double EstimatedRms(const SurfaceDeviation& deviation,
                             const Eigen::MatrixX3d& residuals,
                             const Eigen::MatrixX3d& normals,
                             const Eigen::VectorXd& weights) {
    const Eigen::VectorXd normal_part =
        100.0 * residuals.cwiseProduct(normals).rowwise().sum();
    const double ms =
        weights.dot(normal_part.cwiseAbs2()) / std::max(weights.sum(), 1e-300);
    const double s2m = deviation.surface_to_mesh_rms_percent;
    return std::sqrt(0.5 * (s2m * s2m + ms));
  }
  // The unit mesh normal at every row of `samples`: a vertex's
  // (VertexNormals), or the triangle's of a point inside one.
  Eigen::MatrixX3d RowNormals(const FitSamples& samples) const {
    if (samples.thinned) return samples.row_normal;
    const Eigen::Index nv = samples.num_vertices;
    Eigen::MatrixX3d normals(samples.points.rows(), 3);
    normals.topRows(nv) = vertex_normal;
    for (size_t r = 0; r < samples.triangle.size(); ++r) {
      const Eigen::RowVector3i t = mesh.faces.row(samples.triangle[r]);
      const Eigen::Vector3d a = mesh.vertices.row(t[0]);
      const Eigen::Vector3d b = mesh.vertices.row(t[1]);
      const Eigen::Vector3d c = mesh.vertices.row(t[2]);
      Eigen::Vector3d n = (b - a).cross(c - a);
      if (n.norm() > 0) n.normalize();  // zero for a degenerate triangle
      normals.row(nv + static_cast<Eigen::Index>(r)) = n.transpose();
    }
    return normals;
  }
  // F(u_i) at every vertex: the fitted value of the vertices that are kept
  // rows of thinned `samples`, the spline evaluated at the others.
  Eigen::MatrixX3d VertexPoints(const SphericalSpline& surface,
                                const FitSamples& samples,
                                const Eigen::MatrixX3d& fitted) const {
    const Eigen::Index nv = mesh.vertices.rows();
    Eigen::MatrixX3d out(nv, 3);
    std::vector<char> known(nv, 0);
    for (size_t r = 0; r < samples.row_vertex.size(); ++r) {
      const int v = samples.row_vertex[r];
      if (v < 0) continue;
      out.row(v) = fitted.row(r);
      known[v] = 1;
    }
    std::vector<Eigen::Index> rest;
    for (Eigen::Index v = 0; v < nv; ++v) {
      if (!known[v]) rest.push_back(v);
    }
    Eigen::MatrixX3d points(rest.size(), 3);
    for (size_t i = 0; i < rest.size(); ++i) points.row(i) = u.row(rest[i]);
    const Eigen::MatrixX3d values = surface.EvaluateMany(points);
    for (size_t i = 0; i < rest.size(); ++i) out.row(rest[i]) = values.row(i);
    return out;
  }
  // Per vertex: the parametric residual of the row kept for its cell
  // (thinned samples), percent.
  static Eigen::VectorXd CellVertexErrors(const FitSamples& samples,
                                          const Eigen::MatrixX3d& fitted) {
    Eigen::VectorXd out(samples.vertex_row.size());
    for (size_t v = 0; v < samples.vertex_row.size(); ++v) {
      const int r = samples.vertex_row[v];
      out[v] = 100.0 * (fitted.row(r) - samples.targets.row(r)).norm();
    }
    return out;
  }
  void NextDensity(const Problem& problem, const Eigen::MatrixX3d& fitted,
                   const Eigen::VectorXd& vertex_errors,
                   const SurfaceDeviation& deviation);
  // Rounds still needed at the recent rate of decay (updating
  // estimated_rounds), or -1 if the error does not fall.
  int EstimateRounds();
  // The knots the next round adds: `planned`, or fewer when the power law
  // through the last two rounds says fewer reach the rms target.
  int KnotsToTarget(int planned) const;
};

StatusOr<SplineFitter> SplineFitter::Create(const TriangleMesh& mesh,
                                            FitOptions options) {
  SDCB_RETURN_IF_ERROR(CheckFitOptions(options));
  auto state = std::make_unique<State>();
  State& s = *state;
  s.options = std::move(options);
  const FitOptions& o = s.options;
  // (`automatic` is copied: binding a reference to it needs a definition
  // this TBB version does not export.)
  const int automatic = tbb::task_arena::automatic;
  s.arena =
      std::make_unique<tbb::task_arena>(o.threads > 0 ? o.threads : automatic);
  SDCB_RETURN_IF_ERROR(
      s.arena->execute([&] { return RequireClosedGenusZero(mesh); }));

  SplineModel& model = s.result.model;
  model.degree = o.degree;
  model.basis_form = o.basis_form;
  SDCB_ASSIGN_OR_RETURN(model.transform, ComputeNormalizingTransform(mesh));
  model.source.num_vertices = mesh.num_vertices();
  model.source.num_faces = mesh.num_faces();
  model.source.hash = HashTriangleMesh(mesh);
  SDCB_ASSIGN_OR_RETURN(s.result.features,
                        DetectFeatures(mesh, o.feature_angle_degrees));
  // The mesh the map and the fit use: the input, or the input split
  // (FitOptions::map_vertices), its first rows the input's vertices.
  const std::optional<TriangleMesh> split =
      o.keep_features && FeatureCurvesJoinCorners(s.result.features)
          ? std::nullopt
          : SplitForMap(mesh, o.map_vertices);
  const TriangleMesh& map_mesh = split ? *split : mesh;
  s.mesh.faces = map_mesh.faces;
  s.mesh.vertices = model.transform.ToNormalized(map_mesh.vertices);
  s.input_vertices = mesh.num_vertices();
  s.result.map_vertices = static_cast<int>(map_mesh.num_vertices());
  model.statistics.options = RecordFitOptions(o);
  model.statistics.error_measure = ErrorMeasure::kDenseTwoSided;
  for (Eigen::Index f = 0; f < s.mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = s.mesh.vertices.row(s.mesh.faces(f, 0));
    const Eigen::Vector3d b = s.mesh.vertices.row(s.mesh.faces(f, 1));
    const Eigen::Vector3d c = s.mesh.vertices.row(s.mesh.faces(f, 2));
    s.mesh_area += 0.5 * (b - a).cross(c - a).norm();
  }
  s.vertex_normal = VertexNormals(s.mesh);

  // 1. Spherical parameterization (Sec. 4.3).
  s.Report(FitStage::kParameterization, 0, 0);
  Stopwatch stage;
  SphericalParameterizationOptions param_options;
  param_options.lambda = o.lambda;
  param_options.threads = o.threads;
  param_options.progress = [&s](const std::string&, double f) {
    s.Report(FitStage::kParameterization, 0, f);
  };
  // Meanwhile, independent of it, the mesh's AABB tree and the curvedness
  // (step 2): they keep busy the threads the parameterization's sequential
  // parts leave idle. Same results; all three count as this stage.
  std::optional<StatusOr<MeshDistance>> distance;
  std::optional<StatusOr<Eigen::VectorXd>> curvedness_or;
  SDCB_ASSIGN_OR_RETURN(const SphericalParameterization param, s.InArena([&] {
    tbb::task_group side;
    side.run([&] {
      distance = MeshDistance::Create(s.mesh);
      curvedness_or = Curvedness(map_mesh);
    });
    StatusOr<SphericalParameterization> p =
        ParameterizeOnSphere(map_mesh, param_options);
    side.wait();
    return p;
  }));
  s.UseParameters(param.sphere);
  SDCB_ASSIGN_OR_RETURN(s.mesh_distance, std::move(*distance));
  s.result.timings.parameterization = stage.Seconds();

  // 2. Round-0 density: curvedness^alpha (Sec. 4.4).
  stage = Stopwatch();
  SDCB_ASSIGN_OR_RETURN(Eigen::VectorXd curvedness, std::move(*curvedness_or));
  if (!(curvedness.maxCoeff() > 0)) curvedness.setOnes();  // flat: uniform
  s.density = SphericalDensity{s.u, s.mesh.faces, Eigen::VectorXd()};
  SDCB_ASSIGN_OR_RETURN(s.density.values,
                        DensityFromValues(curvedness, o.alpha));
  // Round 0 tries the corners' knot clusters alone first (RunRound) when
  // they can keep every feature; on a solid whose faces all see its
  // centroid, with the central projection as its parameterization (each
  // face one projective map; the optimized one comes back if the round is
  // dropped).
  if (o.keep_features && FeatureCurvesJoinCorners(s.result.features)) {
    std::optional<Eigen::MatrixX3d> central = CentralProjection(s.mesh);
    if (ClustersKeepEveryFeature(s.result.features, central ? *central : s.u)) {
      if (central) {
        s.default_u = std::move(s.u);
        s.UseParameters(std::move(*central));
      }
      s.feature_knots_per_edge = 1;
      s.feature_knots = CornerKnotClusters(s.result.features, s.u);
    }
  }
  s.result.timings.knot_placement += stage.Seconds();
  return SplineFitter(std::move(state));
}

SplineFitter::SplineFitter(std::unique_ptr<State> state)
    : state_(std::move(state)) {}
SplineFitter::SplineFitter(SplineFitter&&) noexcept = default;
SplineFitter& SplineFitter::operator=(SplineFitter&&) noexcept = default;
SplineFitter::~SplineFitter() = default;

bool SplineFitter::finished() const { return !state_ || state_->finished; }

int SplineFitter::rounds() const {
  return state_
             ? static_cast<int>(state_->result.model.statistics.rounds.size())
             : 0;
}

const SplineModel& SplineFitter::model() const { return state_->result.model; }

Status SplineFitter::AddRound() {
  if (finished()) {
    return InvalidArgumentError("the fit is finished; no round can be added");
  }
  return state_->InArena([&] {
    // The round on the feature clusters is an attempt: when it cannot be
    // built (a basis with a hole, too many samples) the fit goes on from
    // its usual round 0, as when it misses the target.
    const bool feature_round = state_->feature_knots.rows() > 0;
    Status status = state_->RunRound();
    if (!status.ok() && feature_round) {
      state_->DropFeatureRound();
      return Status::Ok();
    }
    return status;
  });
}

// The round's least-squares problem: the basis on the round's knots, the data
// term's samples and design matrix, and the bending rows.
struct SplineFitter::State::Problem {
  DcbBasis basis;
  FitSamples samples;
  DesignMatrix data;
  BendingQuadrature bending;
  ChartHessianRows hessian;

  // Eigen 3.4's sparse matrices have no move constructor: moving a Problem
  // (into and out of its StatusOr) swaps them instead of copying.
  Problem(DcbBasis b, FitSamples s, DesignMatrix* d, BendingQuadrature q,
          ChartHessianRows* h)
      : basis(std::move(b)), samples(std::move(s)), bending(std::move(q)) {
    SwapMatrices(d, h);
  }
  Problem(Problem&& other) noexcept
      : basis(std::move(other.basis)),
        samples(std::move(other.samples)),
        bending(std::move(other.bending)) {
    SwapMatrices(&other.data, &other.hessian);
  }
  void SwapMatrices(DesignMatrix* d, ChartHessianRows* h) {
    data.swap(*d);
    hessian.uu.swap(h->uu);
    hessian.uv.swap(h->uv);
    hessian.vv.swap(h->vv);
  }
};

StatusOr<SplineFitter::State::Problem> SplineFitter::State::BuildProblem(
    bool feature_round, const Eigen::MatrixX3d& knots,
    const DelaunayConfigurations& configurations,
    const DelaunayConfigurations& knot_triangles, RoundDetails* details) const {
  const FitOptions& o = options;
  FitSampleOptions sample_options;
  sample_options.samples_per_spacing = o.samples_per_spacing;
  // Far above what any closed genus-0 CGAL mesh asks (at most 68 sample
  // rows per control point), far below what a fan's needles ask (2,000).
  sample_options.max_pieces = kMaxPiecesPerControlPoint *
                              static_cast<int64_t>(configurations.sets.size());
  if (o.thinned_cells_per_spacing > 0) {
    sample_options.thinned_cells_per_spacing = o.thinned_cells_per_spacing;
    sample_options.thin_above_vertices =
        kThinAboveVerticesPerControlPoint *
        static_cast<int64_t>(configurations.sets.size());
  }
  // The basis and the samples do not depend on each other: the samples are
  // built meanwhile, on the threads the basis's sequential parts (merging
  // the splines' recursions) leave idle. The same results.
  std::optional<FitSamples> samples_or;
  tbb::task_group side;
  side.run([&] {
    // The clusters' knots are a gap apart: spaced by them, the samples
    // would be that dense over each one's whole Voronoi cell (28 million
    // rows on a cube of 866 vertices). Spaced by the corners alone; the
    // rows beside the edges below pin the thin triangles.
    samples_or.emplace(BuildFitSamples(mesh, u,
                                       feature_round ? FeatureCorners() : knots,
                                       sample_options, &vertex_normal));
  });
  StatusOr<DcbBasis> basis_or = DcbBasis::Create(knots, configurations);
  const Status knots_covered =
      basis_or.ok() ? CheckKnotsCovered(*basis_or) : Status();
  side.wait();
  SDCB_ASSIGN_OR_RETURN(DcbBasis basis, std::move(basis_or));
  SDCB_RETURN_IF_ERROR(knots_covered);
  FitSamples samples = std::move(*samples_or);
  if (feature_round) {
    // The thin triangles between a corner's cluster and the next corner
    // (up to the cluster's gap wide) carry basis functions that the
    // samples above miss: unpinned, they slide the parameterization along
    // the edges (by up to 14 % of the cube's side) without moving the
    // surface off the solid. Rows across those bands pin them.
    std::vector<double> offsets;
    for (const double f : kFeatureBandOffsets) {
      offsets.push_back(f * kCornerClusterGap);
    }
    AppendEdgeBandSamples(mesh, u, result.features.edges, offsets,
                          kFeatureBandRowsAlong, samples.weights.mean(),
                          &samples);
  }
  DesignMatrix data =
      BuildFormDesignMatrix(basis, samples.points, o.basis_form);
  BendingQuadrature bending = MakeBendingQuadrature(knots, knot_triangles);
  ChartHessianRows hessian =
      o.fairness > 0
          ? BuildChartHessianRows(basis, bending.points, o.basis_form)
          : ChartHessianRows{};
  details->data_samples = static_cast<int>(samples.points.rows());
  details->unthinned_samples = static_cast<int>(samples.unthinned_rows);
  details->split_triangles = samples.split_triangles;
  // Samples, and input vertices (the first rows, or the thinned rows that
  // are vertices), in each basis function's support.
  std::vector<int> per_column(basis.size(), 0), vertices(basis.size(), 0);
  for (Eigen::Index r = 0; r < data.rows(); ++r) {
    const bool vertex = r < samples.num_vertices ||
                        (samples.thinned && samples.row_vertex[r] >= 0);
    for (int k = data.outerIndexPtr()[r]; k < data.outerIndexPtr()[r + 1];
         ++k) {
      ++per_column[data.innerIndexPtr()[k]];
      if (vertex) ++vertices[data.innerIndexPtr()[k]];
    }
  }
  if (!per_column.empty()) {
    details->min_samples_per_basis =
        *std::min_element(per_column.begin(), per_column.end());
    details->min_vertices_per_basis =
        *std::min_element(vertices.begin(), vertices.end());
  }
  return Problem(std::move(basis), std::move(samples), &data,
                 std::move(bending), &hessian);
}

DesignMatrix SplineFitter::State::StackedDesign(const Problem& p) const {
  // sqrt(w) rows of the data term, sqrt(fairness * area / 4 pi * weight)
  // rows of the bending energy (uv counted twice) with zero targets.
  const FitOptions& o = options;
  const Eigen::VectorXd data_scale = p.samples.weights.cwiseSqrt();
  std::vector<std::pair<const DesignMatrix*, const Eigen::VectorXd*>> parts = {
      {&p.data, &data_scale}};
  Eigen::VectorXd bend_scale, bend_scale_uv;
  if (o.fairness > 0) {
    bend_scale =
        (o.fairness * mesh_area / (4.0 * M_PI) * p.bending.weights).cwiseSqrt();
    bend_scale_uv = std::sqrt(2.0) * bend_scale;
    parts.push_back({&p.hessian.uu, &bend_scale});
    parts.push_back({&p.hessian.uv, &bend_scale_uv});
    parts.push_back({&p.hessian.vv, &bend_scale});
  }
  return StackScaledRows(parts);
}

StatusOr<Eigen::MatrixX3d> SplineFitter::State::Solve(const Problem& p) const {
  const FitOptions& o = options;
  const DesignMatrix design = StackedDesign(p);
  const Eigen::VectorXd data_scale = p.samples.weights.cwiseSqrt();
  Eigen::MatrixX3d targets = Eigen::MatrixX3d::Zero(design.rows(), 3);
  targets.topRows(p.data.rows()) = data_scale.asDiagonal() * p.samples.targets;
  const Eigen::MatrixX3d prior = GrevillePrior(
      p.data, p.samples.targets,
      NearestSamplePrior(p.basis, *parameter_tree, mesh.vertices));
  LeastSquaresOptions ls;
  ls.regularization = o.regularization;
  return SolveRegularizedLeastSquares(design, targets, prior, ls);
}

StatusOr<FoldRepairResult> SplineFitter::State::RepairRoundFolds(
    const Problem& p, const DcbBasis& basis,
    Eigen::MatrixX3d* control_points) const {
  const FitOptions& o = options;
  // The final measurement's lattice, whose fold test decides the round.
  DeviationOptions lattice;
  lattice.min_surface_samples = std::max(
      o.final_surface_samples,
      o.round_samples_per_knot * static_cast<int>(basis.knots().rows()));
  lattice.closest_points = false;
  lattice.search_all_vertices = false;
  lattice.mesh_to_surface = false;
  FoldRepairOptions repair;
  repair.max_distance_percent = std::max(0.0, MaxErrorTarget(o));
  return RepairFolds(
      basis, o.basis_form,
      RegularizedNormalMatrixLower(StackedDesign(p), o.regularization), mesh,
      *mesh_distance, lattice, repair, control_points);
}

StatusOr<SurfaceDeviation> SplineFitter::State::Measure(
    const SphericalSpline& surface, const Eigen::MatrixX3d* vertex_points,
    bool final_measurement) const {
  // Rounds: surface -> mesh at a lattice with round_samples_per_knot
  // samples per knot (the round bounds the other half at its data rows).
  // The final one: at least final_surface_samples, and the closest points
  // on the spline from the mesh's vertices and about final_mesh_samples
  // points of its triangles.
  DeviationOptions measure;
  const int per_knot =
      options.round_samples_per_knot * static_cast<int>(surface.knots().rows());
  measure.min_surface_samples =
      final_measurement ? std::max(options.final_surface_samples, per_knot)
                        : per_knot;
  measure.closest_points = final_measurement;
  measure.mesh_samples = final_measurement ? options.final_mesh_samples : 0;
  measure.search_all_vertices = false;
  measure.mesh_to_surface = final_measurement;
  return MeasureSurfaceDeviation(surface, mesh, measure, vertex_points,
                                 &*mesh_distance);
}

void SplineFitter::State::NextDensity(const Problem& p,
                                      const Eigen::MatrixX3d& fitted,
                                      const Eigen::VectorXd& vertex_errors,
                                      const SurfaceDeviation& deviation) {
  // The error of a vertex is the largest of its parametric residual, those
  // of the data samples inside its triangles, and the surface -> mesh
  // distance of the surface samples nearest to it on the sphere. A folded
  // sample counts as the largest error: knots go there. In a round after the
  // target was met, only there.
  const Eigen::Index first = p.samples.num_vertices;
  Eigen::VectorXd error = vertex_errors;
  for (size_t r = 0; r < p.samples.triangle.size(); ++r) {
    if (p.samples.triangle[r] < 0) continue;  // a thinned vertex row
    const double e =
        100.0 *
        (fitted.row(first + r) - p.samples.targets.row(first + r)).norm();
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(p.samples.triangle[r], k);
      error[v] = std::max(error[v], e);
    }
  }
  if (fold_round) error.setConstant(0.0);
  const double worst =
      std::max(error.maxCoeff(),
               deviation.surface_sample_distance_percent.size()
                   ? deviation.surface_sample_distance_percent.maxCoeff()
                   : 0.0);
  for (Eigen::Index i = 0; i < deviation.surface_sample_points.rows(); ++i) {
    const PointKdTree::Neighbor n = parameter_tree->Nearest(
        deviation.surface_sample_points.row(i).transpose());
    if (n.index < 0) continue;
    const double e = deviation.surface_sample_folded[i] ? worst
                     : fold_round
                         ? 0.0
                         : deviation.surface_sample_distance_percent[i];
    error[n.index] = std::max(error[n.index], e);
  }
  if (!(error.maxCoeff() > 0)) return;  // keep the last density
  // A floor keeps the density positive everywhere (the CVT needs it).
  error = error.cwiseMax(1e-3 * error.maxCoeff());
  // Knots where the error is per unit of the mesh's area, not the
  // sphere's: the map compresses thin parts and features (docs/KNOTS.md).
  StatusOr<Eigen::VectorXd> values = DensityFromValues(error, options.alpha);
  if (!area_ratio) area_ratio = VertexAreaRatio(mesh, u);
  if (values.ok() && area_ratio->ok()) {
    values = PullBackDensity(*values, **area_ratio);
  }
  if (values.ok()) density.values = std::move(values).value();
}

int SplineFitter::State::EstimateRounds() {
  // The decay per round over the last (up to) three rounds of each error
  // still above its target: the rms, and the Hausdorff distance when it has
  // a target.
  const auto& rounds = result.model.statistics.rounds;
  const int n = static_cast<int>(rounds.size());
  if (n < 2) return -1;
  const int window = std::min(3, n - 1);
  auto rounds_to = [&](double target, double RoundStatistics::*error) {
    const double now = rounds[n - 1].*error;
    if (target < 0 || now <= target) return 0.0;
    const double decay =
        std::pow(now / (rounds[n - 1 - window].*error), 1.0 / window);
    if (!(decay > 0 && decay < 1)) return -1.0;
    return std::ceil(std::log(target / now) / std::log(decay));
  };
  const double for_rms =
      rounds_to(options.rmse_percent, &RoundStatistics::rmse_percent);
  // The Hausdorff distance counts once the rms is met: before, the rounds
  // bound its mesh -> surface half coarsely (Measure).
  const double for_max = for_rms != 0
                             ? 0.0
                             : rounds_to(MaxErrorTarget(options),
                                         &RoundStatistics::max_error_percent);
  if (for_rms < 0 || for_max < 0) return -1;
  const int needed =
      static_cast<int>(std::clamp(std::max(for_rms, for_max), 1.0, 1e6));
  estimated_rounds = std::min(options.max_rounds, n + needed);
  return needed;
}

int SplineFitter::State::KnotsToTarget(int planned) const {
  // rms = c knots^-p through the last two rounds (both above the rms
  // target, neither folded, the last within the Hausdorff target) gives the
  // knots at the target; the round adds kLastRoundShare of the difference
  // when that is less than planned. A round still above the Hausdorff
  // target is not sized: that distance (at a crease, a corner) falls
  // unevenly, and rounds sized by it come short many times over.
  const auto& rounds = result.model.statistics.rounds;
  const size_t n = rounds.size();
  if (n < 2) return planned;
  const RoundStatistics& a = rounds[n - 2];
  const RoundStatistics& b = rounds[n - 1];
  const double target = options.rmse_percent;
  const double max_target = MaxErrorTarget(options);
  if (!(b.knots > a.knots && a.rmse_percent > b.rmse_percent &&
        b.rmse_percent > target && a.folded_area_percent == 0 &&
        b.folded_area_percent == 0 &&
        (max_target < 0 || b.max_error_percent <= max_target))) {
    return planned;
  }
  const double p = std::log(a.rmse_percent / b.rmse_percent) /
                   std::log(static_cast<double>(b.knots) / a.knots);
  const double at_target = b.knots * std::pow(b.rmse_percent / target, 1 / p);
  const double needed = kLastRoundShare * (at_target - b.knots);
  if (!(needed < planned)) return planned;
  return std::max(kMinFoldKnots, static_cast<int>(std::ceil(needed)));
}

Status SplineFitter::State::RunRound() {
  const FitOptions& o = options;
  SplineModel& model = result.model;
  FitStatistics& stats = model.statistics;
  const int round = static_cast<int>(stats.rounds.size());
  const Stopwatch round_clock;
  RoundDetails details;

  // 1. Knot placement with the existing knots fixed. No room for the
  // round's knots: the rounds so far are the result.
  Report(FitStage::kKnotPlacement, round, kRoundStageStart[0]);
  Stopwatch stage;
  const int grown = static_cast<int>(std::min<double>(
      o.knots_growth * static_cast<double>(model.knots.rows()), 1e7));
  const int new_knots = round == 0 && o.initial_knots > 0 ? o.initial_knots
                        : fold_round
                            ? std::max(kMinFoldKnots, o.knots_per_round / 4)
                            : KnotsToTarget(std::max(o.knots_per_round, grown));
  const bool feature_round = round == 0 && feature_knots.rows() > 0;
  // Steps 1-3 again, with the density floored, when the basis on the placed
  // knots has a hole (no support reaches part of the sphere; kInvalidInput
  // from the basis): a density too peaked for that many knots put them all
  // in a few places (a split mesh's curvedness is 0 inside each of its flat
  // triangles, so its round 0 puts every knot on the old edges).
  SphericalDensity floored;
  const SphericalDensity* placing_density = &density;
  KnotPlacement placement;
  DelaunayConfigurations configurations, knot_triangles;
  std::optional<Problem> built;
  for (int attempt = 0;; ++attempt) {
    // Too many to keep apart: as many as fit, halving down to kMinFoldKnots.
    int placing = new_knots;
    StatusOr<KnotPlacement> placed =
        feature_round
            ? FeatureKnotPlacement(feature_knots)
            : PlaceKnots(*placing_density, model.knots, placing, CvtOptions());
    auto no_room = [&] {
      return !placed.ok() && round > 0 &&
             placed.status().code() == StatusCode::kUnsupported;
    };
    while (no_room() && placing > kMinFoldKnots) {
      placing = std::max(kMinFoldKnots, placing / 2);
      placed = PlaceKnots(*placing_density, model.knots, placing, CvtOptions());
    }
    if (no_room()) {
      return Finish(
          false, "no room for more knots (" + placed.status().message() + ")");
    }
    SDCB_RETURN_IF_ERROR(placed.status());
    placement = std::move(placed).value();
    // The corners' clusters stay exact: a grid cell (7.6e-5 rad at 16 bits)
    // would break the co-circularity that makes the creases (the file then
    // stores the knots as they are).
    if (o.knot_grid_bits > 0 && !feature_round) {
      SnapNewKnots(o.knot_grid_bits, &placement);
    }
    details.timings.knot_placement += stage.Seconds();
    details.cvt_initial_energy = placement.initial_energy;
    details.cvt_final_energy = placement.final_energy;
    details.cvt_iterations = placement.iterations;
    details.min_knot_separation = placement.min_separation;

    // 2. Configurations; a round that would exceed the control-point cap is
    // not added.
    Report(FitStage::kConfigurations, round, kRoundStageStart[1]);
    stage = Stopwatch();
    SDCB_ASSIGN_OR_RETURN(configurations, ComputeDelaunayConfigurations(
                                              placement.knots, o.degree));
    SDCB_ASSIGN_OR_RETURN(knot_triangles,
                          ComputeDelaunayConfigurations(placement.knots, 0));
    details.timings.configurations += stage.Seconds();
    if (round > 0 &&
        static_cast<int>(configurations.sets.size()) > o.max_control_points) {
      return Finish(false, "the next round would exceed " +
                               std::to_string(o.max_control_points) +
                               " control points");
    }

    // 3. Basis, samples, design matrix; 4. least squares.
    Report(FitStage::kBasis, round, kRoundStageStart[2]);
    stage = Stopwatch();
    StatusOr<Problem> problem =
        BuildProblem(feature_round, placement.knots, configurations,
                     knot_triangles, &details);
    if (problem.ok()) {
      built.emplace(std::move(problem).value());
      break;
    }
    if (feature_round ||
        attempt == static_cast<int>(std::size(kHoleRetryFloors)) ||
        problem.status().code() != StatusCode::kInvalidInput) {
      return problem.status();
    }
    details.timings.basis += stage.Seconds();
    stage = Stopwatch();
    floored = density;
    floored.values = density.values.cwiseMax(kHoleRetryFloors[attempt] *
                                             density.values.maxCoeff());
    placing_density = &floored;
    ++details.hole_retries;
  }
  const Eigen::MatrixX3d& knots = placement.knots;
  Problem& problem = *built;
  details.timings.basis += stage.Seconds();
  Report(FitStage::kSolve, round, kRoundStageStart[3]);
  stage = Stopwatch();
  SDCB_ASSIGN_OR_RETURN(Eigen::MatrixX3d control_points, Solve(problem));
  Eigen::MatrixX3d fitted = problem.data * control_points;
  details.timings.solve = stage.Seconds();

  // 5. Measure; a round that meets the target is confirmed by the final
  // measurement.
  Report(FitStage::kMeasure, round, kRoundStageStart[4]);
  stage = Stopwatch();
  const Eigen::Index nv = mesh.vertices.rows();
  const FitSamples& samples = problem.samples;
  // The mesh -> surface half bounded by the parametric residual at the rows
  // of the data term (the vertices and the points inside split triangles,
  // or a thinned data term's kept rows), each standing for its area.
  std::optional<SphericalSpline> surface_or;
  std::optional<SurfaceDeviation> deviation_or;
  Eigen::MatrixX3d residuals;
  auto measure_round = [&](DcbBasis basis) -> Status {
    SDCB_ASSIGN_OR_RETURN(SphericalSpline spline,
                          SphericalSpline::Create(
                              std::move(basis), control_points, o.basis_form));
    surface_or.emplace(std::move(spline));
    SDCB_ASSIGN_OR_RETURN(SurfaceDeviation measured,
                          Measure(*surface_or, nullptr, false));
    residuals = fitted - samples.targets;
    SetMeshToSurface(100.0 * residuals.rowwise().norm(), samples.weights,
                     &measured);
    details.estimated_rmse_percent =
        EstimatedRms(measured, residuals, RowNormals(samples), samples.weights);
    deviation_or.emplace(std::move(measured));
    return Status::Ok();
  };
  SDCB_RETURN_IF_ERROR(measure_round(std::move(problem.basis)));
  // A round that folds where it otherwise meets the target: its folds
  // removed by the least change of its fit, and the round measured again.
  // The repair looks at the final measurement's lattice, whose fold test
  // decides the round: where that lattice has no fold (left or repaired),
  // the round goes on to the final measurement though its own coarser
  // lattice saw one. Folds over more of the area than the repair takes on
  // at the round's own lattice (which sees fewer) are not tried.
  bool final_lattice_unfolded = false;
  if (deviation_or->folded_area_percent > 0 &&
      deviation_or->folded_area_percent <=
          FoldRepairOptions().max_folded_percent &&
      std::min(deviation_or->rms_percent, details.estimated_rmse_percent) <=
          o.rmse_percent) {
    SDCB_ASSIGN_OR_RETURN(
        const FoldRepairResult repair,
        RepairRoundFolds(problem, surface_or->basis(), &control_points));
    details.fold_repair_iterations = repair.iterations;
    details.folded_before_repair_percent = repair.folded_before_percent;
    details.fold_repaired = repair.changed;
    final_lattice_unfolded = repair.folded_after_percent == 0;
    if (repair.changed) {
      fitted = problem.data * control_points;
      SDCB_RETURN_IF_ERROR(measure_round(DcbBasis(surface_or->basis())));
    }
  }
  const SphericalSpline& surface = *surface_or;
  SurfaceDeviation& deviation = *deviation_or;
  // F(u_i) at every vertex: the first rows of unthinned samples; for thinned
  // ones evaluated only for a round measured densely (below).
  Eigen::MatrixX3d vertex_points;
  if (!samples.thinned) vertex_points = fitted.topRows(nv);
  // A round's own measurement bounds the mesh -> surface half by the
  // parametric residual, which overstates it where the map shears (up to
  // 1.3 times on CGAL's meshes): the targets are judged on the final
  // measurement only, run when nothing folds and the round's rms, or its
  // first-order estimate (within 0.90-1.21 of the dense rms on them,
  // docs/FITTING.md), meets the target.
  details.round_rmse_percent = deviation.rms_percent;
  if (std::min(deviation.rms_percent, details.estimated_rmse_percent) <=
          o.rmse_percent &&
      (deviation.folded_area_percent == 0 || final_lattice_unfolded)) {
    if (samples.thinned) {
      vertex_points = VertexPoints(surface, samples, fitted);
    }
    SDCB_ASSIGN_OR_RETURN(deviation, Measure(surface, &vertex_points, true));
    details.closest_points = true;
    details.mesh_samples = deviation.mesh_samples;
    details.mesh_to_surface_max_bound_percent =
        deviation.mesh_to_surface_max_bound_percent;
  }
  const bool reached =
      details.closest_points &&
      MeetsTarget(deviation.rms_percent, deviation.hausdorff_percent,
                  deviation.folded_area_percent);
  details.surface_samples = deviation.surface_samples;
  details.timings.measure = stage.Seconds();

  // The round's statistics; the vertex errors are the paper's measure,
  // |F(u_i) - x_i|, where F(u_i) is known; a round of thinned samples that
  // was not measured densely gives each vertex its cell's kept row's.
  const Eigen::VectorXd vertex_errors =
      vertex_points.rows() == nv
          ? Eigen::VectorXd(100.0 *
                            (vertex_points - mesh.vertices).rowwise().norm())
          : CellVertexErrors(samples, fitted);
  RoundStatistics rs;
  rs.round = round;
  rs.knots = static_cast<int>(knots.rows());
  rs.control_points = static_cast<int>(control_points.rows());
  rs.rmse_percent = deviation.rms_percent;
  rs.max_error_percent = deviation.hausdorff_percent;
  // The statistics at the input's vertices (a split mesh's first rows).
  const Eigen::VectorXd input_errors = vertex_errors.head(input_vertices);
  rs.vertex_rmse_percent = std::sqrt(input_errors.squaredNorm() /
                                     std::max<Eigen::Index>(input_vertices, 1));
  rs.vertex_max_error_percent =
      input_vertices > 0 ? input_errors.maxCoeff() : 0;
  rs.folded_area_percent = deviation.folded_area_percent;
  model.knots = knots;
  model.configurations = std::move(configurations);
  model.control_points = control_points;
  result.vertex_errors_percent = input_errors;
  vertex_errors_exact = vertex_points.rows() == nv;
  stats.rounds.push_back(rs);
  stats.final_result = rs;
  details.timings.total = round_clock.Seconds();
  AddRoundStages(details.timings, &result.timings);
  result.round_details.push_back(details);
  if (!best || Better(rs, best->model.statistics.final_result)) {
    best = Candidate{model, input_errors, vertex_errors_exact};
  }
  if (!most_accurate ||
      IsBetterFallback(rs, most_accurate->model.statistics.final_result,
                       /*accept_folds=*/true)) {
    most_accurate = Candidate{model, input_errors, vertex_errors_exact};
  }

  // 6. Stop, or go on. Met the target but folded: the next rounds put fewer
  // knots, only where the surface folds, a few times at most.
  if (reached) {
    result.features_kept = feature_round;
    return Finish(true, "");
  }
  if (feature_round) {
    // The clusters alone did not meet the target (features that are not
    // between corners, curved ones, or a shape that needs more knots): the
    // fit starts again from its usual round 0, which does not keep them.
    DropFeatureRound();
    return Status::Ok();
  }
  const bool only_folds =
      rs.rmse_percent <= o.rmse_percent && rs.folded_area_percent > 0;
  const std::string folds_left =
      "the surface still folds (narrow creases or thin parts the spline "
      "cannot follow yet)";
  if (only_folds && fold_rounds_in_a_row == 0) {
    folds_when_fold_rounds_began = rs.folded_area_percent;
  }
  if (only_folds && fold_rounds >= o.max_fold_rounds) {
    return Finish(false, folds_left);
  }
  if (fold_progress.Stalls(rs.knots, rs.folded_area_percent)) {
    return Finish(false, folds_left +
                             "; its folds do not shrink as knots are added (" +
                             ShortNumber(fold_progress.least_folded_percent()) +
                             " % of its area at " +
                             std::to_string(fold_progress.knots_at_least()) +
                             " knots, " + ShortNumber(rs.folded_area_percent) +
                             " % at " + std::to_string(rs.knots) + ")");
  }
  // Fold rounds that have not shrunk the folds give way to an ordinary
  // round (knots where the error is, and where it folds).
  const bool folds_stay =
      fold_rounds_in_a_row >= kFoldRoundsToShrink &&
      rs.folded_area_percent > kFoldShrink * folds_when_fold_rounds_began;
  if (round + 1 == o.max_rounds) {
    return Finish(false, only_folds
                             ? folds_left
                             : "the target was not reached within " +
                                   std::to_string(o.max_rounds) + " rounds");
  }
  fold_round = only_folds && !folds_stay;
  if (fold_round) {
    ++fold_rounds;
    ++fold_rounds_in_a_row;
  } else {
    fold_rounds_in_a_row = 0;
  }
  // A fit whose error falls too slowly to reach the target within the
  // rounds left (judged after six rounds) stops now rather than later.
  const int needed = EstimateRounds();
  const int left = o.max_rounds - round - 1;
  if (!only_folds && round >= kMinRoundsBeforeRateStop &&
      (needed < 0 || needed > left)) {
    const std::string error =
        rs.rmse_percent <= o.rmse_percent
            ? "the Hausdorff distance (" + ShortNumber(rs.max_error_percent) +
                  " %, target " + ShortNumber(MaxErrorTarget(o)) + " %)"
            : std::string("the error");
    return Finish(false,
                  needed < 0
                      ? error + " stopped falling"
                      : "at its current rate " + error + " needs about " +
                            std::to_string(needed) +
                            " more rounds, more than --max-rounds leaves (" +
                            std::to_string(left) + ")");
  }
  NextDensity(problem, fitted, vertex_errors, deviation);
  return Status::Ok();
}

FitResult SplineFitter::TakeResult() {
  State& s = *state_;
  if (s.options.store_parameters) {
    s.result.model.parameters = s.u.topRows(s.input_vertices);
  }
  s.result.timings.total = s.clock.Seconds();
  s.Report(FitStage::kDone, rounds(), 0);
  FitResult out = std::move(s.result);
  state_.reset();
  return out;
}

namespace {

StatusOr<FitResult> RunFit(const TriangleMesh& mesh,
                           const FitOptions& options) {
  SDCB_ASSIGN_OR_RETURN(SplineFitter fitter,
                        SplineFitter::Create(mesh, options));
  while (!fitter.finished()) SDCB_RETURN_IF_ERROR(fitter.AddRound());
  return fitter.TakeResult();
}

// Whether the mesh passes through itself (FindSelfIntersections), on at
// most `threads` threads (0: as many as the caller's context allows). A
// surface that follows such a mesh folds where it does, split or not.
bool IntersectsItself(const TriangleMesh& mesh, int threads) {
  const int automatic = tbb::task_arena::automatic;  // copied, as in Create
  tbb::task_arena arena(threads > 0 ? threads : automatic);
  return arena.execute([&] {
    const StatusOr<SelfIntersectionReport> report = FindSelfIntersections(mesh);
    return report.ok() && report->checked && report->intersecting_pairs > 0;
  });
}

bool AnyRoundFolded(const FitStatistics& stats) {
  for (const RoundStatistics& r : stats.rounds) {
    if (r.folded_area_percent > 0) return true;
  }
  return false;
}

// Whether `candidate`, a further fit of the same input, should be returned
// instead of `current`, which misses its target: one that reaches; between
// two folded fits, the one folded less (the folds are what the further fits
// are for); else IsBetterFallback's order.
bool ReplacesMissedFit(const FitResult& candidate, const FitResult& current,
                       const FitOptions& options) {
  if (candidate.reached_target()) return true;
  const RoundStatistics& a = candidate.model.statistics.final_result;
  const RoundStatistics& b = current.model.statistics.final_result;
  if (!options.fallback_accepts_folds && a.folded_area_percent > 0 &&
      b.folded_area_percent > 0) {
    return a.folded_area_percent < b.folded_area_percent;
  }
  return IsBetterFallback(a, b, options.fallback_accepts_folds);
}

bool MissedFolded(const FitResult& fit) {
  return !fit.reached_target() && AnyRoundFolded(fit.model.statistics);
}

// `kept` gets the seconds of `other`, a fit of the same input not returned.
void AddSeconds(const FitResult& other, FitResult* kept) {
  AddRoundStages(other.timings, &kept->timings);
  kept->timings.parameterization += other.timings.parameterization;
  kept->timings.total += other.timings.total;
}

std::string Summary(const FitResult& fit) {
  const RoundStatistics& r = fit.model.statistics.final_result;
  return std::to_string(r.control_points) + " control points, rms " +
         ShortNumber(r.rmse_percent) + " %, folded " +
         ShortNumber(r.folded_area_percent) + " % of its area";
}

// `options` whose progress reports carry `retry`.
FitOptions Retry(const FitOptions& options, const std::string& retry) {
  FitOptions again = options;
  if (options.progress) {
    again.progress = [&options, retry](const FitProgress& p) {
      FitProgress labelled = p;
      labelled.retry = retry;
      options.progress(labelled);
    };
  }
  return again;
}

// The fit on the split input (FitOptions::retry_map_vertices) when `first`
// calls for it, and the better of the two.
FitResult FitAgainSplit(const TriangleMesh& mesh, const FitOptions& options,
                        FitResult first, bool intersects_itself) {
  // A fit that reached the target smooth with more control points than the
  // input has vertices (its knots about as dense as the input's triangles:
  // the spline follows the map's jumps between them, as on a CAD solid's
  // few large triangles whose edges it rounds); a fit that missed with a
  // folded round, on a mesh that does not pass through itself.
  const RoundStatistics& returned = first.model.statistics.final_result;
  const bool dense_knots = first.reached_target() && !first.features_kept &&
                           returned.control_points > mesh.num_vertices();
  const bool folded = MissedFolded(first) && !intersects_itself;
  if (!dense_knots && !folded) return first;
  if (!SplitForMap(mesh, options.retry_map_vertices)) return first;
  FitOptions again = Retry(options, "split");
  again.map_vertices = options.retry_map_vertices;
  // Smooth: corners' clusters, had they been kept, would have ended it above
  // (and they are tried on the input's own triangles only).
  again.keep_features = false;
  again.max_control_points =
      std::min(options.max_control_points, returned.control_points);
  StatusOr<FitResult> second = RunFit(mesh, again);
  if (!second.ok()) return first;
  // Of two that reach, the one with fewer control points.
  const bool take_second =
      first.reached_target()
          ? second->reached_target() &&
                second->model.statistics.final_result.control_points <
                    returned.control_points
          : ReplacesMissedFit(*second, first, options);
  FitResult& kept = take_second ? *second : first;
  const FitResult& other = take_second ? first : *second;
  kept.split_retry_run = true;
  kept.split_retry_returned = take_second;
  AddSeconds(other, &kept);
  if (!take_second && !first.reached_target()) {
    kept.shortfall += "; a second fit on the input split to " +
                      std::to_string(second->map_vertices) +
                      " vertices did no better (" + Summary(*second) + ")";
  }
  return std::move(kept);
}

}  // namespace

StatusOr<FitResult> FitSphericalSpline(const TriangleMesh& mesh,
                                       const FitOptions& options) {
  SDCB_ASSIGN_OR_RETURN(FitResult first, RunFit(mesh, options));
  if (options.map_vertices > 0 ||
      mesh.num_vertices() >= options.retry_map_vertices) {
    return first;
  }
  const bool intersects_itself =
      MissedFolded(first) && IntersectsItself(mesh, options.threads);
  FitResult best =
      FitAgainSplit(mesh, options, std::move(first), intersects_itself);
  // Thin parts: the map's area term weaker; on the split input when the
  // fit to return has more control points than the input has vertices.
  std::string tried;
  for (double factor : options.retry_lambda_factors) {
    if (!MissedFolded(best) || intersects_itself) break;
    const double lambda = options.lambda * factor;
    const bool split = best.model.statistics.final_result.control_points >
                           mesh.num_vertices() &&
                       SplitForMap(mesh, options.retry_map_vertices);
    FitOptions lower = Retry(options, std::string(split ? "split, " : "") +
                                          "lambda " + ShortNumber(lambda));
    lower.lambda = lambda;
    if (split) {
      lower.map_vertices = options.retry_map_vertices;
      lower.keep_features = false;
    }
    StatusOr<FitResult> retry = RunFit(mesh, lower);
    if (!retry.ok()) break;
    const bool take = ReplacesMissedFit(*retry, best, options);
    FitResult& kept = take ? *retry : best;
    FitResult& other = take ? best : *retry;
    kept.lambda_retries_run = best.lambda_retries_run + 1;
    kept.split_retry_run = best.split_retry_run;
    kept.split_retry_returned = take ? false : best.split_retry_returned;
    AddSeconds(other, &kept);
    if (take && !kept.reached_target()) {
      kept.shortfall += "; this is a fit with lambda " + ShortNumber(lambda) +
                        ", folded less than the one before it (" +
                        Summary(other) + ")";
    } else if (!take) {
      tried += (tried.empty() ? "" : "; ") + std::string("lambda ") +
               ShortNumber(lambda) + ": " + Summary(*retry);
    }
    if (take) best = std::move(*retry);
  }
  if (!tried.empty() && !best.reached_target()) {
    best.shortfall +=
        "; fits with a smaller lambda did no better (" + tried + ")";
  }
  return best;
}

}  // namespace sdcb
