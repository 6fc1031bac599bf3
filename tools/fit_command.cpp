// sdcb fit MESH -o MODEL.sdcb [--degree K] [--rmse PCT] [--knots-per-round N]
//          [--max-rounds R] [--max-control-points M] [--lambda L]
//          [--threads T] [--json FILE] [--plot FILE.svg] [--quiet]
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "sdcb/converters/convergence_plot.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/io/fit_statistics_json.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace sdcb::cli {

int RunFit(const std::vector<std::string>& argv) {
  const Args args(argv,
                  {"output", "degree", "rmse", "knots-per-round", "max-rounds",
                   "max-control-points", "lambda", "threads", "json", "plot",
                   "regularization"},
                  {"quiet"});
  args.RequirePositionals(
      1, "MESH (usage: sdcb fit MESH -o MODEL.sdcb [options])");
  const std::string& path = args.positionals()[0];
  const std::string output = args.Get("output");
  if (output.empty()) throw UsageError{"missing -o MODEL.sdcb"};
  FitOptions options;
  options.degree = args.GetInt("degree", options.degree, 2, 5);
  options.rmse_percent =
      args.GetDouble("rmse", options.rmse_percent, 1e-6, 100);
  options.knots_per_round =
      args.GetInt("knots-per-round", options.knots_per_round, 1, 100000);
  options.max_rounds = args.GetInt("max-rounds", options.max_rounds, 1, 1000);
  options.max_control_points = args.GetInt(
      "max-control-points", options.max_control_points, 10, 10000000);
  options.lambda = args.GetDouble("lambda", options.lambda, 1e-3, 1e3);
  options.threads = args.GetInt("threads", 0, 0, 1024);
  options.regularization =
      args.GetDouble("regularization", options.regularization, 1e-12, 1e3);

  StatusOr<TriangleMesh> mesh = ReadMesh(path);
  if (!mesh.ok()) return ReportError(mesh.status());
  const Status intake = RequireClosedGenusZero(*mesh);
  if (!intake.ok()) return ReportError(intake.WithPrefix(path));

  ProgressBar progress("sdcb fit", args.Has("quiet"));
  options.progress = [bar = progress.Callback()](const FitProgress& p) {
    bar(FitStageName(p.stage), p.fraction);
  };
  StatusOr<FitResult> fit = FitSphericalSpline(*mesh, options);
  progress.Finish();
  if (!fit.ok()) return ReportError(fit.status().WithPrefix(path));
  fit->model.source.file_name = std::filesystem::path(path).filename().string();

  Status written = WriteSdcbFile(fit->model, output);
  if (!written.ok()) return ReportError(written);
  const FitStatistics& stats = fit->model.statistics;
  if (args.Has("json")) {
    nlohmann::ordered_json report;
    report["input"] = path;
    report["output"] = output;
    report["vertices"] = mesh->num_vertices();
    report["faces"] = mesh->num_faces();
    const nlohmann::ordered_json fit_report = FitReportToJson(*fit);
    for (const auto& [key, value] : fit_report.items()) report[key] = value;
    written = WriteTextOutput(args.Get("json"), report.dump(2) + "\n");
    if (!written.ok()) return ReportError(written);
  }
  if (args.Has("plot")) {
    written =
        WriteConvergencePlot(stats,
                             std::filesystem::path(path).filename().string() +
                                 ", degree " + std::to_string(options.degree),
                             args.Get("plot"));
    if (!written.ok()) return ReportError(written);
  }
  const RoundStatistics& f = stats.final_result;
  if (!args.Has("quiet") && args.Get("json") != "-") {
    std::printf("%s -> %s: degree %d, %d knots, %d control points, %d rounds\n",
                path.c_str(), output.c_str(), options.degree, f.knots,
                f.control_points, static_cast<int>(stats.rounds.size()));
    std::printf(
        "  rmse %.4f%%  max error %.4f%%  (target rmse %.4f%%)  %.2f s\n",
        f.rmse_percent, f.max_error_percent, options.rmse_percent,
        fit->timings.total);
  }
  if (!fit->reached_target()) {
    std::fprintf(
        stderr,
        "sdcb: %s: warning: rmse %.4f%% did not reach the target %.4f%% "
        "within the round or control-point limits\n",
        path.c_str(), f.rmse_percent, options.rmse_percent);
  }
  return kExitOk;
}

}  // namespace sdcb::cli
