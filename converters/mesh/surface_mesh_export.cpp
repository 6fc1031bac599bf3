#include "sdcb/converters/mesh/surface_mesh_export.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sdcb/converters/gltf/gltf_asset.h"
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

namespace {

// One part of a model as the export sees it.
struct PartView {
  const SplineModel* spline;
  const std::vector<TrimLoop>* trims;
  const KeptMesh* kept;  // null for a fitted part
  // How messages name the part: "" for a model of one part, else "part N"
  // (counted from 1); and its name in the file (ExportPartName).
  std::string label;
  std::string name;
};

// A part tessellated, measured and mapped to input coordinates: everything
// but the file's bytes.
struct PartExport {
  SurfaceMesh mesh;
  Tessellation tessellation;  // its figures (the mesh holds its geometry)
  TessellationDeviation measured;
  CurvatureIntegrals curvature_integrals;
  double optimum = 0.0;  // 0 for a trimmed or kept part (see below)
  bool kept = false;     // a kept part: `mesh` is its input, nothing measured
  double quantization_budget = 0.0, surface_tolerance = 0.0;
  double scale = 1.0;  // the part's normalized frame -> input
  int feature_arcs = 0;
  SurfaceMeshExportReport::Colors colors;
  double seconds_tessellate = 0.0, seconds_measure = 0.0, seconds_optimum = 0.0,
         seconds_mesh = 0.0;
};

// A kept part as it was: its vertices and faces, area-weighted vertex
// normals (VertexNormals; +z where those cancel), mid grey where the other
// parts are coloured; its quantization budget that of a fitted part of its
// size.
PartExport ExportKeptPart(const KeptMesh& kept,
                          const SurfaceMeshExportOptions& options) {
  PartExport out;
  out.kept = true;
  SurfaceMesh& mesh = out.mesh;
  mesh.positions = kept.mesh.vertices;
  mesh.faces = kept.mesh.faces;
  mesh.normals = VertexNormals(kept.mesh);
  for (Eigen::Index v = 0; v < mesh.normals.rows(); ++v) {
    if (mesh.normals.row(v).squaredNorm() == 0) {
      mesh.normals.row(v) = Eigen::RowVector3d::UnitZ();
    }
  }
  if (options.colors != VertexColoring::kNone) {
    mesh.colors.setConstant(mesh.positions.rows(), 3, 128);
  }
  const Eigen::RowVector3d side =
      mesh.positions.colwise().maxCoeff() - mesh.positions.colwise().minCoeff();
  out.scale = std::max(side.maxCoeff(), std::numeric_limits<double>::min());
  if (options.compression != GltfCompression::kNone &&
      options.position_bits == 0) {
    out.quantization_budget =
        kQuantizationShare * options.tolerance_percent / 100.0;
  }
  return out;
}

// `progress` gets this part's own fraction in [0, 1].
StatusOr<PartExport> ExportPart(const PartView& part,
                                const SurfaceMeshExportOptions& options,
                                const ProgressCallback& progress) {
  const SplineModel& model = *part.spline;
  const bool trimmed = !part.trims->empty();
  const std::string prefix = part.label.empty() ? "" : part.label + ": ";
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
    return InvalidInputError(prefix + message);
  }
  if (trimmed && options.uniform_vertices > 0) {
    return InvalidInputError(
        prefix + "the part is open (" + std::to_string(part.trims->size()) +
        " trim loops) and a uniform mesh does not follow trims yet: export "
        "it adaptively (without --uniform)");
  }
  SDCB_ASSIGN_OR_RETURN(const SphericalSpline spline, SurfaceFromModel(model));
  // Positions and normals from the per-piece polynomials (fast; equal to
  // the spline's to rounding), curvature from the spline.
  const PiecewiseSurface pieces(spline);
  const PiecewiseSplineSampler sampler(spline, pieces);
  const NormalizingTransform& transform = model.transform;
  const bool quantized = options.compression != GltfCompression::kNone;
  const bool meshopt = options.compression == GltfCompression::kMeshopt;

