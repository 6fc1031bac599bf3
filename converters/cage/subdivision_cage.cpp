#include "sdcb/converters/cage/subdivision_cage.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>
#include <sstream>
#include <utility>

#include "sdcb/core/common/stopwatch.h"
#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/knots/feature_knots.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/tessellate/feature_pattern.h"

namespace sdcb {
namespace {

// The k^2 sample parameters of one face: centres of a k by k grid (quads),
// centroids of the k^2 triangles of a level-k lattice (triangles).
std::vector<Eigen::Vector2d> FaceSampleParameters(bool triangle, int k) {
  std::vector<Eigen::Vector2d> uv;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < (triangle ? k - i : k); ++j) {
      if (!triangle) {
        uv.emplace_back((j + 0.5) / k, (i + 0.5) / k);
        continue;
      }
      uv.emplace_back((j + 1.0 / 3) / k, (i + 1.0 / 3) / k);
      if (i + j < k - 1) uv.emplace_back((j + 2.0 / 3) / k, (i + 2.0 / 3) / k);
    }
  }
  return uv;
}

// Area of the flat polygon through a face's sphere corners.
double SphereFaceArea(const SphereCage& layout, int f) {
  const auto& c = layout.faces[f];
  const Eigen::Vector3d a = layout.sphere_points.row(c[0]);
  const Eigen::Vector3d b = layout.sphere_points.row(c[1]);
  const Eigen::Vector3d d = layout.sphere_points.row(c[2]);
  if (layout.face_size == 3) return 0.5 * (b - a).cross(d - a).norm();
  const Eigen::Vector3d e = layout.sphere_points.row(c[3]);
  return 0.5 * (d - a).cross(e - b).norm();
}

// Rows of the cage's least-squares system in one design matrix: the samples'
// limit stencils (scaled by sqrt(weight)), then one umbrella row per cage
// vertex (scaled by `fairing_scale`).
DesignMatrix BuildCageDesign(const LimitSurface& limit,
                             const std::vector<int>& face,
                             const Eigen::MatrixX2d& uv,
                             const Eigen::VectorXd& row_scale,
                             const std::vector<std::vector<int>>& neighbours,
                             double fairing_scale) {
  const Eigen::Index ns = uv.rows();
  const Eigen::Index nv = static_cast<Eigen::Index>(neighbours.size());
  std::vector<std::vector<std::pair<int, double>>> rows(ns);
  tbb::parallel_for(
      tbb::blocked_range<Eigen::Index>(0, ns, 256),
      [&](const tbb::blocked_range<Eigen::Index>& range) {
        LimitStencil s;
        for (Eigen::Index r = range.begin(); r < range.end(); ++r) {
          limit.Stencil(face[r], uv(r, 0), uv(r, 1), &s);
          auto& row = rows[r];
          row.clear();
          for (size_t k = 0; k < s.indices.size(); ++k) {
            row.emplace_back(s.indices[k], row_scale[r] * s.position[k]);
          }
          // Ascending columns, repeated vertices (a tiny cage) summed.
          std::sort(row.begin(), row.end());
          size_t out = 0;
          for (size_t k = 0; k < row.size(); ++k) {
            if (out > 0 && row[out - 1].first == row[k].first) {
              row[out - 1].second += row[k].second;
            } else {
              row[out++] = row[k];
            }
          }
          row.resize(out);
        }
      });
  Eigen::Index nonzeros = 0;
  for (const auto& row : rows)
    nonzeros += static_cast<Eigen::Index>(row.size());
  for (const auto& n : neighbours)
    nonzeros += static_cast<Eigen::Index>(n.size()) + 1;
  DesignMatrix a(ns + nv, nv);
  a.resizeNonZeros(nonzeros);
  Eigen::Index at = 0;
  auto* outer = a.outerIndexPtr();
  for (Eigen::Index r = 0; r < ns; ++r) {
    outer[r] = static_cast<int>(at);
    for (const auto& [col, value] : rows[r]) {
      a.innerIndexPtr()[at] = col;
      a.valuePtr()[at++] = value;
    }
  }
  for (Eigen::Index i = 0; i < nv; ++i) {
    outer[ns + i] = static_cast<int>(at);
    const std::vector<int>& n = neighbours[i];
    const double w = -fairing_scale / static_cast<double>(n.size());
    bool placed = false;
    for (int j : n) {
      if (!placed && j > i) {
        a.innerIndexPtr()[at] = static_cast<int>(i);
        a.valuePtr()[at++] = fairing_scale;
        placed = true;
      }
      a.innerIndexPtr()[at] = j;
      a.valuePtr()[at++] = w;
    }
    if (!placed) {
      a.innerIndexPtr()[at] = static_cast<int>(i);
      a.valuePtr()[at++] = fairing_scale;
    }
  }
  outer[ns + nv] = static_cast<int>(at);
  return a;
}

