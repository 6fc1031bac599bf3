#include "sdcb/core/fit/round_problem.h"

#include <tbb/task_group.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/fit/feature_round.h"
#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/knots/feature_knots.h"
#include "sdcb/core/sphere/point_kd_tree.h"

namespace sdcb {
namespace {

// An open part's boundary is pinned: its vertex rows weigh kBoundaryWeight
// times their area, and rows on its edges (kBoundaryRowsAlong per edge, on
// the edge's arc, the mean row's weight times kBoundaryWeight) follow it
// between the vertices. The boundary is where the spline, held on one side
// only, leaves the part first, and the trims put it in the export.
constexpr int kBoundaryRowsAlong = 3;

void PinBoundary(const FitMesh& fit, FitSamples* samples) {
  const double mean_weight = samples->weights.mean();
  for (Eigen::Index r = 0; r < samples->weights.size(); ++r) {
    int vertex = -1;
    if (samples->thinned) {
      vertex = samples->row_vertex[r];
    } else if (r < samples->num_vertices) {
      vertex = static_cast<int>(r);
    }
    if (vertex >= 0 && vertex < fit.input_vertices && fit.on_boundary[vertex]) {
      samples->weights[r] *= kBoundaryWeight;
    }
  }
  std::vector<std::array<int, 2>> edges;
  for (const std::vector<int>& loop : fit.boundary_loops) {
    for (size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  AppendEdgeBandSamples(fit.mesh, fit.u, edges, {0.0}, kBoundaryRowsAlong,
                        kBoundaryWeight * mean_weight, samples);
}

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

}  // namespace

StatusOr<RoundProblem> BuildRoundProblem(
    const FitOptions& options, const FitMesh& fit,
    const Eigen::MatrixX3d& knots, const DelaunayConfigurations& configurations,
    const DelaunayConfigurations& knot_triangles, const MeshFeatures* features,
    RoundDetails* details) {
  const FitOptions& o = options;
  const bool feature_round = features != nullptr;
  const TriangleMesh& mesh = fit.mesh;
  const Eigen::MatrixX3d& u = fit.u;
  FitSampleOptions sample_options;
  sample_options.samples_per_spacing = o.samples_per_spacing;
  if (fit.trimmed()) sample_options.face_weights = &fit.face_weights;
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
    samples_or.emplace(BuildFitSamples(
        mesh, u, feature_round ? FeatureCorners(*features, u) : knots,
        sample_options, &fit.vertex_normal));
  });
  StatusOr<DcbBasis> basis_or = DcbBasis::Create(knots, configurations);
  const Status knots_covered =
      basis_or.ok() ? CheckKnotsCovered(*basis_or) : Status();
  side.wait();
  SDCB_ASSIGN_OR_RETURN(DcbBasis basis, std::move(basis_or));
  SDCB_RETURN_IF_ERROR(knots_covered);
  FitSamples samples = std::move(*samples_or);
  if (fit.trimmed()) PinBoundary(fit, &samples);
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
    AppendEdgeBandSamples(mesh, u, features->edges, offsets,
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
  return RoundProblem(std::move(basis), std::move(samples), &data,
                      std::move(bending), &hessian);
}

DesignMatrix StackedDesign(const FitOptions& options, const FitMesh& fit,
                           const RoundProblem& p) {
  // sqrt(w) rows of the data term, sqrt(fairness * area / 4 pi * weight)
  // rows of the bending energy (uv counted twice) with zero targets.
  const FitOptions& o = options;
  const Eigen::VectorXd data_scale = p.samples.weights.cwiseSqrt();
  std::vector<std::pair<const DesignMatrix*, const Eigen::VectorXd*>> parts = {
      {&p.data, &data_scale}};
  Eigen::VectorXd bend_scale, bend_scale_uv;
  if (o.fairness > 0) {
    bend_scale = (o.fairness * fit.mesh_area / (4.0 * kPi) * p.bending.weights)
                     .cwiseSqrt();
    bend_scale_uv = std::sqrt(2.0) * bend_scale;
    parts.push_back({&p.hessian.uu, &bend_scale});
    parts.push_back({&p.hessian.uv, &bend_scale_uv});
    parts.push_back({&p.hessian.vv, &bend_scale});
  }
  return StackScaledRows(parts);
}

StatusOr<Eigen::MatrixX3d> SolveRoundProblem(const FitOptions& options,
                                             const FitMesh& fit,
                                             const RoundProblem& p) {
  const FitOptions& o = options;
  const DesignMatrix design = StackedDesign(options, fit, p);
  const Eigen::VectorXd data_scale = p.samples.weights.cwiseSqrt();
  Eigen::MatrixX3d targets = Eigen::MatrixX3d::Zero(design.rows(), 3);
  targets.topRows(p.data.rows()) = data_scale.asDiagonal() * p.samples.targets;
  const Eigen::MatrixX3d prior = GrevillePrior(
      p.data, p.samples.targets,
      NearestSamplePrior(p.basis, *fit.parameter_tree, fit.mesh.vertices));
  LeastSquaresOptions ls;
  ls.regularization = o.regularization;
  return SolveRegularizedLeastSquares(design, targets, prior, ls);
}

}  // namespace sdcb
