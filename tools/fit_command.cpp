// sdcb fit MESH -o MODEL.sdcb [--degree K] [--rmse PCT] [--max-error PCT]
//          [--knots-per-round N]
//          [--knots-growth G] [--max-rounds R] [--max-control-points M]
//          [--lambda L]
//          [--threads T] [--regularization R] [--store-parameters]
//          [--quantize BITS|auto] [--knot-grid BITS] [--feature-angle DEG]
//          [--map-vertices N|auto] [--json FILE] [--plot FILE.svg] [--quiet]
//          [--accept-folds] [--repair] [--max-file-mb N] [--max-memory-mb N]
#include <tbb/task_arena.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "sdcb/converters/convergence_plot.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/sphere/unit_vector_grid.h"
#include "sdcb/io/fit_statistics_json.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace sdcb::cli {

const CommandOptions& FitOptionNames() {
  static const CommandOptions names = {
      Concat({"output", "degree", "rmse", "max-error", "knots-per-round",
              "knots-growth", "max-rounds", "max-control-points", "lambda",
              "threads", "json", "plot", "regularization", "quantize",
              "knot-grid", "feature-angle", "map-vertices"},
             kMeshValueOptions),
      Concat({"quiet", "store-parameters", "accept-folds"}, kMeshFlagOptions)};
  return names;
}

