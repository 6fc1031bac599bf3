// sdcb compare MODEL.sdcb MESH [--json FILE] [--samples N] [--mesh-samples N]
//              [--picture OUT.ply] [--quiet]
// The two-sided distance between a model's surface and any mesh
// (core/measure/surface_deviation.h), in percent of the mesh's largest
// bounding-box side; --picture writes the measured surface colored by it,
// its folded samples blue.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sdcb/converters/mesh/color_ramp.h"
#include "sdcb/core/measure/boundary_deviation.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/mesh/mesh_parts.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/mesh/mesh_writer.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {

namespace {

constexpr int kDefaultMeshSamples = 100000;

// A trimmed part's boundary distance: the trims sampled every this many
// radians on the sphere, the mesh's boundary edges every this share of the
// length unit.
constexpr double kBoundaryTrimStep = 1e-3;
constexpr double kBoundaryMeshStep = 1e-4;

// The picture's color of a folded surface sample (the distance ramp runs from
// white to red).
constexpr std::uint8_t kFoldedColor[3] = {0, 64, 255};

// The measured surface (the lattice's image, one vertex per surface sample,
// in the input's coordinates), each vertex colored by its distance to the
// mesh from white (0) to red (the largest), folded samples blue.
Status WritePicture(const SurfaceDeviation& d,
                    const NormalizingTransform& transform,
                    const std::string& path) {
  TriangleMesh picture;
  picture.vertices = transform.ToInput(d.surface_sample_positions);
  picture.faces = d.surface_sample_triangles;
  MeshWriteOptions options;
  options.colors = ColorRamp(d.surface_sample_distance_percent, 0.0,
                             d.surface_to_mesh_max_percent,
                             /*diverging=*/false);
  for (size_t i = 0; i < d.surface_sample_folded.size(); ++i) {
    if (!d.surface_sample_folded[i]) continue;
    options.colors.row(i) << kFoldedColor[0], kFoldedColor[1], kFoldedColor[2];
  }
  return WriteMesh(picture, path, options);
}

// `part`'s surface against `mesh` in the part's normalized frame, in
// percent of the mesh's largest side, in the region the part's trims keep;
// for a trimmed part and a mesh with a boundary, also the distance between
// the trims' images and the mesh's boundary edges (boundary_percent).
StatusOr<SurfaceDeviation> MeasurePart(const ModelPart& part,
                                       const TriangleMesh& mesh,
                                       DeviationOptions options) {
  const SplineModel& model = part.spline;
  SDCB_ASSIGN_OR_RETURN(const SphericalSpline surface, SurfaceFromModel(model));
  SDCB_ASSIGN_OR_RETURN(const TrimRegion region,
                        TrimRegion::Create(part.trims));
  // Both in the model's normalized frame; 100 % = the mesh's largest side.
  TriangleMesh normalized = mesh;
  normalized.vertices = model.transform.ToNormalized(mesh.vertices);
  SDCB_ASSIGN_OR_RETURN(const NormalizingTransform own,
                        ComputeNormalizingTransform(mesh));
  options.length_unit = own.scale / model.transform.scale;
  options.region = &region;
  SDCB_ASSIGN_OR_RETURN(SurfaceDeviation d,
                        MeasureSurfaceDeviation(surface, normalized, options));
  if (!part.trimmed()) return d;
  SDCB_ASSIGN_OR_RETURN(const Eigen::MatrixX2i edges,
                        BoundaryEdges(normalized));
  if (edges.rows() == 0) return d;
  SDCB_ASSIGN_OR_RETURN(
      const BoundaryDeviation boundary,
      MeasureBoundaryDeviation(surface, part.trims, normalized.vertices, edges,
                               options.length_unit, kBoundaryTrimStep,
                               kBoundaryMeshStep * options.length_unit));
  d.boundary_percent = boundary.max_percent();
  return d;
}

// The figures of `d` (docs/CLI.md, `sdcb compare --json`).
void AddFigures(const SurfaceDeviation& d, nlohmann::ordered_json* out) {
  nlohmann::ordered_json& j = *out;
  j["rmse_percent"] = d.rms_percent;
  j["max_error_percent"] = d.hausdorff_percent;
  j["hausdorff_percent"] = d.hausdorff_percent;
  j["surface_to_mesh_rms_percent"] = d.surface_to_mesh_rms_percent;
  j["surface_to_mesh_max_percent"] = d.surface_to_mesh_max_percent;
  j["mesh_to_surface_rms_percent"] = d.mesh_to_surface_rms_percent;
  j["mesh_to_surface_max_percent"] = d.mesh_to_surface_max_percent;
  j["mesh_to_surface_max_bound_percent"] = d.mesh_to_surface_max_bound_percent;
  j["folded_area_percent"] = d.folded_area_percent;
  if (d.boundary_percent >= 0) j["boundary_percent"] = d.boundary_percent;
  j["surface_samples"] = d.surface_samples;
  j["mesh_samples"] = d.mesh_samples;
  j["mesh_bound_samples"] = d.mesh_bound_samples;
  j["mesh_sample_spacing_percent"] = d.mesh_sample_spacing_percent;
}

// The largest of each figure over the parts (each in percent of its own
// part's largest side), the sample counts summed: a model of several parts
// is as good as its worst part.
SurfaceDeviation Worst(const std::vector<SurfaceDeviation>& parts) {
  SurfaceDeviation w;
  for (const SurfaceDeviation& d : parts) {
    w.rms_percent = std::max(w.rms_percent, d.rms_percent);
    w.hausdorff_percent = std::max(w.hausdorff_percent, d.hausdorff_percent);
    w.surface_to_mesh_rms_percent =
        std::max(w.surface_to_mesh_rms_percent, d.surface_to_mesh_rms_percent);
    w.surface_to_mesh_max_percent =
        std::max(w.surface_to_mesh_max_percent, d.surface_to_mesh_max_percent);
    w.mesh_to_surface_rms_percent =
        std::max(w.mesh_to_surface_rms_percent, d.mesh_to_surface_rms_percent);
    w.mesh_to_surface_max_percent =
        std::max(w.mesh_to_surface_max_percent, d.mesh_to_surface_max_percent);
    w.mesh_to_surface_max_bound_percent =
        std::max(w.mesh_to_surface_max_bound_percent,
                 d.mesh_to_surface_max_bound_percent);
    w.folded_area_percent =
        std::max(w.folded_area_percent, d.folded_area_percent);
    w.boundary_percent = std::max(w.boundary_percent, d.boundary_percent);
    w.mesh_sample_spacing_percent =
        std::max(w.mesh_sample_spacing_percent, d.mesh_sample_spacing_percent);
    w.surface_samples += d.surface_samples;
    w.mesh_samples += d.mesh_samples;
    w.mesh_bound_samples += d.mesh_bound_samples;
    w.refined_vertices += d.refined_vertices;
    w.lattice_level = std::max(w.lattice_level, d.lattice_level);
  }
  return w;
}

}  // namespace

