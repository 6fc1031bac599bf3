#include "sdcb/converters/mesh/surface_mesh_export.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <vector>

#include "sdcb/converters/mesh/color_ramp.h"
#include "sdcb/converters/mesh/mesh_export.h"
#include "sdcb/converters/mesh/tessellation_deviation.h"
#include "sdcb/core/common/stopwatch.h"
#include "sdcb/core/knots/feature_knots.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/core/tessellate/feature_pattern.h"
#include "sdcb/io/common/atomic_file.h"

namespace sdcb {
namespace {

// Fraction of the tolerance given to position quantization when a
// compressed glTF is written; the tessellation gets the rest.
constexpr double kQuantizationShare = 0.1;

// Largest quantization error of 16-bit positions over the surface's
// bounding box (normalized frame): sqrt(3) / 2 steps of its largest side
// / (2^16 - 1). The box comes from 40,962 surface points, widened by 1 %
// (more than a sampled box can miss); a tessellation's vertices lie on the
// surface, so their box is no larger.
double SixteenBitQuantizationError(const SurfaceSampler& surface) {
  Eigen::MatrixX3d positions;
  surface.Sample(MakeIcosphere(6).vertices, &positions, nullptr);
  const double side =
      (positions.colwise().maxCoeff() - positions.colwise().minCoeff())
          .maxCoeff();
  return std::sqrt(3.0) / 2.0 * 1.01 * side / (std::pow(2.0, 16) - 1.0);
}

// Unit normals for every vertex: the analytic one, or where the surface is
// singular (zero normal) the area-weighted normal of the adjacent faces.
Eigen::MatrixX3d CompleteNormals(const Tessellation& t) {
  Eigen::MatrixX3d normals = t.normals;
  Eigen::MatrixX3d face_sum = Eigen::MatrixX3d::Zero(t.positions.rows(), 3);
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f) {
    const Eigen::Vector3d a = t.positions.row(t.faces(f, 0)),
                          b = t.positions.row(t.faces(f, 1)),
                          c = t.positions.row(t.faces(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) face_sum.row(t.faces(f, k)) += n.transpose();
  }
  for (Eigen::Index v = 0; v < normals.rows(); ++v) {
    if (std::abs(normals.row(v).norm() - 1.0) < 1e-9) continue;
    const double len = face_sum.row(v).norm();
    normals.row(v) = len > 0 ? Eigen::RowVector3d(face_sum.row(v) / len)
                             : Eigen::RowVector3d(0, 0, 1);
  }
  return normals;
}

double Percentile(const Eigen::VectorXd& values, double q) {
  std::vector<double> v;
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) v.push_back(std::abs(values[i]));
  }
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)))];
}

bool IsGltf(ExportFormat f) {
  return f == ExportFormat::kGltf || f == ExportFormat::kGlb;
}

// The tessellation splits a vertex on a crease once per side (hard edges
// for glTF renderers). Mesh files are closed meshes to be read back (sdcb
// check, a refit): the copies (equal `directions` rows) become one vertex
// again, whose normal is the mean of the copies'.
void WeldCreaseCopies(const Eigen::MatrixX3d& directions, SurfaceMesh* mesh) {
  const Eigen::Index n = directions.rows();
  std::map<std::array<double, 3>, Eigen::Index> first;
  std::vector<Eigen::Index> to(n);
  Eigen::Index kept = 0;
  std::vector<Eigen::Index> kept_row;
  for (Eigen::Index v = 0; v < n; ++v) {
    const std::array<double, 3> key = {directions(v, 0), directions(v, 1),
                                       directions(v, 2)};
    const auto [it, inserted] = first.emplace(key, kept);
    if (inserted) {
      kept_row.push_back(v);
      ++kept;
    }
    to[v] = it->second;
  }
  if (kept == n) return;
  SurfaceMesh welded;
  welded.positions.resize(kept, 3);
  for (Eigen::Index k = 0; k < kept; ++k) {
    welded.positions.row(k) = mesh->positions.row(kept_row[k]);
  }
  if (mesh->normals.rows() == n) {
    welded.normals = Eigen::MatrixX3d::Zero(kept, 3);
    for (Eigen::Index v = 0; v < n; ++v) {
      welded.normals.row(to[v]) += mesh->normals.row(v);
    }
    welded.normals.rowwise().normalize();
  }
  if (mesh->colors.rows() == n) {
    welded.colors.resize(kept, 3);
    for (Eigen::Index k = 0; k < kept; ++k) {
      welded.colors.row(k) = mesh->colors.row(kept_row[k]);
    }
  }
  welded.faces = mesh->faces;
  for (Eigen::Index f = 0; f < welded.faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      welded.faces(f, c) = static_cast<int>(to[mesh->faces(f, c)]);
    }
  }
  *mesh = std::move(welded);
}