  PartExport out;
  out.scale = transform.scale;
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
      return InvalidArgumentError(prefix + message);
    }
    quantization_budget = std::max(quantization_budget, floor);
  }
  const double surface_tolerance = tolerance - quantization_budget;
  out.quantization_budget = quantization_budget;
  out.surface_tolerance = surface_tolerance;

  progress("tessellate", 0.0);
  Stopwatch t0;
  Tessellation& t = out.tessellation;
  std::optional<SphereTriangulation> feature_pattern;
  if (options.uniform_vertices > 0) {
    t = TessellateUniformly(sampler,
                            UniformLevelForVertices(options.uniform_vertices));
  } else {
    TessellationOptions tessellation = options.tessellation;
    tessellation.tolerance = surface_tolerance;
    // Creases along the knots' feature arcs: a pattern whose edges follow
    // them (arcs that do not cut the sphere into simple faces are left to
    // the plain pattern, which crosses them). A trimmed part starts from
    // its trims' pattern instead, which does not follow creases yet.
    const KnotFeatureArcs arcs = FeatureArcsOfKnots(model.knots);
    if (!arcs.arcs.empty() && !trimmed) {
      StatusOr<SphereTriangulation> pattern =
          FeatureAlignedPattern(arcs.corner_directions, arcs.arcs);
      if (pattern.ok()) {
        feature_pattern = std::move(pattern).value();
        out.feature_arcs = static_cast<int>(arcs.arcs.size());
      }
    }
    if (feature_pattern) tessellation.initial_pattern = &*feature_pattern;
    if (trimmed) tessellation.trims = *part.trims;
    tessellation.angle_degrees = options.angle_degrees;
    tessellation.progress = [&](const std::string& stage, double fraction) {
      progress(stage, 0.8 * fraction);
    };
    StatusOr<Tessellation> made = TessellateAdaptively(sampler, tessellation);
    if (!made.ok()) {
      return part.label.empty() ? made.status()
                                : made.status().WithPrefix(part.label);
    }
    t = std::move(made).value();
  }
  out.seconds_tessellate = t0.Seconds();

  progress("measure", 0.8);
  t0.Restart();
  out.measured = MeasureTessellationDeviation(sampler, t,
                                              options.measure_samples_per_face);
  out.seconds_measure = t0.Seconds();
  progress("optimum", 0.9);
  t0.Restart();
  SDCB_ASSIGN_OR_RETURN(out.curvature_integrals,
                        IntegrateCurvatureOverSurface(sampler));
  // The optimum integrates over the whole sphere: for a trimmed part it
  // would count the region the trims remove, so it is not given.
  out.optimum = trimmed ? 0.0
                        : OptimalTriangleCount(out.curvature_integrals,
                                               surface_tolerance);
  out.seconds_optimum = t0.Seconds();

  progress("encode", 0.95);
  t0.Restart();
  SurfaceMesh& mesh = out.mesh;
  mesh.positions = transform.ToInput(t.positions);
  mesh.normals = CompleteNormals(t);
  mesh.faces = t.faces;
  mesh.directions = t.directions;
  // A model fitted to a mesh stored inward turns its faces as that mesh
  // did (its sphere is mirrored); the file's faces turn outward. An open
  // mesh has no volume: a trimmed part asks its whole (closed) surface,
  // from a coarse uniform mesh.
  double volume = 0.0;
  if (trimmed) {
    const Tessellation whole = TessellateUniformly(sampler, 3);
    volume = SignedVolume(transform.ToInput(whole.positions), whole.faces);
  } else {
    volume = SignedVolume(mesh.positions, mesh.faces);
  }
  if (volume < 0) {
    mesh.faces.col(1).swap(mesh.faces.col(2));
    mesh.normals = -mesh.normals;
  }
  SDCB_RETURN_IF_ERROR(
      ColorVertices(options, sampler, t, transform, &mesh, &out.colors));
  if (out.feature_arcs > 0 && !IsGltf(options.format)) {
    WeldCreaseCopies(t.directions, &mesh);
  }
  out.seconds_mesh = t0.Seconds();
  // The geometry now lives in `mesh`; keep the tessellation's figures only.
  t.directions.resize(0, 3);
  t.positions.resize(0, 3);
  t.normals.resize(0, 3);
  return out;
}

