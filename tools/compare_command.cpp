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
#include <vector>

#include "sdcb/converters/mesh/color_ramp.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/mesh/mesh_writer.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {

namespace {

constexpr int kDefaultMeshSamples = 100000;

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
  StatusOr<SplineModel> model = ReadSdcbFile(model_path);
  if (!model.ok()) return ReportError(model.status());
  StatusOr<TriangleMesh> mesh = ReadMesh(mesh_path);
  if (!mesh.ok()) return ReportError(mesh.status());
  StatusOr<SphericalSpline> surface = SurfaceFromModel(*model);
  if (!surface.ok())
    return ReportError(surface.status().WithPrefix(model_path));

  // Both in the model's normalized frame; 100 % = the mesh's largest side.
  TriangleMesh normalized = *mesh;
  normalized.vertices = model->transform.ToNormalized(mesh->vertices);
  StatusOr<NormalizingTransform> own = ComputeNormalizingTransform(*mesh);
  if (!own.ok()) return ReportError(own.status().WithPrefix(mesh_path));
  options.length_unit = own->scale / model->transform.scale;
  StatusOr<SurfaceDeviation> d =
      MeasureSurfaceDeviation(*surface, normalized, options);
  if (!d.ok()) {
    return ReportError(d.status().WithPrefix(model_path + " vs " + mesh_path));
  }
  if (args.Has("picture")) {
    const Status s = WritePicture(*d, model->transform, picture_path);
    if (!s.ok()) return ReportError(s);
  }
  if (args.Has("json")) {
    nlohmann::ordered_json j;
    j["model"] = model_path;
    j["mesh"] = mesh_path;
    j["rmse_percent"] = d->rms_percent;
    j["max_error_percent"] = d->hausdorff_percent;
    j["hausdorff_percent"] = d->hausdorff_percent;
    j["surface_to_mesh_rms_percent"] = d->surface_to_mesh_rms_percent;
    j["surface_to_mesh_max_percent"] = d->surface_to_mesh_max_percent;
    j["mesh_to_surface_rms_percent"] = d->mesh_to_surface_rms_percent;
    j["mesh_to_surface_max_percent"] = d->mesh_to_surface_max_percent;
    j["mesh_to_surface_max_bound_percent"] =
        d->mesh_to_surface_max_bound_percent;
    j["folded_area_percent"] = d->folded_area_percent;
    j["surface_samples"] = d->surface_samples;
    j["mesh_samples"] = d->mesh_samples;
    j["mesh_bound_samples"] = d->mesh_bound_samples;
    j["mesh_sample_spacing_percent"] = d->mesh_sample_spacing_percent;
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
    std::printf("  lattice level %d, %lld vertices refined on the spline\n",
                d->lattice_level, static_cast<long long>(d->refined_vertices));
    if (args.Has("picture")) {
      std::printf(
          "  picture           %s (white 0 to red %.5f%%, folded blue)\n",
          picture_path.c_str(), d->surface_to_mesh_max_percent);
    }
  }
  return kExitOk;
}

}  // namespace sdcb::cli