std::vector<std::vector<int>> VertexNeighbours(const SphereCage& layout) {
  std::vector<std::vector<int>> n(layout.num_vertices());
  const int corners = layout.face_size;
  for (const auto& f : layout.faces) {
    for (int k = 0; k < corners; ++k) {
      const int a = f[k], b = f[(k + 1) % corners];
      n[a].push_back(b);
      n[b].push_back(a);
    }
  }
  for (auto& list : n) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return n;
}

Status CheckOptions(const CageOptions& o) {
  if (!(o.tolerance_percent > 0) || o.max_faces < 1 || o.max_rounds < 1 ||
      o.initial_levels < 0 || o.initial_levels > 8 || o.samples_per_side < 1 ||
      !(o.fairing >= 0) || o.parameter_corrections < 0 ||
      !(o.refine_share > 0 && o.refine_share <= 1) || !(o.max_growth > 1) ||
      !(o.length_unit > 0) || o.measure_samples < 1 ||
      o.round_samples_per_face < 1) {
    return InvalidArgumentError("subdivision cage: invalid options");
  }
  return Status::Ok();
}

}  // namespace

StatusOr<Eigen::MatrixX3d> FitCagePositions(const SphericalSpline& spline,
                                            const SphereCage& layout,
                                            const LimitSurface& limit,
                                            const CageOptions& options) {
  const PiecewiseSurface pieces(spline);
  return FitCagePositions(PiecewiseSplineSampler(spline, pieces), layout, limit,
                          options);
}