// The OBJ of several parts: `obj` (all parts' vertices, then all faces, as
// EncodeSurfaceMesh writes them) with "o NAME" before each part's first
// face.
std::string NameObjParts(const std::string& obj,
                         const std::vector<Eigen::Index>& first_faces,
                         const std::vector<std::string>& names) {
  std::string out;
  out.reserve(obj.size() + 32 * names.size());
  Eigen::Index face = 0;
  size_t next = 0;
  size_t at = 0;
  while (at < obj.size()) {
    size_t end = obj.find('\n', at);
    end = end == std::string::npos ? obj.size() : end + 1;
    if (obj.compare(at, 2, "f ") == 0) {
      while (next < names.size() && first_faces[next] == face) {
        out += "o " + names[next++] + "\n";
      }
      ++face;
    }
    out.append(obj, at, end - at);
    at = end;
  }
  return out;
}

// `asset`: Model::asset, "" for none.
StatusOr<SurfaceMeshExport> ExportParts(const std::vector<PartView>& parts,
                                        const SurfaceMeshExportOptions& options,
                                        std::string_view asset) {
  const Stopwatch start;
  SDCB_RETURN_IF_ERROR(CheckOptions(options));
  if (parts.empty()) return InvalidArgumentError("the model has no parts");
  const auto progress = [&](const std::string& stage, double fraction) {
    if (options.progress) options.progress(stage, fraction);
  };
  const bool quantized = options.compression != GltfCompression::kNone;
  const bool meshopt = options.compression == GltfCompression::kMeshopt;
  const double n = static_cast<double>(parts.size());

  SurfaceMeshExport out;
  SurfaceMeshExportReport& report = out.report;
  std::vector<PartExport> done;
  done.reserve(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].kept) {
      done.push_back(ExportKeptPart(*parts[i].kept, options));
      continue;
    }
    SDCB_ASSIGN_OR_RETURN(
        PartExport part,
        ExportPart(parts[i], options,
                   [&](const std::string& stage, double fraction) {
                     progress(stage, (i + fraction) / n);
                   }));
    done.push_back(std::move(part));
  }

  const Stopwatch t0;
  // Every part's mesh, one after the other: what PLY and STL hold.
  SurfaceMesh& mesh = out.mesh;
  if (done.size() == 1) {
    mesh = std::move(done[0].mesh);
  } else {
    Eigen::Index nv = 0, nf = 0;
    for (const PartExport& p : done) {
      nv += p.mesh.positions.rows();
      nf += p.mesh.faces.rows();
    }
    const bool colors = done[0].mesh.colors.rows() > 0;
    mesh.positions.resize(nv, 3);
    mesh.normals.resize(nv, 3);
    mesh.faces.resize(nf, 3);
    if (colors) mesh.colors.resize(nv, 3);
    nv = nf = 0;
    for (const PartExport& p : done) {
      out.part_vertices.push_back(nv);
      out.part_faces.push_back(nf);
      const Eigen::Index v = p.mesh.positions.rows(), f = p.mesh.faces.rows();
      mesh.positions.middleRows(nv, v) = p.mesh.positions;
      mesh.normals.middleRows(nv, v) = p.mesh.normals;
      if (colors) mesh.colors.middleRows(nv, v) = p.mesh.colors;
      mesh.faces.middleRows(nf, f) =
          p.mesh.faces.array() + static_cast<int>(nv);
      nv += v;
      nf += f;
    }
  }
  if (out.part_vertices.empty()) out.part_vertices = {0};
  if (out.part_faces.empty()) out.part_faces = {0};
  std::vector<std::string> names;
  for (const PartView& p : parts) names.push_back(p.name);

  GltfExportResult gltf;
  int bits = 0;
  if (IsGltf(options.format)) {
    std::vector<GltfExportOptions> per_part;
    for (const PartExport& p : done) {
      GltfExportOptions gltf_options;
      gltf_options.compression = options.compression;
      int part_bits = options.position_bits;
      const SurfaceMesh& part_mesh = done.size() == 1 ? mesh : p.mesh;
      if (quantized && part_bits == 0) {
        part_bits =
            PositionBitsFor(part_mesh.positions,
                            p.quantization_budget * p.scale, meshopt ? 16 : 30);
      }
      bits = std::max(bits, part_bits);
      gltf_options.position_bits = std::max(part_bits, 1);
      gltf_options.draco_level = options.draco_level;
      per_part.push_back(gltf_options);
    }
    const bool glb = options.format == ExportFormat::kGlb;
    EncodedGltf encoded;
    if (!asset.empty()) {
      std::vector<SurfaceMesh> meshes;
      if (done.size() == 1) {
        meshes.push_back(mesh);
      } else {
        for (PartExport& p : done) meshes.push_back(std::move(p.mesh));
      }
      SDCB_ASSIGN_OR_RETURN(EncodedGltfAsset asset,
                            EncodeGltfAsset(asset, meshes, per_part, glb));
      encoded = std::move(asset.gltf);
      report.textureless_materials = asset.textureless_materials;
      report.atlas_primitives = asset.atlas_primitives;
      report.atlas_vertices_beyond_extent = asset.atlas_vertices_beyond_extent;
    } else if (done.size() == 1) {
      SDCB_ASSIGN_OR_RETURN(encoded, EncodeGltf(mesh, per_part[0], glb));
    } else {
      std::vector<SurfaceMesh> meshes;
      for (PartExport& p : done) meshes.push_back(std::move(p.mesh));
      SDCB_ASSIGN_OR_RETURN(encoded,
                            EncodeGltfParts(meshes, names, per_part, glb));
    }
    out.bytes = std::move(encoded.bytes);
    gltf = encoded.result;
  } else {
    // A kept part passes through with the input's doubles, which OpenMesh's
    // OBJ writer would round to floats.
    bool kept = false;
    for (const PartExport& p : done) kept = kept || p.kept;
    if (options.format == ExportFormat::kObj && kept) {
      out.bytes = EncodeObjWithDoubles(mesh);
    } else {
      SDCB_ASSIGN_OR_RETURN(
          out.bytes, EncodeSurfaceMesh(
                         mesh, std::string(".") + FormatName(options.format)));
    }
    if (options.format == ExportFormat::kObj && done.size() > 1) {
      out.bytes = NameObjParts(out.bytes, out.part_faces, names);
    }
  }
  report.seconds.write = t0.Seconds();

  // The figures over the parts: counts add up, distances (percent of each
  // part's own largest side) and quantization take the largest.
  double measured_max = 0.0, surface_to_mesh = 0.0, mesh_to_surface = 0.0;
  double certified = 0.0, quantization_percent = 0.0, optimum = 0.0;
  double surface_tolerance = 1e300;
  bool all_closed = true;
  for (size_t i = 0; i < done.size(); ++i) {
    const PartExport& p = done[i];
    if (p.kept) {  // counted, not measured
      report.triangles += p.mesh.faces.rows();
      report.seconds.write += p.seconds_mesh;
      all_closed = false;
      continue;
    }
    const Tessellation& t = p.tessellation;
    report.triangles += t.faces.rows();
    report.max_normal_angle_degrees =
        std::max(report.max_normal_angle_degrees, t.max_normal_angle_degrees);
    report.uncertified_triangles += t.uncertified_faces;
    report.feature_arcs += p.feature_arcs;
    report.evaluations += t.evaluations;
    report.samples += t.samples;
    report.seconds.tessellate += p.seconds_tessellate;
    report.seconds.samples += t.seconds.samples;
    report.seconds.simplify += t.seconds.simplify;
    report.seconds.verify += t.seconds.verify;
    report.seconds.measure += p.seconds_measure;
    report.seconds.optimum += p.seconds_optimum;
    report.seconds.write += p.seconds_mesh;
    report.curvature_integrals.convex += p.curvature_integrals.convex;
    report.curvature_integrals.saddle += p.curvature_integrals.saddle;
    report.curvature_integrals.area += p.curvature_integrals.area;
    certified = std::max(certified, t.certified_distance);
    surface_to_mesh = std::max(surface_to_mesh, p.measured.surface_to_mesh);
    mesh_to_surface = std::max(mesh_to_surface, p.measured.mesh_to_surface);
    surface_tolerance = std::min(surface_tolerance, p.surface_tolerance);
    optimum += p.optimum;
    all_closed = all_closed && !parts[i].trims->size();
    report.trim_loops += static_cast<int>(parts[i].trims->size());
  }
  measured_max = std::max(surface_to_mesh, mesh_to_surface);
  // One part: its scale; several: the encoder's largest error against the
  // smallest part's scale (a bound for every part).
  double scale = done[0].scale;
  for (const PartExport& p : done) scale = std::min(scale, p.scale);
  quantization_percent = 100.0 * gltf.quantization_error / scale;
  report.parts = static_cast<int>(done.size());
  report.format = FormatName(options.format);
  report.compression = options.compression == GltfCompression::kDraco ? "draco"
                       : meshopt ? "meshopt"
                                 : "none";
  report.mode = options.uniform_vertices > 0 ? "uniform" : "adaptive";
  report.vertices = mesh.positions.rows();
  report.bytes = static_cast<int64_t>(out.bytes.size());
  report.tolerance_percent = options.tolerance_percent;
  report.surface_tolerance_percent =
      surface_tolerance < 1e300 ? 100.0 * surface_tolerance : 0.0;
  report.angle_degrees = options.angle_degrees;
  report.certified_distance_percent = 100.0 * certified;
  report.max_distance_percent = 100.0 * measured_max;
  report.spline_to_mesh_percent = 100.0 * surface_to_mesh;
  report.mesh_to_spline_percent = 100.0 * mesh_to_surface;
  report.total_error_bound_percent =
      100.0 * measured_max + quantization_percent;
  report.optimal_triangles = all_closed ? optimum : 0.0;
  report.triangles_vs_optimum =
      all_closed && optimum > 0
          ? static_cast<double>(report.triangles) / optimum
          : 0.0;
  for (const PartExport& p : done) {  // the first fitted part's ramp
    if (p.kept) continue;
    report.colors = p.colors;
    break;
  }
  report.quantization.bits = quantized ? bits : 0;
  // meshopt's exponential positions (a glTF asset): their mantissa bits.
  if (gltf.exponential_bits > 0) {
    report.quantization.bits = gltf.exponential_bits;
  }
  report.quantization.step = gltf.quantization_step;
  report.quantization.error_percent = quantization_percent;
  report.quantization.float32_error_percent =
      100.0 * gltf.float32_error / scale;
  report.seconds.total = start.Seconds();
  progress("done", 1.0);
  return out;
}