const char* FormatName(ExportFormat f) {
  switch (f) {
    case ExportFormat::kObj:
      return "obj";
    case ExportFormat::kPly:
      return "ply";
    case ExportFormat::kStl:
      return "stl";
    case ExportFormat::kGltf:
      return "gltf";
    default:
      return "glb";
  }
}

Status CheckOptions(const SurfaceMeshExportOptions& o) {
  if (!(o.tolerance_percent > 0.0) || !std::isfinite(o.tolerance_percent) ||
      !(o.angle_degrees > 0.0 && o.angle_degrees <= 180.0)) {
    return InvalidArgumentError(
        "the tolerance must be positive and the angle in (0, 180] degrees");
  }
  if (o.compression != GltfCompression::kNone && !IsGltf(o.format)) {
    return InvalidArgumentError("Draco and meshopt need a glTF output");
  }
  const int max_bits = o.compression == GltfCompression::kMeshopt ? 16 : 30;
  if (o.position_bits < 0 || o.position_bits > max_bits) {
    return InvalidArgumentError("position bits must be in 1.." +
                                std::to_string(max_bits) + " (0: derived)");
  }
  if (o.colors != VertexColoring::kNone && o.format != ExportFormat::kPly &&
      !IsGltf(o.format)) {
    return InvalidArgumentError("vertex colors need a PLY or glTF output");
  }
  if (o.colors == VertexColoring::kDistanceToMesh && o.mesh == nullptr) {
    return InvalidArgumentError(
        "distance colors need the mesh to compare with");
  }
  if (o.measure_samples_per_face < 0 || o.uniform_vertices < 0) {
    return InvalidArgumentError(
        "measure samples and uniform vertices must not be negative");
  }
  return Status::Ok();
}

// Fills mesh->colors and the report's colors for `options.colors`.
Status ColorVertices(const SurfaceMeshExportOptions& options,
                     const SurfaceSampler& sampler, const Tessellation& t,
                     const NormalizingTransform& transform, SurfaceMesh* mesh,
                     SurfaceMeshExportReport::Colors* report) {
  switch (options.colors) {
    case VertexColoring::kNone:
      report->mode = "none";
      return Status::Ok();
    case VertexColoring::kMeanCurvature:
    case VertexColoring::kGaussianCurvature: {
      const bool mean_curvature =
          options.colors == VertexColoring::kMeanCurvature;
      Eigen::VectorXd gaussian, mean;
      sampler.SampleCurvature(t.directions, &gaussian, &mean);
      // Input units: curvature 1/length scales by 1/scale, K by 1/scale^2.
      const double s = transform.scale;
      const Eigen::VectorXd values = mean_curvature
                                         ? Eigen::VectorXd(mean / s)
                                         : Eigen::VectorXd(gaussian / (s * s));
      const double range = Percentile(values, 0.95);
      mesh->colors = ColorRamp(values, -range, range, /*diverging=*/true);
      report->mode = mean_curvature ? "curvature" : "gaussian";
      report->quantity =
          mean_curvature ? "mean_curvature" : "gaussian_curvature";
      report->unit = mean_curvature ? "1/length" : "1/length^2";
      report->ramp = "blue (min) - white (0) - red (max)";
      report->min = -range;
      report->max = range;
      report->scale_rule = "symmetric, 95th percentile of |value|";
      return Status::Ok();
    }
    case VertexColoring::kDistanceToMesh: {
      StatusOr<MeshDistance> distance = MeshDistance::Create(*options.mesh);
      if (!distance.ok()) {
        return distance.status().WithPrefix(options.mesh_name);
      }
      const Eigen::VectorXd d = distance->Distances(mesh->positions);
      const double top = d.size() ? d.maxCoeff() : 0.0;
      mesh->colors = ColorRamp(d, 0.0, top, /*diverging=*/false);
      report->mode = "error";
      report->quantity = "distance_to_mesh";
      report->mesh = options.mesh_name;
      report->unit = "percent of the largest bounding-box side";
      report->ramp = "white (min) - red (max)";
      report->min = 0.0;
      report->max = 100.0 * top / transform.scale;
      return Status::Ok();
    }
  }
  return Status::Ok();
}

}  // namespace

