#include "sdcb/core/fit/fit_round.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/fit/feature_round.h"
#include "sdcb/core/fit/fold_repair.h"
#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/measure/boundary_deviation.h"
#include "sdcb/core/sphere/point_kd_tree.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/sphere/unit_vector_grid.h"

namespace sdcb {
namespace {

// The floors of the density (fractions of its maximum) with which a round is
// placed again when the basis on its knots has a hole (PlaceRound).
constexpr double kHoleRetryFloors[] = {0.01, 1.0};

// Samples of an open part's boundary per knot spacing (MeasureFitBoundary).
constexpr double kBoundarySamplesPerSpacing = 16;

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

// Step 1: the round's knots (`placement`), `new_knots` placed by `density`
// with `fixed_knots` fixed, or `feature_knots` alone when not null. No room
// for that many: as many as fit, halving down to kMinFoldKnots; no room for
// those either: `shortfall` says so and the rounds so far are the result.
Status PlaceRoundKnots(const RoundContext& c, const SphericalDensity& density,
                       const Eigen::MatrixX3d& fixed_knots, int new_knots,
                       const Eigen::MatrixX3d* feature_knots,
                       KnotPlacement* placement, std::string* shortfall) {
  int placing = new_knots;
  StatusOr<KnotPlacement> placed =
      feature_knots != nullptr
          ? StatusOr<KnotPlacement>(FeatureKnotPlacement(*feature_knots))
          : PlaceKnots(density, fixed_knots, placing, CvtOptions());
  auto no_room = [&] {
    return !placed.ok() && c.round > 0 &&
           placed.status().code() == StatusCode::kUnsupported;
  };
  while (no_room() && placing > kMinFoldKnots) {
    placing = std::max(kMinFoldKnots, placing / 2);
    placed = PlaceKnots(density, fixed_knots, placing, CvtOptions());
  }
  if (no_room()) {
    *shortfall = "no room for more knots (" + placed.status().message() + ")";
    return Status::Ok();
  }
  SDCB_RETURN_IF_ERROR(placed.status());
  *placement = std::move(placed).value();
  // The corners' clusters stay exact: a grid cell (7.6e-5 rad at 16 bits)
  // would break the co-circularity that makes the creases (the file then
  // stores the knots as they are).
  if (c.options.knot_grid_bits > 0 && feature_knots == nullptr) {
    SnapNewKnots(c.options.knot_grid_bits, placement);
  }
  return Status::Ok();
}

// The round's rms with the mesh -> surface half estimated by the residuals'
// components along the mesh's normals (the distance to first order,
// without the tangential part by which the parametric bound overstates
// it), at mesh samples of the given normals and area weights.
double EstimatedRms(const SurfaceDeviation& deviation,
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
// The data rows' area weights as the mesh -> surface half counts them: an
// open part's fill rows (inside a fill triangle, or at a fill vertex) count
// nothing, the part's rows their whole area.
Eigen::VectorXd MeasuredWeights(const FitMesh& fit, const FitSamples& samples) {
  Eigen::VectorXd weights = samples.weights;
  if (!fit.trimmed()) return weights;
  for (Eigen::Index r = 0; r < weights.size(); ++r) {
    int vertex = -1, triangle = -1;
    if (samples.thinned) {
      vertex = samples.row_vertex[r];
      if (vertex < 0) triangle = samples.triangle[r];
    } else if (r < samples.num_vertices) {
      vertex = static_cast<int>(r);
    } else {
      triangle = samples.triangle[r - samples.num_vertices];
    }
    if (vertex >= fit.input_vertices || triangle >= fit.input_faces) {
      weights[r] = 0;
    }
  }
  return weights;
}

// The unit mesh normal at every row of `samples`: a vertex's
// (VertexNormals), or the triangle's of a point inside one.
Eigen::MatrixX3d RowNormals(const FitMesh& fit, const FitSamples& samples) {
  const TriangleMesh& mesh = fit.mesh;
  if (samples.thinned) return samples.row_normal;
  const Eigen::Index nv = samples.num_vertices;
  Eigen::MatrixX3d normals(samples.points.rows(), 3);
  normals.topRows(nv) = fit.vertex_normal;
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
Eigen::MatrixX3d VertexPoints(const FitMesh& fit,
                              const SphericalSpline& surface,
                              const FitSamples& samples,
                              const Eigen::MatrixX3d& fitted) {
  const Eigen::Index nv = fit.mesh.vertices.rows();
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
  for (size_t i = 0; i < rest.size(); ++i) points.row(i) = fit.u.row(rest[i]);
  const Eigen::MatrixX3d values = surface.EvaluateMany(points);
  for (size_t i = 0; i < rest.size(); ++i) out.row(rest[i]) = values.row(i);
  return out;
}
// Per vertex: the parametric residual of the row kept for its cell
// (thinned samples), percent.
Eigen::VectorXd CellVertexErrors(const FitSamples& samples,
                                 const Eigen::MatrixX3d& fitted) {
  Eigen::VectorXd out(samples.vertex_row.size());
  for (size_t v = 0; v < samples.vertex_row.size(); ++v) {
    const int r = samples.vertex_row[v];
    out[v] = 100.0 * (fitted.row(r) - samples.targets.row(r)).norm();
  }
  return out;
}

// RepairFolds (core/fit/fold_repair.h) on the round's solution, at the
// lattice of the final measurement, its steps allowed the Hausdorff target
// as distance; `basis` is the round's (moved from the problem into the
// round's surface).
StatusOr<FoldRepairResult> RepairRoundFolds(const RoundContext& c,
                                            const RoundProblem& p,
                                            const DcbBasis& basis,
                                            Eigen::MatrixX3d* control_points) {
  const FitOptions& o = c.options;
  // The final measurement's lattice, whose fold test decides the round.
  DeviationOptions lattice;
  lattice.min_surface_samples = std::max(
      o.final_surface_samples,
      o.round_samples_per_knot * static_cast<int>(basis.knots().rows()));
  lattice.closest_points = false;
  lattice.search_all_vertices = false;
  lattice.mesh_to_surface = false;
  lattice.region = &c.fit.region;
  FoldRepairOptions repair;
  repair.max_distance_percent =
      std::max(0.0, c.stop.target().max_error_percent);
  return RepairFolds(basis, o.basis_form,
                     RegularizedNormalMatrixLower(StackedDesign(o, c.fit, p),
                                                  o.regularization),
                     c.fit.measured(), *c.fit.mesh_distance, lattice, repair,
                     control_points);
}

// The round's own measurement of `solved`'s control points on `basis`: the
// surface -> mesh half at a lattice, the mesh -> surface half bounded by the
// parametric residual at the rows of the data term (the vertices and the
// points inside split triangles, or a thinned data term's kept rows), each
// standing for its area.
Status MeasureRound(const RoundContext& c, const FitSamples& samples,
                    DcbBasis basis, SolvedRound* solved,
                    RoundDetails* details) {
  SDCB_ASSIGN_OR_RETURN(
      SphericalSpline spline,
      SphericalSpline::Create(std::move(basis), solved->control_points,
                              c.options.basis_form));
  solved->surface.emplace(std::move(spline));
  SDCB_ASSIGN_OR_RETURN(
      SurfaceDeviation measured,
      MeasureFitSurface(c.options, c.fit, *solved->surface, nullptr, false));
  const Eigen::MatrixX3d residuals = solved->fitted - samples.targets;
  const Eigen::VectorXd weights = MeasuredWeights(c.fit, samples);
  SetMeshToSurface(100.0 * residuals.rowwise().norm(), weights, &measured);
  details->estimated_rmse_percent =
      EstimatedRms(measured, residuals, RowNormals(c.fit, samples), weights);
  solved->deviation = std::move(measured);
  return Status::Ok();
}

// Whether the round's rms, or its first-order estimate, meets the target.
bool RoundRmsMeetsTarget(const RoundContext& c, const SurfaceDeviation& d,
                         const RoundDetails& details) {
  return CompareWithTarget(
             c.stop.target(),
             std::min(d.rms_percent, details.estimated_rmse_percent),
             d.hausdorff_percent, d.folded_area_percent)
      .rms;
}

// A round that folds where it otherwise meets the target: its folds
// removed by the least change of its fit, and the round measured again.
// The repair looks at the final measurement's lattice, whose fold test
// decides the round: where that lattice has no fold (left or repaired),
// the round goes on to the final measurement though its own coarser
// lattice saw one (the result: whether it has none). Folds over more of
// the area than the repair takes on at the round's own lattice (which sees
// fewer) are not tried.
StatusOr<bool> RepairSmallFolds(const RoundContext& c,
                                const RoundProblem& problem,
                                SolvedRound* solved, RoundDetails* details) {
  const SurfaceDeviation& d = solved->deviation;
  if (!(d.folded_area_percent > 0 &&
        d.folded_area_percent <= FoldRepairOptions().max_folded_percent &&
        RoundRmsMeetsTarget(c, d, *details))) {
    return false;
  }
  SDCB_ASSIGN_OR_RETURN(const FoldRepairResult repair,
                        RepairRoundFolds(c, problem, solved->surface->basis(),
                                         &solved->control_points));
  details->fold_repair_iterations = repair.iterations;
  details->folded_before_repair_percent = repair.folded_before_percent;
  details->fold_repaired = repair.changed;
  if (repair.changed) {
    solved->fitted = problem.data * solved->control_points;
    SDCB_RETURN_IF_ERROR(MeasureRound(c, problem.samples,
                                      DcbBasis(solved->surface->basis()),
                                      solved, details));
  }
  return repair.folded_after_percent == 0;
}

}  // namespace

StatusOr<PlacedRound> PlaceRound(const RoundContext& c,
                                 const SphericalDensity& density,
                                 const Eigen::MatrixX3d& fixed_knots,
                                 int new_knots,
                                 const Eigen::MatrixX3d* feature_knots,
                                 RoundDetails* details) {
  const FitOptions& o = c.options;
  c.progress.StartRoundStage(FitStage::kKnotPlacement, c.round);
  Stopwatch stage;
  PlacedRound placed;
  // Steps 1-3 again, with the density floored, when the basis on the placed
  // knots has a hole (no support reaches part of the sphere; kInvalidInput
  // from the basis): a density too peaked for that many knots put them all
  // in a few places (a split mesh's curvedness is 0 inside each of its flat
  // triangles, so its round 0 puts every knot on the old edges).
  SphericalDensity floored;
  const SphericalDensity* placing_density = &density;
  DelaunayConfigurations knot_triangles;
  for (int attempt = 0;; ++attempt) {
    SDCB_RETURN_IF_ERROR(PlaceRoundKnots(c, *placing_density, fixed_knots,
                                         new_knots, feature_knots,
                                         &placed.placement, &placed.shortfall));
    if (!placed.shortfall.empty()) return placed;
    const KnotPlacement& placement = placed.placement;
    details->timings.knot_placement += stage.Seconds();
    details->cvt_initial_energy = placement.initial_energy;
    details->cvt_final_energy = placement.final_energy;
    details->cvt_iterations = placement.iterations;
    details->min_knot_separation = placement.min_separation;

    // 2. Configurations; a round that would exceed the control-point cap is
    // not added.
    c.progress.StartRoundStage(FitStage::kConfigurations, c.round);
    stage = Stopwatch();
    SDCB_ASSIGN_OR_RETURN(
        placed.configurations,
        ComputeDelaunayConfigurations(placement.knots, o.degree));
    SDCB_ASSIGN_OR_RETURN(knot_triangles,
                          ComputeDelaunayConfigurations(placement.knots, 0));
    details->timings.configurations += stage.Seconds();
    if (std::optional<std::string> limit = c.stop.ControlPointLimit(
            c.round, static_cast<int>(placed.configurations.sets.size()))) {
      placed.shortfall = std::move(*limit);
      return placed;
    }
    if (c.stop.Pauses(c.round,
                      static_cast<int>(placed.configurations.sets.size()))) {
      placed.paused = true;
      placed.held_control_points =
          static_cast<int>(placed.configurations.sets.size());
      return placed;
    }

    // 3. Basis, samples, design matrix.
    c.progress.StartRoundStage(FitStage::kBasis, c.round);
    stage = Stopwatch();
    StatusOr<RoundProblem> problem = BuildRoundProblem(
        o, c.fit, placement.knots, placed.configurations, knot_triangles,
        feature_knots != nullptr ? &c.features : nullptr, details);
    if (problem.ok()) {
      placed.problem.emplace(std::move(problem).value());
      break;
    }
    if (feature_knots != nullptr ||
        attempt == static_cast<int>(std::size(kHoleRetryFloors)) ||
        problem.status().code() != StatusCode::kInvalidInput) {
      return problem.status();
    }
    details->timings.basis += stage.Seconds();
    stage = Stopwatch();
    floored = density;
    floored.values = density.values.cwiseMax(kHoleRetryFloors[attempt] *
                                             density.values.maxCoeff());
    placing_density = &floored;
    ++details->hole_retries;
  }
  details->timings.basis += stage.Seconds();
  return placed;
}

StatusOr<SolvedRound> SolveAndMeasure(const RoundContext& c,
                                      RoundProblem* problem,
                                      RoundDetails* details) {
  // 4. Least squares.
  c.progress.StartRoundStage(FitStage::kSolve, c.round);
  Stopwatch stage;
  SolvedRound solved;
  SDCB_ASSIGN_OR_RETURN(solved.control_points,
                        SolveRoundProblem(c.options, c.fit, *problem));
  solved.fitted = problem->data * solved.control_points;
  details->timings.solve = stage.Seconds();

  // 5. Measure; a round that may meet the target is confirmed by the final
  // measurement.
  c.progress.StartRoundStage(FitStage::kMeasure, c.round);
  stage = Stopwatch();
  const FitSamples& samples = problem->samples;
  SDCB_RETURN_IF_ERROR(
      MeasureRound(c, samples, std::move(problem->basis), &solved, details));
  SDCB_ASSIGN_OR_RETURN(const bool final_lattice_unfolded,
                        RepairSmallFolds(c, *problem, &solved, details));
  SurfaceDeviation& deviation = solved.deviation;
  // F(u_i) at every vertex: the first rows of unthinned samples; for thinned
  // ones evaluated only for a round measured densely (below).
  if (!samples.thinned) {
    solved.vertex_points = solved.fitted.topRows(c.fit.mesh.vertices.rows());
  }
  // A round's own measurement bounds the mesh -> surface half by the
  // parametric residual, which overstates it where the map shears (up to
  // 1.3 times on CGAL's meshes): the targets are judged on the final
  // measurement only, run when nothing folds and the round's rms, or its
  // first-order estimate (within 0.90-1.21 of the dense rms on them,
  // docs/FITTING.md), meets the target.
  details->round_rmse_percent = deviation.rms_percent;
  if (RoundRmsMeetsTarget(c, deviation, *details) &&
      (deviation.folded_area_percent == 0 || final_lattice_unfolded)) {
    if (samples.thinned) {
      solved.vertex_points =
          VertexPoints(c.fit, *solved.surface, samples, solved.fitted);
    }
    SDCB_ASSIGN_OR_RETURN(deviation,
                          MeasureFitSurface(c.options, c.fit, *solved.surface,
                                            &solved.vertex_points, true));
    details->closest_points = true;
    details->mesh_samples = deviation.mesh_samples;
    details->mesh_to_surface_max_bound_percent =
        deviation.mesh_to_surface_max_bound_percent;
  }
  solved.reached = details->closest_points &&
                   CompareWithTarget(c.stop.target(), deviation.rms_percent,
                                     deviation.hausdorff_percent,
                                     deviation.folded_area_percent,
                                     deviation.boundary_percent)
                       .reached();
  details->surface_samples = deviation.surface_samples;
  details->timings.measure = stage.Seconds();
  return solved;
}

namespace {

// An open part's boundary distance (core/measure/boundary_deviation.h):
// `surface`'s trims against the part's loops, sampled
// kBoundarySamplesPerSpacing times per knot spacing along them; percent.
StatusOr<double> MeasureFitBoundary(const FitMesh& fit,
                                    const SphericalSpline& surface) {
  std::vector<Eigen::MatrixX3d> loops;
  for (const std::vector<int>& loop : fit.boundary_loops) {
    Eigen::MatrixX3d x(static_cast<Eigen::Index>(loop.size()), 3);
    for (size_t i = 0; i < loop.size(); ++i) {
      x.row(static_cast<Eigen::Index>(i)) = fit.mesh.vertices.row(loop[i]);
    }
    loops.push_back(std::move(x));
  }
  // Sixteen samples per knot spacing along the trims (the spacing of K
  // knots spread evenly over the sphere, sqrt(4 pi / K) radians).
  const double spacing = std::sqrt(
      4 * kPi /
      std::max<double>(1.0, static_cast<double>(surface.knots().rows())));
  SDCB_ASSIGN_OR_RETURN(
      const BoundaryDeviation boundary,
      MeasureBoundaryDeviation(surface, fit.Trims(), loops, 1.0,
                               spacing / kBoundarySamplesPerSpacing));
  return boundary.max_percent();
}

}  // namespace

StatusOr<SurfaceDeviation> MeasureFitSurface(
    const FitOptions& options, const FitMesh& fit,
    const SphericalSpline& surface, const Eigen::MatrixX3d* vertex_points,
    bool final_measurement) {
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
  measure.region = &fit.region;
  std::optional<Eigen::MatrixX3d> part_points;
  if (fit.part && vertex_points != nullptr) {
    part_points = vertex_points->topRows(fit.part->vertices.rows());
  }
  SDCB_ASSIGN_OR_RETURN(
      SurfaceDeviation deviation,
      MeasureSurfaceDeviation(
          surface, fit.measured(), measure,
          part_points ? &*part_points : (fit.part ? nullptr : vertex_points),
          &*fit.mesh_distance));
  if (fit.trimmed()) {
    SDCB_ASSIGN_OR_RETURN(deviation.boundary_percent,
                          MeasureFitBoundary(fit, surface));
  }
  return deviation;
}

Eigen::VectorXd RoundVertexErrors(const FitMesh& fit, const FitSamples& samples,
                                  const Eigen::MatrixX3d& fitted,
                                  const Eigen::MatrixX3d& vertex_points) {
  if (vertex_points.rows() == fit.mesh.vertices.rows()) {
    return 100.0 * (vertex_points - fit.mesh.vertices).rowwise().norm();
  }
  return CellVertexErrors(samples, fitted);
}

void NextDensity(const FitOptions& options, const RoundProblem& p,
                 const Eigen::MatrixX3d& fitted,
                 const Eigen::VectorXd& vertex_errors,
                 const SurfaceDeviation& deviation, bool fold_round,
                 FitMesh* fit, SphericalDensity* density) {
  const TriangleMesh& mesh = fit->mesh;
  // The error of a vertex is the largest of its parametric residual, those
  // of the data samples inside its triangles, and the surface -> mesh
  // distance of the surface samples nearest to it on the sphere. A folded
  // sample counts as the largest error: knots go there. In a round after the
  // target was met, only there.
  const Eigen::Index first = p.samples.num_vertices;
  Eigen::VectorXd error = vertex_errors;
  for (size_t r = 0; r < p.samples.triangle.size(); ++r) {
    if (p.samples.triangle[r] < 0) continue;  // a thinned vertex row
    if (p.samples.triangle[r] >= fit->input_faces) continue;  // the fill
    const double e =
        100.0 *
        (fitted.row(first + r) - p.samples.targets.row(first + r)).norm();
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(p.samples.triangle[r], k);
      error[v] = std::max(error[v], e);
    }
  }
  if (fold_round) error.setConstant(0.0);
  // An open part's fill is not measured: no knots are placed for it.
  if (fit->trimmed()) {
    error.tail(error.size() - fit->input_vertices).setZero();
    // The boundary counts double: the export's boundary follows it.
    for (Eigen::Index v = 0; v < fit->input_vertices; ++v) {
      if (fit->on_boundary[v]) error[v] *= 2;
    }
  }
  const double worst =
      std::max(error.maxCoeff(),
               deviation.surface_sample_distance_percent.size()
                   ? deviation.surface_sample_distance_percent.maxCoeff()
                   : 0.0);
  for (Eigen::Index i = 0; i < deviation.surface_sample_points.rows(); ++i) {
    const PointKdTree::Neighbor n = fit->parameter_tree->Nearest(
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
  const StatusOr<Eigen::VectorXd>& area_ratio = fit->AreaRatio();
  if (values.ok() && area_ratio.ok()) {
    values = PullBackDensity(*values, *area_ratio);
  }
  if (values.ok()) density->values = std::move(values).value();
}

}  // namespace sdcb