std::vector<PartView> PartsOf(const Model& model) {
  std::vector<PartView> parts;
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const ModelPart& part = model.parts[i];
    parts.push_back({&part.spline, &part.trims,
                     part.kept ? &*part.kept : nullptr,
                     model.parts.size() == 1 ? std::string()
                                             : "part " + std::to_string(i + 1),
                     ExportPartName(model, i)});
  }
  return parts;
}

}  // namespace

std::string ExportPartName(const Model& model, size_t part) {
  const std::string& name = model.parts[part].name;
  return name.empty() ? "part" + std::to_string(part + 1) : name;
}

StatusOr<SurfaceMeshExport> ExportSurfaceMesh(
    const Model& model, const SurfaceMeshExportOptions& options) {
  return ExportParts(PartsOf(model), options, model.asset);
}

StatusOr<SurfaceMeshExport> ExportSurfaceMesh(
    const SplineModel& model, const SurfaceMeshExportOptions& options) {
  static const std::vector<TrimLoop> kNoTrims;
  return ExportParts({{&model, &kNoTrims, nullptr, "", "part1"}}, options, "");
}

StatusOr<SurfaceMeshExportReport> WriteSurfaceMeshExport(
    const Model& model, const SurfaceMeshExportOptions& options,
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

StatusOr<SurfaceMeshExportReport> WriteSurfaceMeshExport(
    const SplineModel& model, const SurfaceMeshExportOptions& options,
    const std::string& path) {
  return WriteSurfaceMeshExport(SinglePartModel(model), options, path);
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
  if (r.parts > 1 || r.trim_loops > 0) {
    j["parts"] = r.parts;
    j["trim_loops"] = r.trim_loops;
  }
  if (r.atlas_primitives > 0) {
    j["atlas_primitives"] = r.atlas_primitives;
    j["atlas_vertices_beyond_extent"] = r.atlas_vertices_beyond_extent;
  }
  if (r.textureless_materials > 0) {
    j["textureless_materials"] = r.textureless_materials;
  }
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