bool ExportFormatOfExtension(const std::string& extension,
                             ExportFormat* format) {
  std::string ext = extension;
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (ExportFormat f :
       {ExportFormat::kObj, ExportFormat::kPly, ExportFormat::kStl,
        ExportFormat::kGltf, ExportFormat::kGlb}) {
    if (ext == std::string(".") + FormatName(f)) {
      *format = f;
      return true;
    }
  }
  return false;
}

StatusOr<SurfaceMeshExport> ExportSurfaceMesh(
    const SplineModel& model, const SurfaceMeshExportOptions& options) {
  const Stopwatch start;
  SDCB_RETURN_IF_ERROR(CheckOptions(options));
  // Across a fold the surface's normal turns over: no flat triangle holds a
  // tolerance there, and the tessellation would refine the fold without
  // end. The fit measured the folds; a uniform mesh has no tolerance to
  // hold.
  const double folded = model.statistics.final_result.folded_area_percent;
  if (options.uniform_vertices == 0 && folded > 0.0) {
    char message[320];
    std::snprintf(message, sizeof message,
                  "the surface folds over %.4g %% of its area (as its fit "
                  "measured), and no mesh holds a tolerance across a fold: "
                  "refit the mesh, or export a uniform mesh (--uniform N)",
                  folded);
    return InvalidInputError(message);
  }
  const auto progress = [&](const std::string& stage, double fraction) {
    if (options.progress) options.progress(stage, fraction);
  };
  SDCB_ASSIGN_OR_RETURN(const SphericalSpline spline, SurfaceFromModel(model));
  // Positions and normals from the per-piece polynomials (fast; equal to
  // the spline's to rounding), curvature from the spline.
  const PiecewiseSurface pieces(spline);
  const PiecewiseSplineSampler sampler(spline, pieces);
  const NormalizingTransform& transform = model.transform;
  const bool quantized = options.compression != GltfCompression::kNone;
  const bool meshopt = options.compression == GltfCompression::kMeshopt;

  SurfaceMeshExport out;
  SurfaceMeshExportReport& report = out.report;
  // Tolerances in the normalized frame (largest side 1): PCT / 100.
  const double tolerance = options.tolerance_percent / 100.0;
  double quantization_budget = quantized && options.position_bits == 0
                                   ? kQuantizationShare * tolerance
                                   : 0.0;
  if (meshopt && options.position_bits == 0) {
    const double floor = SixteenBitQuantizationError(sampler);
    if (floor > 0.5 * tolerance) {
      char message[240];
      std::snprintf(message, sizeof message,
                    "meshopt cannot keep the tolerance %g %%: its 16-bit "
                    "positions alone are off by up to %.3g %% (use Draco, or "
                    "16 position bits to accept that)",
                    options.tolerance_percent, 100.0 * floor);
      return InvalidArgumentError(message);
    }
    quantization_budget = std::max(quantization_budget, floor);
  }
  const double surface_tolerance = tolerance - quantization_budget;

  progress("tessellate", 0.0);
  Stopwatch t0;
  Tessellation t;
  std::optional<SphereTriangulation> feature_pattern;
  if (options.uniform_vertices > 0) {
    t = TessellateUniformly(sampler,
                            UniformLevelForVertices(options.uniform_vertices));
  } else {
    TessellationOptions tessellation = options.tessellation;
    tessellation.tolerance = surface_tolerance;
    // Creases along the knots' feature arcs: a pattern whose edges follow
    // them (arcs that do not cut the sphere into simple faces are left to
    // the plain pattern, which crosses them).
    const KnotFeatureArcs arcs = FeatureArcsOfKnots(model.knots);
    if (!arcs.arcs.empty()) {
      StatusOr<SphereTriangulation> pattern =
          FeatureAlignedPattern(arcs.corner_directions, arcs.arcs);
      if (pattern.ok()) {
        feature_pattern = std::move(pattern).value();
        report.feature_arcs = static_cast<int>(arcs.arcs.size());
      }
    }
    if (feature_pattern) tessellation.initial_pattern = &*feature_pattern;
    tessellation.angle_degrees = options.angle_degrees;
    tessellation.progress = [&](const std::string& stage, double fraction) {
      progress(stage, 0.8 * fraction);
    };
    SDCB_ASSIGN_OR_RETURN(t, TessellateAdaptively(sampler, tessellation));
  }
  report.seconds.tessellate = t0.Seconds();
  report.seconds.samples = t.seconds.samples;
  report.seconds.simplify = t.seconds.simplify;
  report.seconds.verify = t.seconds.verify;
  report.samples = t.samples;

  progress("measure", 0.8);
  t0.Restart();
  const TessellationDeviation measured = MeasureTessellationDeviation(
      sampler, t, options.measure_samples_per_face);
  report.seconds.measure = t0.Seconds();
  progress("optimum", 0.9);
  t0.Restart();
  SDCB_ASSIGN_OR_RETURN(report.curvature_integrals,
                        IntegrateCurvatureOverSurface(sampler));
  const double optimum =
      OptimalTriangleCount(report.curvature_integrals, surface_tolerance);
  report.seconds.optimum = t0.Seconds();

  progress("encode", 0.95);
  t0.Restart();
  SurfaceMesh& mesh = out.mesh;
  mesh.positions = transform.ToInput(t.positions);
  mesh.normals = CompleteNormals(t);
  mesh.faces = t.faces;
  // A model fitted to a mesh stored inward turns its faces as that mesh
  // did (its sphere is mirrored); the file's faces turn outward.
  if (SignedVolume(mesh.positions, mesh.faces) < 0) {
    mesh.faces.col(1).swap(mesh.faces.col(2));
    mesh.normals = -mesh.normals;
  }
  SDCB_RETURN_IF_ERROR(
      ColorVertices(options, sampler, t, transform, &mesh, &report.colors));
  if (report.feature_arcs > 0 && !IsGltf(options.format)) {
    WeldCreaseCopies(t.directions, &mesh);
  }
  GltfExportResult gltf;
  int bits = 0;
  if (IsGltf(options.format)) {
    GltfExportOptions gltf_options;
    gltf_options.compression = options.compression;
    bits = options.position_bits;
    if (quantized && bits == 0) {
      bits =
          PositionBitsFor(mesh.positions, quantization_budget * transform.scale,
                          meshopt ? 16 : 30);
    }
    gltf_options.position_bits = std::max(bits, 1);
    gltf_options.draco_level = options.draco_level;
    SDCB_ASSIGN_OR_RETURN(
        EncodedGltf encoded,
        EncodeGltf(mesh, gltf_options, options.format == ExportFormat::kGlb));
    out.bytes = std::move(encoded.bytes);
    gltf = encoded.result;
  } else {
    SDCB_ASSIGN_OR_RETURN(
        out.bytes,
        EncodeSurfaceMesh(mesh, std::string(".") + FormatName(options.format)));
  }
  report.seconds.write = t0.Seconds();

  const double measured_max =
      std::max(measured.surface_to_mesh, measured.mesh_to_surface);
  const double quantization_percent =
      100.0 * gltf.quantization_error / transform.scale;
  report.format = FormatName(options.format);
  report.compression = options.compression == GltfCompression::kDraco ? "draco"
                       : meshopt ? "meshopt"
                                 : "none";
  report.mode = options.uniform_vertices > 0 ? "uniform" : "adaptive";
  report.triangles = t.faces.rows();
  report.vertices = mesh.positions.rows();
  report.bytes = static_cast<int64_t>(out.bytes.size());
  report.tolerance_percent = options.tolerance_percent;
  report.surface_tolerance_percent = 100.0 * surface_tolerance;
  report.angle_degrees = options.angle_degrees;
  report.certified_distance_percent = 100.0 * t.certified_distance;
  report.max_normal_angle_degrees = t.max_normal_angle_degrees;
  report.uncertified_triangles = t.uncertified_faces;
  report.max_distance_percent = 100.0 * measured_max;
  report.spline_to_mesh_percent = 100.0 * measured.surface_to_mesh;
  report.mesh_to_spline_percent = 100.0 * measured.mesh_to_surface;
  report.total_error_bound_percent =
      100.0 * measured_max + quantization_percent;
  report.optimal_triangles = optimum;
  report.triangles_vs_optimum =
      optimum > 0 ? static_cast<double>(t.faces.rows()) / optimum : 0.0;
  report.quantization.bits = quantized ? bits : 0;
  report.quantization.step = gltf.quantization_step;
  report.quantization.error_percent = quantization_percent;
  report.quantization.float32_error_percent =
      100.0 * gltf.float32_error / transform.scale;
  report.evaluations = t.evaluations;
  report.seconds.total = start.Seconds();
  progress("done", 1.0);
  return out;
}