int RunCompare(const std::vector<std::string>& argv) {
  const Args args(argv, {"json", "samples", "mesh-samples", "picture"},
                  {"quiet"});
  args.RequirePositionals(
      2, "MODEL and MESH (usage: sdcb compare MODEL.sdcb MESH [--json FILE])");
  const std::string& model_path = args.positionals()[0];
  const std::string& mesh_path = args.positionals()[1];
  const std::string picture_path = args.Get("picture");
  if (args.Has("picture") && LowercaseExtension(picture_path) != ".ply") {
    throw UsageError{"--picture needs a .ply output (it has vertex colors)"};
  }
  DeviationOptions options;
  options.min_surface_samples =
      args.GetInt("samples", options.min_surface_samples, 1000, 100000000);
  // The mesh's side as densely as the surface's by default: at its vertices
  // alone, the inside of large triangles would go unmeasured.
  options.mesh_samples =
      args.GetInt("mesh-samples", kDefaultMeshSamples, 0, 100000000);

  const Status outputs = PrepareOutputs({args.Get("json"), picture_path});
  if (!outputs.ok()) return ReportError(outputs);
  StatusOr<Model> model = ReadSdcbModelFile(model_path);
  if (!model.ok()) return ReportError(model.status());
  StatusOr<TriangleMesh> mesh = ReadInputMesh(mesh_path);
  if (!mesh.ok()) return ReportError(mesh.status());
  // One untrimmed part: against the whole mesh, whatever it is. Otherwise
  // part i against the mesh's part i (core/mesh/mesh_parts.h).
  const bool whole = model->parts.size() == 1 && model->parts[0].fitted() &&
                     !model->parts[0].trimmed();
  size_t first_fitted = 0;  // kept parts are reported, not measured
  while (first_fitted < model->parts.size() &&
         model->parts[first_fitted].kept) {
    ++first_fitted;
  }
  if (first_fitted == model->parts.size()) {
    return ReportError(InvalidInputError(
        model_path +
        ": every part was kept as a mesh, not fitted; there is "
        "no surface to measure"));
  }
  std::vector<TriangleMesh> meshes;
  if (whole) {
    meshes.push_back(std::move(*mesh));
  } else {
    StatusOr<std::vector<MeshPart>> parts = SplitIntoParts(*mesh, 0);
    if (!parts.ok()) return ReportError(parts.status().WithPrefix(mesh_path));
    if (parts->size() != model->parts.size()) {
      return ReportError(InvalidInputError(
          mesh_path + " has " + std::to_string(parts->size()) + " part" +
          (parts->size() == 1 ? "" : "s") + ", " + model_path + " " +
          std::to_string(model->parts.size()) +
          "; compare measures each part against its own"));
    }
    for (MeshPart& part : *parts) meshes.push_back(std::move(part.mesh));
  }
  std::vector<SurfaceDeviation> measured;  // per part, empty when kept
  std::vector<SurfaceDeviation> fitted;
  for (size_t i = 0; i < meshes.size(); ++i) {
    if (model->parts[i].kept) {
      measured.emplace_back();
      continue;
    }
    StatusOr<SurfaceDeviation> d =
        MeasurePart(model->parts[i], meshes[i], options);
    if (!d.ok()) {
      const std::string which =
          whole ? "" : " (part " + std::to_string(i + 1) + ")";
      return ReportError(
          d.status().WithPrefix(model_path + " vs " + mesh_path + which));
    }
    fitted.push_back(*d);
    measured.push_back(std::move(d).value());
  }
  const SurfaceDeviation worst = whole ? SurfaceDeviation() : Worst(fitted);
  const SurfaceDeviation* d = whole ? &measured[0] : &worst;
  if (args.Has("picture")) {
    // The first fitted part's picture (docs/CLI.md).
    const Status s =
        WritePicture(measured[first_fitted],
                     model->parts[first_fitted].spline.transform, picture_path);
    if (!s.ok()) return ReportError(s);
  }
  if (args.Has("json")) {
    nlohmann::ordered_json j;
    j["model"] = model_path;
    j["mesh"] = mesh_path;
    AddFigures(*d, &j);
    if (!whole) {
      nlohmann::ordered_json parts = nlohmann::ordered_json::array();
      for (size_t i = 0; i < measured.size(); ++i) {
        nlohmann::ordered_json part;
        part["number"] = static_cast<int>(i) + 1;
        part["kept"] = model->parts[i].kept.has_value();
        if (model->parts[i].kept) {
          part["reason"] = model->parts[i].kept->reason;
          parts.push_back(std::move(part));
          continue;
        }
        part["trim_loops"] = model->parts[i].trims.size();
        AddFigures(measured[i], &part);
        parts.push_back(std::move(part));
      }
      j["parts"] = std::move(parts);
    }
    if (args.Has("picture")) j["picture"] = picture_path;
    const Status s = WriteTextOutput(args.Get("json"), j.dump(2) + "\n");
    if (!s.ok()) return ReportError(s);
  }
  if (!args.Has("quiet") && args.Get("json") != "-") {
    std::printf("%s vs %s (percent of the mesh's largest side)\n",
                model_path.c_str(), mesh_path.c_str());
    std::printf("  surface -> mesh   rms %.5f%%  max %.5f%%  (%lld samples)\n",
                d->surface_to_mesh_rms_percent, d->surface_to_mesh_max_percent,
                static_cast<long long>(d->surface_samples));
    std::printf(
        "  mesh -> surface   rms %.5f%%  max %.5f%%  (%lld samples; at most "
        "%.5f%% anywhere)\n",
        d->mesh_to_surface_rms_percent, d->mesh_to_surface_max_percent,
        static_cast<long long>(d->mesh_samples),
        d->mesh_to_surface_max_bound_percent);
    std::printf("  two-sided         rms %.5f%%  Hausdorff %.5f%%\n",
                d->rms_percent, d->hausdorff_percent);
    std::printf("  folded area       %.4f%%\n", d->folded_area_percent);
    if (d->boundary_percent >= 0) {
      std::printf(
          "  boundary          max %.5f%%  (the trims' images against the "
          "mesh's boundary edges, both ways)\n",
          d->boundary_percent);
    }
    std::printf("  lattice level %d, %lld vertices refined on the spline\n",
                d->lattice_level, static_cast<long long>(d->refined_vertices));
    if (!whole) {
      std::printf("  (the largest over %zu fitted parts; per part:)\n",
                  fitted.size());
      for (size_t i = 0; i < measured.size(); ++i) {
        if (model->parts[i].kept) {
          std::printf("  part %zu  kept as a mesh, not measured: %s\n", i + 1,
                      model->parts[i].kept->reason.c_str());
          continue;
        }
        std::printf("  part %zu%s  rms %.5f%%  Hausdorff %.5f%%  folded %.4f%%",
                    i + 1, model->parts[i].trimmed() ? " (trimmed)" : "",
                    measured[i].rms_percent, measured[i].hausdorff_percent,
                    measured[i].folded_area_percent);
        if (measured[i].boundary_percent >= 0) {
          std::printf("  boundary %.5f%%", measured[i].boundary_percent);
        }
        std::printf("\n");
      }
    }
    if (args.Has("picture")) {
      std::printf(
          "  picture           %s (white 0 to red %.5f%%, folded blue)\n",
          picture_path.c_str(), d->surface_to_mesh_max_percent);
    }
  }
  return kExitOk;
}

}  // namespace sdcb::cli