StatusOr<Eigen::MatrixX3d> FitCagePositions(const SurfaceSampler& spline,
                                            const SphereCage& layout,
                                            const LimitSurface& limit,
                                            const CageOptions& options) {
  SDCB_RETURN_IF_ERROR(CheckOptions(options));
  const int nf = layout.num_faces();
  if (limit.num_faces() != nf ||
      limit.num_vertices() != layout.num_vertices()) {
    return InvalidArgumentError(
        "subdivision cage: the layout and the limit surface differ");
  }
  const bool triangle = layout.face_size == 3;
  const std::vector<Eigen::Vector2d> local =
      FaceSampleParameters(triangle, options.samples_per_side);
  const int spf = static_cast<int>(local.size());
  const Eigen::Index ns = static_cast<Eigen::Index>(nf) * spf;

  // Samples: face, (u, v), sphere point; the spline there is the target,
  // and two points a small step away along a tangent frame give its
  // derivatives (finite differences).
  constexpr double kStep = 1e-6;
  std::vector<int> face(ns);
  Eigen::MatrixX2d uv(ns, 2);
  Eigen::MatrixX3d probes(3 * ns, 3);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < spf; ++k) {
      const Eigen::Index r = static_cast<Eigen::Index>(f) * spf + k;
      face[r] = f;
      uv.row(r) = local[k].transpose();
      const Eigen::Vector3d p = layout.SpherePoint(f, local[k][0], local[k][1]);
      Eigen::Vector3d a, b;
      TangentFrame(p, &a, &b);
      probes.row(3 * r) = p;
      probes.row(3 * r + 1) = (p + kStep * a).normalized();
      probes.row(3 * r + 2) = (p + kStep * b).normalized();
    }
  }
  Eigen::MatrixX3d points;
  spline.Sample(probes, &points, nullptr);
  Eigen::MatrixX3d targets(ns, 3);
  Eigen::VectorXd weight(ns);
  for (Eigen::Index r = 0; r < ns; ++r) {
    targets.row(r) = points.row(3 * r);
    const Eigen::Vector3d du =
        (points.row(3 * r + 1) - points.row(3 * r)).transpose() / kStep;
    const Eigen::Vector3d dv =
        (points.row(3 * r + 2) - points.row(3 * r)).transpose() / kStep;
    // The spline's area the sample stands for.
    weight[r] = du.cross(dv).norm() * SphereFaceArea(layout, face[r]) / spf;
  }
  const double mean = weight.mean();
  if (!(mean > 0) || !std::isfinite(mean)) {
    return InvalidInputError("subdivision cage: the spline has no area");
  }
  weight /= mean;
  const Eigen::VectorXd scale = weight.cwiseSqrt();
  const std::vector<std::vector<int>> neighbours = VertexNeighbours(layout);
  const double fairing_scale = std::sqrt(
      options.fairing * static_cast<double>(ns) / layout.num_vertices());

  // The prior of the regularization: the cage pulled through the spline.
  Eigen::MatrixX3d prior;
  spline.Sample(layout.sphere_points, &prior, nullptr);
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(ns + layout.num_vertices(), 3);
  rhs.topRows(ns) = scale.asDiagonal() * targets;
  Eigen::MatrixX3d cage;
  for (int pass = 0; pass <= options.parameter_corrections; ++pass) {
    if (pass > 0) {
      // Each sample moves to its closest point of the current limit surface.
      const PreparedLimit prepared(limit, cage);
      tbb::parallel_for(
          tbb::blocked_range<Eigen::Index>(0, ns, 256),
          [&](const tbb::blocked_range<Eigen::Index>& range) {
            for (Eigen::Index r = range.begin(); r < range.end(); ++r) {
              double u = uv(r, 0), v = uv(r, 1);
              ClosestOnLimitFace(prepared, face[r], targets.row(r).transpose(),
                                 2, &u, &v);
              uv(r, 0) = u;
              uv(r, 1) = v;
            }
          });
    }
    const DesignMatrix design =
        BuildCageDesign(limit, face, uv, scale, neighbours, fairing_scale);
    SDCB_ASSIGN_OR_RETURN(cage,
                          SolveRegularizedLeastSquares(design, rhs, prior));
  }
  return cage;
}

// The creased cage of a spline whose knots hold feature arcs cutting the
// sphere into quads (see the header): its vertices fitted, its limit surface
// measured at full density. Nothing when there are no such arcs.
StatusOr<std::optional<CageFit>> CreasedCage(const SphericalSpline& spline,
                                             const SurfaceSampler& sampler,
                                             const SplineImage& image,
                                             const CageOptions& options,
                                             CageDeviationOptions measure) {
  if (options.scheme != SubdivisionScheme::kCatmullClark)
    return std::optional<CageFit>();
  const KnotFeatureArcs arcs = FeatureArcsOfKnots(spline.knots());
  if (arcs.arcs.empty()) return std::optional<CageFit>();
  // Only faces that are quads themselves: cut into quads, the octahedron's
  // triangles fitted to rms 0.39 % (the fit trades the planes for the
  // parameterization's mismatch along them).
  StatusOr<FeatureQuadMesh> quads =
      FeatureQuads(arcs.corner_directions, arcs.arcs, /*split=*/false);
  if (!quads.ok() || quads->split ||
      static_cast<int>(quads->quads.size()) > options.max_faces) {
    return std::optional<CageFit>();
  }
  const int n = static_cast<int>(quads->points.rows());
  SphereCage layout;
  layout.face_size = 4;
  layout.sphere_points = quads->points;
  for (const std::array<int, 4>& quad : quads->quads) {
    layout.faces.push_back({quad[0], quad[1], quad[2], quad[3]});
    layout.face_cell.push_back(static_cast<int>(layout.face_cell.size()));
  }
  SDCB_ASSIGN_OR_RETURN(
      const LimitSurface limit,
      LimitSurface::Create(options.scheme, n, layout.faces,
                           /*approximation_level=*/4, quads->creases));
  SDCB_ASSIGN_OR_RETURN(Eigen::MatrixX3d positions,
                        FitCagePositions(sampler, layout, limit, options));
  measure.min_samples = options.measure_samples;
  SDCB_ASSIGN_OR_RETURN(
      CageDeviation deviation,
      MeasureCageDeviation(sampler, limit, positions, layout, measure, &image));
  CageFit fit;
  fit.cage.scheme = options.scheme;
  fit.cage.vertices = std::move(positions);
  fit.cage.layout = std::move(layout);
  fit.cage.creases = quads->creases;
  fit.deviation = std::move(deviation);
  CageRound r;
  r.faces = fit.cage.layout.num_faces();
  r.vertices = n;
  r.limit_rmse_percent = fit.deviation.rms_percent;
  r.limit_max_error_percent = fit.deviation.max_percent;
  fit.rounds.push_back(r);
  fit.stop_reason = "tolerance reached by the creased cage";
  return std::optional<CageFit>(std::move(fit));
}