StatusOr<SurfaceMeshExportReport> WriteSurfaceMeshExport(
    const SplineModel& model, const SurfaceMeshExportOptions& options,
    const std::string& path) {
  const Stopwatch start;
  SurfaceMeshExportOptions o = options;
  const std::string extension =
      std::filesystem::path(path).extension().string();
  if (!ExportFormatOfExtension(extension, &o.format)) {
    return InvalidArgumentError(path + ": unknown mesh extension '" +
                                extension +
                                "' (use .obj, .ply, .stl, .gltf or .glb)");
  }
  SDCB_ASSIGN_OR_RETURN(SurfaceMeshExport exported,
                        ExportSurfaceMesh(model, o));
  const Stopwatch t0;
  SDCB_RETURN_IF_ERROR(WriteFileAtomically(exported.bytes, path));
  exported.report.seconds.write += t0.Seconds();
  exported.report.seconds.total = start.Seconds();
  return exported.report;
}

nlohmann::ordered_json SurfaceMeshExportReportToJson(
    const SurfaceMeshExportReport& r) {
  nlohmann::ordered_json j;
  j["format"] = r.format;
  j["compression"] = r.compression;
  j["mode"] = r.mode;
  j["triangles"] = r.triangles;
  j["vertices"] = r.vertices;
  j["bytes"] = r.bytes;
  j["tolerance_percent"] = r.tolerance_percent;
  j["surface_tolerance_percent"] = r.surface_tolerance_percent;
  j["angle_degrees"] = r.angle_degrees;
  j["certified_distance_percent"] = r.certified_distance_percent;
  j["max_normal_angle_degrees"] = r.max_normal_angle_degrees;
  j["uncertified_triangles"] = r.uncertified_triangles;
  j["feature_arcs"] = r.feature_arcs;
  j["max_distance_percent"] = r.max_distance_percent;
  j["spline_to_mesh_percent"] = r.spline_to_mesh_percent;
  j["mesh_to_spline_percent"] = r.mesh_to_spline_percent;
  j["total_error_bound_percent"] = r.total_error_bound_percent;
  j["optimal_triangles"] = r.optimal_triangles;
  j["triangles_vs_optimum"] = r.triangles_vs_optimum;
  j["curvature_integrals"] = {
      {"convex_sqrt_k", r.curvature_integrals.convex},
      {"saddle_sqrt_abs_k", r.curvature_integrals.saddle},
      {"area", r.curvature_integrals.area}};
  j["quantization"] = {
      {"bits", r.quantization.bits},
      {"step", r.quantization.step},
      {"error_percent", r.quantization.error_percent},
      {"float32_error_percent", r.quantization.float32_error_percent}};
  nlohmann::ordered_json colors;
  colors["mode"] = r.colors.mode;
  if (r.colors.mode != "none") {
    colors["quantity"] = r.colors.quantity;
    if (!r.colors.mesh.empty()) colors["mesh"] = r.colors.mesh;
    colors["unit"] = r.colors.unit;
    colors["ramp"] = r.colors.ramp;
    colors["min"] = r.colors.min;
    colors["max"] = r.colors.max;
    if (!r.colors.scale_rule.empty())
      colors["scale_rule"] = r.colors.scale_rule;
  }
  j["colors"] = colors;
  j["evaluations"] = r.evaluations;
  j["samples"] = r.samples;
  j["seconds"] = {
      {"tessellate", r.seconds.tessellate}, {"samples", r.seconds.samples},
      {"simplify", r.seconds.simplify},     {"verify", r.seconds.verify},
      {"measure", r.seconds.measure},       {"optimum", r.seconds.optimum},
      {"write", r.seconds.write},           {"total", r.seconds.total}};
  return j;
}

}  // namespace sdcb