int RunFit(const std::vector<std::string>& argv) {
  const Args args(argv, FitOptionNames().values, FitOptionNames().flags);
  args.RequirePositionals(
      1, "MESH (usage: sdcb fit MESH -o MODEL.sdcb [options])");
  const std::string& path = args.positionals()[0];
  const std::string output = args.Get("output");
  if (output.empty()) throw UsageError{"missing -o MODEL.sdcb"};
  FitOptions options;
  options.degree = args.GetInt("degree", options.degree, 2, 5);
  options.rmse_percent =
      args.GetDouble("rmse", options.rmse_percent, 1e-6, 100);
  options.max_error_percent =
      args.GetDouble("max-error", options.max_error_percent, 0, 1000);
  options.knots_per_round =
      args.GetInt("knots-per-round", options.knots_per_round, 1, 100000);
  options.knots_growth =
      args.GetDouble("knots-growth", options.knots_growth, 0, 10);
  options.max_rounds = args.GetInt("max-rounds", options.max_rounds, 1, 1000);
  options.max_control_points = args.GetInt(
      "max-control-points", options.max_control_points, 10, 10000000);
  options.lambda = args.GetDouble("lambda", options.lambda, 1e-3, 1e3);
  // --map-vertices N: split (N > 0) or not (0) from the start, no second
  // fit; auto (default): a second fit split when the first folds or needs
  // more control points than the input has vertices.
  constexpr int kAutoMap = -1;
  const int map_vertices =
      args.GetIntOrAuto("map-vertices", kAutoMap, 0, 10000000, kAutoMap);
  if (map_vertices != kAutoMap) {
    options.map_vertices = map_vertices;
    options.retry_map_vertices = 0;
  }
  options.threads = args.GetInt("threads", 0, 0, 1024);
  options.regularization =
      args.GetDouble("regularization", options.regularization, 1e-12, 1e3);
  // The sphere point of every input vertex is kept only on request: it is
  // most of a file's bytes and needed only to check the vertex errors.
  options.store_parameters = args.Has("store-parameters");
  options.fallback_accepts_folds = args.Has("accept-folds");
  options.feature_angle_degrees =
      args.GetDouble("feature-angle", options.feature_angle_degrees, 1e-3, 180);
  SdcbWriteOptions write_options;
  write_options.store_parameters = options.store_parameters;
  // --quantize auto: the coarsest grid whose bound is within a fraction of the
  // fit's rms. Any --quantize also snaps the knots to a grid, so that the
  // file stores them in a few bytes, exactly as fitted.
  write_options.quantize_bits =
      args.GetIntOrAuto("quantize", 0, 8, 30, kQuantizeBitsAuto);
  if (write_options.quantize_bits != 0) {
    options.knot_grid_bits = kQuantizedFitKnotGridBits;
  }
  // --knot-grid BITS: knots on that grid (0: off), quantized or not.
  options.knot_grid_bits = args.GetInt("knot-grid", options.knot_grid_bits, 0,
                                       kMaxUnitVectorGridBits);

  // Outputs are checked before the work; the mesh is read, repaired if
  // asked, checked (tools/cli.h).
  const Status outputs =
      PrepareOutputs({output, args.Get("json"), args.Get("plot")});
  if (!outputs.ok()) return ReportError(outputs);
  // The checks run on --threads threads too; the self-intersection search
  // beside the fit, in its idle cycles.
  tbb::task_arena arena(options.threads > 0 ? options.threads
                                            : int{tbb::task_arena::automatic});
  StatusOr<TriangleMesh> mesh =
      arena.execute([&] { return ReadFittableMesh(args, path); });
  if (!mesh.ok()) return ReportError(mesh.status());
  SelfIntersectionsBeside intersections(*mesh);

  ProgressBar progress("sdcb fit", args.Has("quiet"));
  options.progress = [bar = progress.Callback()](const FitProgress& p) {
    bar((p.retry.empty() ? "" : p.retry + ", ") + FitStageName(p.stage),
        p.fraction);
  };
  StatusOr<FitResult> fit = FitSphericalSpline(*mesh, options);
  progress.Finish();
  const long long intersecting_pairs = intersections.Warn(path);
  if (!fit.ok()) return ReportError(fit.status().WithPrefix(path));
  if (!fit->reached_target() && intersecting_pairs > 0) {
    // Where the input passes through itself, so does any surface that
    // follows it: its folds may be the mesh's (in the report's shortfall
    // and the warning alike).
    fit->shortfall += "; the input intersects itself (" +
                      IntersectingPairsText(intersecting_pairs) +
                      "), which a surface that follows it does too";
  }
  fit->model.source.file_name = std::filesystem::path(path).filename().string();

  SdcbFileInfo file_info;
  Status written = WriteSdcbFile(fit->model, output, write_options, &file_info);
  if (!written.ok()) return ReportError(written);
  const ControlPointQuantization& quantization = file_info.quantization;
  const FitStatistics& stats = fit->model.statistics;
  if (args.Has("json")) {
    nlohmann::ordered_json report;
    report["input"] = path;
    report["output"] = output;
    report["vertices"] = mesh->num_vertices();
    report["faces"] = mesh->num_faces();
    report["output_bytes"] = file_info.file_bytes;
    if (!quantization.lossless()) {
      // The stored surface is within this of the fitted one everywhere
      // (io/control_point_quantization.h); the errors below are the fit's.
      report["quantization_bits"] = quantization.bits;
      report["quantization_error_bound_percent"] =
          quantization.surface_error_bound_percent();
      report["quantization_bound_measured"] = quantization.basis_sum_measured;
      report["knot_grid_bits"] = file_info.knot_grid_bits;
    }
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
        "  rmse %.4f%%  max error %.4f%%  (targets: rmse %.4f%%, max %.4f%%)  "
        "%.2f s\n",
        f.rmse_percent, f.max_error_percent, options.rmse_percent,
        MaxErrorTarget(options), fit->timings.total);
    const StageTimings& t = fit->timings;
    std::printf(
        "  stages: parameterization %.2f s, knot placement %.2f s, "
        "configurations %.2f s, basis %.2f s, solve %.2f s, measure %.2f s\n",
        t.parameterization, t.knot_placement, t.configurations, t.basis,
        t.solve, t.measure);
    const MeshFeatures& features = fit->features;
    std::printf(
        "  sharp features (normals turning by > %g deg): %zu edges, %zu "
        "curves, %zu corners (%s)\n",
        features.angle_degrees, features.edges.size(), features.curves.size(),
        features.corners.size(),
        fit->features_kept ? "kept: the surface is creased along them"
                           : "detected; the surface is smooth across them");
    const double lambda = fit->model.statistics.options.lambda;
    if (lambda != options.lambda) {
      std::printf(
          "  map: lambda %g (fitted again with the area term weaker: it "
          "folded less%s)\n",
          lambda, fit->reached_target() ? " and reached the targets" : "");
    }
    if (fit->map_vertices != mesh->num_vertices()) {
      std::printf(
          "  map: %s on the input split to %d vertices (the same surface)\n",
          fit->split_retry_returned
              ? "better than the fit on its own triangles; fitted again"
              : "parameterized and fitted",
          fit->map_vertices);
    }
    if (!quantization.lossless()) {
      std::printf(
          "  control points quantized to %d bits: the stored surface is "
          "within %.3g%% of the fitted one%s\n",
          quantization.bits, quantization.surface_error_bound_percent(),
          quantization.basis_sum_measured ? " (bound measured)" : "");
    }
  }
  if (!fit->reached_target()) {
    // Where a returned surface folds, the measurement's picture shows it.
    const std::string where =
        fit->model.statistics.final_result.folded_area_percent > 0
            ? "; `sdcb compare " + output + " " + path +
                  " --picture folds.ply` shows where (blue)"
            : "";
    std::fprintf(
        stderr,
        "sdcb: %s: warning: the targets (rmse %.4f%%, max %.4f%%) were not "
        "reached: %s%s\n",
        path.c_str(), options.rmse_percent, MaxErrorTarget(options),
        fit->shortfall.c_str(), where.c_str());
  }
  return kExitOk;
}

}  // namespace sdcb::cli