StatusOr<CageFit> FitSubdivisionCage(const SphericalSpline& spline,
                                     const CageOptions& options) {
  SDCB_RETURN_IF_ERROR(CheckOptions(options));
  const Stopwatch start;
  const CageCellShape shape = options.scheme == SubdivisionScheme::kLoop
                                  ? CageCellShape::kTriangle
                                  : CageCellShape::kQuad;
  int levels = options.initial_levels;
  SphereCageTopology topology = SphereCageTopology::Create(shape, levels);
  while (levels > 0 && topology.cage().num_faces() > options.max_faces) {
    topology = SphereCageTopology::Create(shape, --levels);
  }
  if (topology.cage().num_faces() > options.max_faces) {
    return InvalidArgumentError(
        "subdivision cage: the face budget is smaller than the coarsest "
        "cage (" +
        std::to_string(topology.cage().num_faces()) + " faces)");
  }
  CageDeviationOptions measure;
  measure.length_unit = options.length_unit;
  // The spline through its fast evaluator, for the fits and measurements.
  const PiecewiseSurface pieces(spline);
  const PiecewiseSplineSampler sampler(spline, pieces);
  SDCB_ASSIGN_OR_RETURN(const SplineImage image, SplineImage::Create(sampler));

  const double setup = start.Seconds();
  SDCB_ASSIGN_OR_RETURN(std::optional<CageFit> creased,
                        CreasedCage(spline, sampler, image, options, measure));
  if (creased && creased->deviation.rms_percent <= options.tolerance_percent) {
    creased->stage_seconds.setup = setup;
    creased->stage_seconds.final_measure = start.Seconds() - setup;
    creased->seconds = creased->rounds[0].seconds = start.Seconds();
    return std::move(*creased);
  }
  CageFit fit;
  fit.stage_seconds.setup = setup;
  double progress = 0.0;  // never going back
  for (int round = 0;; ++round) {
    const SphereCage& layout = topology.cage();
    Stopwatch t0;
    SDCB_ASSIGN_OR_RETURN(
        const LimitSurface limit,
        LimitSurface::Create(options.scheme, layout.num_vertices(),
                             layout.faces));
    SDCB_ASSIGN_OR_RETURN(Eigen::MatrixX3d positions,
                          FitCagePositions(sampler, layout, limit, options));
    fit.stage_seconds.fit += t0.Seconds();
    t0.Restart();
    measure.min_samples = std::min(
        options.measure_samples,
        std::max(10000, options.round_samples_per_face * layout.num_faces()));
    SDCB_ASSIGN_OR_RETURN(CageDeviation deviation,
                          MeasureCageDeviation(sampler, limit, positions,
                                               layout, measure, &image));
    fit.stage_seconds.measure += t0.Seconds();
    CageRound r;
    r.round = round;
    r.faces = layout.num_faces();
    r.vertices = layout.num_vertices();
    r.limit_rmse_percent = deviation.rms_percent;
    r.limit_max_error_percent = deviation.max_percent;
    r.seconds = start.Seconds();
    fit.rounds.push_back(r);
    if (options.progress) {
      // Toward the tolerance or the face budget, whichever is nearer.
      const double toward_tolerance =
          std::min(1.0, options.tolerance_percent / r.limit_rmse_percent);
      const double toward_budget =
          static_cast<double>(r.faces) / options.max_faces;
      progress = std::max(
          progress,
          0.9 * std::max(toward_tolerance * toward_tolerance, toward_budget));
      options.progress("round " + std::to_string(round) + ", " +
                           std::to_string(r.faces) + " faces",
                       progress);
    }
    fit.cage.scheme = options.scheme;
    fit.cage.vertices = std::move(positions);
    fit.cage.layout = layout;
    fit.deviation = std::move(deviation);
    if (fit.deviation.rms_percent <= options.tolerance_percent) {
      fit.stop_reason = "tolerance reached";
      break;
    }
    if (round + 1 >= options.max_rounds) {
      fit.stop_reason = "round limit reached";
      break;
    }

    // Dorfler marking over the leaves: the fewest leaves holding
    // refine_share of the squared error.
    std::vector<double> mass(1, 0.0);
    for (int f = 0; f < layout.num_faces(); ++f) {
      const int cell = layout.face_cell[f];
      if (cell >= static_cast<int>(mass.size())) mass.resize(cell + 1, 0.0);
      mass[cell] += fit.deviation.face_squared_error[f];
    }
    std::vector<int> cells;
    for (int c = 0; c < static_cast<int>(mass.size()); ++c) {
      if (mass[c] > 0) cells.push_back(c);
    }
    std::stable_sort(cells.begin(), cells.end(),
                     [&](int a, int b) { return mass[a] > mass[b]; });
    const double total = std::accumulate(mass.begin(), mass.end(), 0.0);
    size_t marked = 0;
    for (double sum = 0;
         marked < cells.size() && sum < options.refine_share * total;
         ++marked) {
      sum += mass[cells[marked]];
    }
    // Within the growth limit (at least one leaf) and the face budget:
    // fewer leaves until the refined cage fits.
    const int growth =
        static_cast<int>(options.max_growth * layout.num_faces());
    bool refined = false;
    while (marked > 0) {
      SphereCageTopology next = topology;
      next.Refine(std::vector<int>(cells.begin(), cells.begin() + marked));
      const int faces = next.cage().num_faces();
      if (faces <= options.max_faces && (faces <= growth || marked == 1)) {
        topology = std::move(next);
        refined = true;
        break;
      }
      marked /= 2;
    }
    if (!refined) {
      fit.stop_reason = "face budget reached";
      break;
    }
  }
  // The returned cage measured at full density.
  if (options.progress) options.progress("measuring", 0.9);
  const Stopwatch final_start;
  SDCB_ASSIGN_OR_RETURN(
      const LimitSurface limit,
      LimitSurface::Create(options.scheme, fit.cage.layout.num_vertices(),
                           fit.cage.layout.faces));
  measure.min_samples = options.measure_samples;
  SDCB_ASSIGN_OR_RETURN(fit.deviation,
                        MeasureCageDeviation(sampler, limit, fit.cage.vertices,
                                             fit.cage.layout, measure, &image));
  fit.stage_seconds.final_measure = final_start.Seconds();
  fit.seconds = start.Seconds();
  return fit;
}

