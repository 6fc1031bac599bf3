// sdcb export MODEL.sdcb -o OUT.{obj,ply,stl,gltf,glb} [--tolerance PCT]
//   [--angle DEG] [--uniform N] [--draco [--qp BITS] [--cl LEVEL]]
//   [--meshopt] [--colors none|error|curvature|gaussian] [--mesh MESH]
//   [--json FILE] [--quiet]
// Parses the flags and calls ExportSurfaceMesh
// (converters/mesh/surface_mesh_export.h), which does the work.
#include <OpenMesh/Core/System/omstream.hh>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "sdcb/converters/mesh/surface_mesh_export.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/io/common/atomic_file.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace sdcb::cli {

const std::vector<ExportOption>& ExportOptions() {
  using T = ExportTarget;
  static const std::vector<ExportOption> options = {
      {"output", true, T::kAll},
      {"tolerance", true, T::kAll},
      {"json", true, T::kAll},
      {"quiet", false, T::kAll},
      {"uniform", true, T::kMesh},
      {"qp", true, T::kMesh},
      {"cl", true, T::kMesh},
      {"colors", true, T::kMesh},
      {"mesh", true, T::kMesh},
      {"measure-samples", true, T::kMesh},
      {"draco", false, T::kMesh},
      {"meshopt", false, T::kMesh},
      {"angle", true, T::kMesh},
      {"max-faces", true, T::kCad},
      {"smoothness-degrees", true, T::kCad},
      {"max-control-points", true, T::kCad},
  };
  return options;
}

const CommandOptions& ExportOptionNames() {
  static const CommandOptions names = [] {
    CommandOptions n;
    for (const ExportOption& o : ExportOptions()) {
      (o.takes_value ? n.values : n.flags).push_back(o.name);
    }
    return n;
  }();
  return names;
}

bool IsExportExtension(const std::string& ext) {
  return ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".gltf" ||
         ext == ".glb";
}

