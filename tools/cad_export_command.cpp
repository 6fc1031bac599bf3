// sdcb export MODEL.sdcb -o OUT.{step,stp,igs,iges} [--tolerance PCT]
//   [--smoothness-degrees DEG] [--max-faces N] [--max-control-points M]
//   [--json FILE] [--quiet]
//
// Parses the flags and calls WriteCadExport (converters/cad/cad_export.h;
// docs/CAD.md).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "sdcb/converters/cad/cad_export.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace sdcb::cli {

bool IsCadExtension(const std::string& ext) {
  return ext == ".step" || ext == ".stp" || ext == ".igs" || ext == ".iges";
}

int RunCadExport(const Args& args, const std::string& ext) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  // OpenCASCADE's writers print statistics on stdout; the command line owns
  // the process, so it silences them.
  SilenceOpenCascadeMessages();
  for (const ExportOption& o : ExportOptions()) {
    if (o.target == ExportTarget::kMesh && args.Has(o.name)) {
      throw UsageError{std::string("--") + o.name + " does not apply to a " +
                       ext + " output"};
    }
  }
  const std::string model_path = args.positionals()[0];
  const std::string output = args.Get("output");
  const std::string json_path = args.Get("json");
  CadExportOptions options;
  CadNetworkOptions& network = options.network;
  network.tolerance_percent =
      args.GetDouble("tolerance", network.tolerance_percent, 1e-6, 50.0);
  network.smoothness_degrees = args.GetDouble(
      "smoothness-degrees", network.smoothness_degrees, 1e-3, 180.0);
  network.max_faces = args.GetInt("max-faces", network.max_faces, 1, 2000000);
  network.max_control_points = args.GetInt(
      "max-control-points", network.max_control_points, 100, 20000000);
  const bool quiet = args.Has("quiet") || json_path == "-";
  options.format =
      (ext == ".igs" || ext == ".iges") ? CadFormat::kIges : CadFormat::kStep;

  const Status prepared = PrepareOutputs({output, json_path});
  if (!prepared.ok()) return ReportError(prepared);
  StatusOr<Model> read = ReadSdcbModelFile(model_path);
  if (!read.ok()) return ReportError(read.status());
  const Model model = std::move(read).value();

  ProgressBar progress("sdcb export", quiet);
  options.progress = progress.Callback();
  StatusOr<CadExportReport> report = WriteCadExport(model, options, output);
  progress.Finish();
  if (!report.ok()) {
    // What the model causes names the model; the writer's messages name
    // the output already.
    const StatusCode code = report.status().code();
    return ReportError(code == StatusCode::kInvalidInput ||
                               code == StatusCode::kInvalidArgument
                           ? report.status().WithPrefix(model_path)
                           : report.status());
  }
  report->seconds.total =
      std::chrono::duration<double>(Clock::now() - start).count();

  if (!json_path.empty()) {
    nlohmann::ordered_json j;
    j["model"] = model_path;
    j["output"] = output;
    j.update(CadExportReportToJson(*report));
    const Status s = WriteTextOutput(json_path, j.dump(2) + "\n");
    if (!s.ok()) {
      // Nothing left behind: the file goes with its report.
      std::error_code ignored;
      std::filesystem::remove(output, ignored);
      return ReportError(s);
    }
  }
  if (!quiet) {
    std::printf(
        "%s -> %s: %d bicubic B-spline faces (%d control points), one "
        "closed solid (volume %.6g mm^3)\n"
        "  max distance to the spline %.4g%% (tolerance %.4g%%), max normal "
        "jump across edges %.3g deg (limit %.3g)  %.2f s\n",
        model_path.c_str(), output.c_str(), report->faces,
        report->control_points, report->volume, report->max_distance_percent,
        report->tolerance_percent, report->max_normal_jump_degrees,
        report->smoothness_degrees, report->seconds.total);
  }
  return kExitOk;
}

}  // namespace sdcb::cli