std::vector<std::array<int, 4>> OutwardCageFaces(
    const SubdivisionCage& cage, const Eigen::MatrixX3d& positions) {
  std::vector<std::array<int, 4>> faces = cage.layout.faces;
  const int size = cage.layout.face_size;
  std::vector<Eigen::Vector3i> fan;
  for (const auto& f : faces) {
    for (int k = 1; k + 1 < size; ++k) fan.emplace_back(f[0], f[k], f[k + 1]);
  }
  Eigen::MatrixX3i triangles(static_cast<Eigen::Index>(fan.size()), 3);
  for (size_t t = 0; t < fan.size(); ++t) {
    triangles.row(static_cast<Eigen::Index>(t)) = fan[t].transpose();
  }
  if (SignedVolume(positions, triangles) < 0) {
    for (auto& f : faces) std::reverse(f.begin(), f.begin() + size);
  }
  return faces;
}

std::string CageObjText(const SubdivisionCage& cage,
                        const Eigen::MatrixX3d& positions) {
  const SphereCage& layout = cage.layout;
  std::string text = "# sdcb cage: ";
  text += cage.scheme == SubdivisionScheme::kLoop
              ? "Loop subdivision (triangles)"
              : "Catmull-Clark subdivision (quads)";
  text += ", " + std::to_string(positions.rows()) + " vertices, " +
          std::to_string(layout.num_faces()) + " faces\n";
  char buffer[128];
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    std::snprintf(buffer, sizeof buffer, "v %.17g %.17g %.17g\n",
                  positions(i, 0), positions(i, 1), positions(i, 2));
    text += buffer;
  }
  for (const auto& f : OutwardCageFaces(cage, positions)) {
    text += "f";
    for (int k = 0; k < layout.face_size; ++k) {
      text += ' ' + std::to_string(f[k] + 1);
    }
    text += '\n';
  }
  for (const auto& [a, b] : cage.creases) {
    text += "t crease 2/1/0 " + std::to_string(a) + ' ' + std::to_string(b) +
            " 10\n";
  }
  return text;
}