int RunExport(const std::vector<std::string>& argv) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  // OpenMesh's writers log to stderr ("[OBJWriter] : write file"); the
  // command line owns the process, so it silences them.
  omlog().disable();
  omout().disable();
  const Args args(argv, ExportOptionNames().values, ExportOptionNames().flags);
  args.RequirePositionals(1,
                          "MODEL (usage: sdcb export MODEL.sdcb "
                          "-o OUT.{obj,ply,stl,gltf,glb,step,stp,igs,iges})");
  const std::string model_path = args.positionals()[0];
  const std::string output = args.Get("output");
  if (output.empty()) {
    throw UsageError{"missing -o OUT.{obj,ply,stl,gltf,glb,step,stp,igs,iges}"};
  }
  const std::string ext = LowercaseExtension(output);
  if (IsCadExtension(ext)) return RunCadExport(args, ext);
  for (const ExportOption& o : ExportOptions()) {
    if (o.target == ExportTarget::kCad && args.Has(o.name)) {
      throw UsageError{std::string("--") + o.name +
                       " goes with a .step, .stp, .igs or .iges output"};
    }
  }
  SurfaceMeshExportOptions options;
  if (!ExportFormatOfExtension(ext, &options.format)) {
    throw UsageError{"unknown output extension '" + ext + "' in " + output +
                     " (use .obj, .ply, .stl, .gltf, .glb, .step, .stp, .igs "
                     "or .iges)"};
  }
  const bool gltf = ext == ".gltf" || ext == ".glb";
  const bool draco = args.Has("draco"), meshopt = args.Has("meshopt");
  if (draco && meshopt)
    throw UsageError{"--draco and --meshopt exclude each other"};
  if ((draco || meshopt) && !gltf) {
    throw UsageError{"--draco and --meshopt need a .gltf or .glb output"};
  }
  if ((args.Has("qp") || args.Has("cl")) && !draco && !meshopt) {
    throw UsageError{
        "--qp and --cl go with --draco (--qp also with --meshopt)"};
  }
  if (args.Has("cl") && !draco) throw UsageError{"--cl goes with --draco"};
  const std::string colors = args.Get("colors", "none");
  if (colors == "curvature") {
    options.colors = VertexColoring::kMeanCurvature;
  } else if (colors == "gaussian") {
    options.colors = VertexColoring::kGaussianCurvature;
  } else if (colors == "error") {
    options.colors = VertexColoring::kDistanceToMesh;
  } else if (colors != "none") {
    throw UsageError{"--colors must be none, error, curvature or gaussian"};
  }
  if (colors == "error" && !args.Has("mesh")) {
    throw UsageError{
        "--colors error needs --mesh MESH (the mesh to compare with)"};
  }
  if (colors != "none" && (ext == ".obj" || ext == ".stl")) {
    throw UsageError{"--colors needs a .ply, .gltf or .glb output"};
  }
  options.tolerance_percent = args.GetDouble("tolerance", 0.1, 1e-6, 50.0);
  options.angle_degrees = args.GetDouble("angle", 20.0, 1e-3, 180.0);
  options.uniform_vertices = args.GetInt("uniform", 0, 0, 3000000);
  options.compression = draco     ? GltfCompression::kDraco
                        : meshopt ? GltfCompression::kMeshopt
                                  : GltfCompression::kNone;
  options.position_bits = args.GetInt("qp", 0, 1, meshopt ? 16 : 30);
  options.draco_level = args.GetInt("cl", 7, 0, 10);
  options.measure_samples_per_face = args.GetInt("measure-samples", 4, 0, 1000);
  const std::string json_path = args.Get("json");
  const bool quiet = args.Has("quiet") || json_path == "-";

  const Status prepared = PrepareOutputs({output, json_path});
  if (!prepared.ok()) return ReportError(prepared);
  StatusOr<Model> read = ReadSdcbModelFile(model_path);
  if (!read.ok()) return ReportError(read.status());
  const Model model = std::move(read).value();
  StatusOr<TriangleMesh> reference = TriangleMesh();
  if (options.colors == VertexColoring::kDistanceToMesh) {
    options.mesh_name = args.Get("mesh");
    reference = ReadInputMesh(options.mesh_name);
    if (!reference.ok()) return ReportError(reference.status());
    options.mesh = &*reference;
  }
  ProgressBar progress("sdcb export", quiet);
  options.progress = progress.Callback();
  StatusOr<SurfaceMeshExport> exported = ExportSurfaceMesh(model, options);
  progress.Finish();
  if (!exported.ok()) {
    // Options the model cannot satisfy (meshopt's 16 bits) are usage.
    if (exported.status().code() == StatusCode::kInvalidArgument) {
      throw UsageError{exported.status().message()};
    }
    return ReportError(exported.status().WithPrefix(model_path));
  }
  SurfaceMeshExportReport& report = exported->report;
  const Clock::time_point t0 = Clock::now();
  Status written = WriteFileAtomically(exported->bytes, output);
  if (!written.ok()) return ReportError(written);
  report.seconds.write +=
      std::chrono::duration<double>(Clock::now() - t0).count();
  report.seconds.total =
      std::chrono::duration<double>(Clock::now() - start).count();

  if (!json_path.empty()) {
    nlohmann::ordered_json j;
    j["model"] = model_path;
    j["output"] = output;
    j.update(SurfaceMeshExportReportToJson(report));
    written = WriteTextOutput(json_path, j.dump(2) + "\n");
    if (!written.ok()) {
      // Nothing left behind: the file goes with its report.
      std::error_code ignored;
      std::filesystem::remove(output, ignored);
      return ReportError(written);
    }
  }
  if (!quiet) {
    std::printf("%s -> %s: %lld triangles, %lld vertices, %lld bytes\n",
                model_path.c_str(), output.c_str(),
                static_cast<long long>(report.triangles),
                static_cast<long long>(report.vertices),
                static_cast<long long>(report.bytes));
    if (options.uniform_vertices > 0) {
      // A uniform mesh has no tolerance to hold or optimum to compare.
      std::printf(
          "  uniform, no tolerance  measured max distance %.4g%%  "
          "%.2f s\n",
          report.max_distance_percent, report.seconds.total);
    } else {
      std::printf(
          "  tolerance %.4g%%  measured max distance %.4g%%  %.2f x optimum  "
          "%.2f s\n",
          report.tolerance_percent, report.max_distance_percent,
          report.triangles_vs_optimum, report.seconds.total);
    }
    std::printf(
        "  seconds: samples %.2f, simplify %.2f, verify %.2f, measure %.2f, "
        "optimum %.2f, encode and write %.2f\n",
        report.seconds.samples, report.seconds.simplify, report.seconds.verify,
        report.seconds.measure, report.seconds.optimum, report.seconds.write);
  }
  return kExitOk;
}

}  // namespace sdcb::cli