Status CheckCageParts(const Model& model) {
  if (model.parts.empty())
    return InvalidArgumentError("the model has no parts");
  for (size_t i = 0; i < model.parts.size(); ++i) {
    if (model.parts[i].kept) {
      return InvalidInputError("part " + std::to_string(i + 1) +
                               " was kept as a mesh, not fitted; a cage is "
                               "made of fitted parts only");
    }
    const size_t loops = model.parts[i].trims.size();
    if (loops == 0) continue;
    return InvalidInputError("part " + std::to_string(i + 1) + " is open (" +
                             std::to_string(loops) +
                             (loops == 1 ? " trim loop" : " trim loops") +
                             "); cages of open parts are not supported yet");
  }
  return Status::Ok();
}

StatusOr<std::vector<PartCage>> FitModelCages(const Model& model,
                                              const CageOptions& options) {
  SDCB_RETURN_IF_ERROR(CheckCageParts(model));
  std::vector<PartCage> out;
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const ModelPart& part = model.parts[i];
    const std::string label = "part " + std::to_string(i + 1);
    StatusOr<SphericalSpline> spline = SurfaceFromModel(part.spline);
    StatusOr<CageFit> fit = spline.ok() ? FitSubdivisionCage(*spline, options)
                                        : StatusOr<CageFit>(spline.status());
    if (!fit.ok()) {
      return model.parts.size() == 1 ? fit.status()
                                     : fit.status().WithPrefix(label);
    }
    PartCage cage;
    cage.name = part.name.empty() ? "part" + std::to_string(i + 1) : part.name;
    cage.positions = part.spline.transform.ToInput(fit->cage.vertices);
    cage.fit = std::move(fit).value();
    out.push_back(std::move(cage));
  }
  return out;
}

std::string CageObjText(const std::vector<PartCage>& parts) {
  if (parts.size() == 1) {
    return CageObjText(parts[0].fit.cage, parts[0].positions);
  }
  std::string text;
  Eigen::Index offset = 0;
  for (const PartCage& part : parts) {
    const SubdivisionCage& cage = part.fit.cage;
    std::istringstream lines(CageObjText(cage, part.positions));
    std::string line;
    bool first = true;
    while (std::getline(lines, line)) {
      if (line.rfind("f ", 0) == 0) {
        std::istringstream corners(line.substr(2));
        line = "f";
        for (Eigen::Index c; corners >> c;) {
          line += ' ' + std::to_string(c + offset);
        }
      } else if (line.rfind("t crease 2/1/0 ", 0) == 0) {
        std::istringstream tag(line.substr(15));
        Eigen::Index a, b;
        std::string sharpness;
        tag >> a >> b >> sharpness;
        line = "t crease 2/1/0 " + std::to_string(a + offset) + ' ' +
               std::to_string(b + offset) + ' ' + sharpness;
      }
      text += line + '\n';
      if (first) text += "o " + part.name + '\n';
      first = false;
    }
    offset += part.positions.rows();
  }
  return text;
}

}  // namespace sdcb
