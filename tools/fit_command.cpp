// sdcb fit MESH -o MODEL.sdcb [options]: the options of its FitOptions come
// from FitOptionTable (core/fit/fit_options.h), the others from
// OwnOptionSpecs below; FitUsage() is its usage text.
#include <tbb/task_arena.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "sdcb/core/fit/fit_options.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/sphere/unit_vector_grid.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/report/convergence_plot.h"
#include "sdcb/io/report/fit_statistics_json.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace sdcb::cli {

namespace {

// "0.05", "1e-06".
std::string DefaultText(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// The options of `sdcb fit` that are not FitOptions.
const std::vector<OptionSpec>& OwnOptionSpecs() {
  static const std::vector<OptionSpec> specs = {
      {"quantize", "BITS|auto",
       "store the control points in BITS bits (8..30), the error bound "
       "reported (auto: the coarsest grid whose bound is within half the "
       "fit's rms), the knots on a 16-bit grid"},
      {"json", "FILE", "the report (docs/CLI.md)"},
      {"plot", "FILE.svg", "the error per round"},
      {"quiet", "", "no progress bar, no summary"},
  };
  return specs;
}

// Sets the FitOptions of `table` that have a flag from `args`.
void ParseFitOptionFlags(const Args& args,
                         const std::vector<FitOptionDescriptor>& table,
                         FitOptions* options) {
  for (const FitOptionDescriptor& d : table) {
    if (d.flag == nullptr) continue;
    if (d.value_name == nullptr) {
      options->*std::get<bool FitOptions::*>(d.field) = args.Has(d.flag);
    } else if (const auto* f = std::get_if<int FitOptions::*>(&d.field)) {
      int& value = options->**f;
      const int lo = static_cast<int>(d.flag_lo);
      const int hi = static_cast<int>(d.flag_hi);
      if (d.auto_clears == nullptr) {
        value = args.GetInt(d.flag, value, lo, hi);
        continue;
      }
      const int automatic = lo - 1;  // no value of the flag's own
      const int v = args.GetIntOrAuto(d.flag, automatic, lo, hi, automatic);
      if (v != automatic) {
        value = v;
        options->*d.auto_clears = 0;
      }
    } else {
      double FitOptions::*g = std::get<double FitOptions::*>(d.field);
      options->*g = args.GetDouble(d.flag, options->*g, d.flag_lo, d.flag_hi);
    }
  }
}

// The summary on stdout (docs/CLI.md): the model, its errors against the
// targets, the seconds per stage, the features, the map and quantization.
void PrintFitSummary(const std::string& path, const std::string& output,
                     const FitOptions& options, const FitResult& result,
                     int input_vertices,
                     const ControlPointQuantization& quantization) {
  const FitStatistics& stats = result.model.statistics;
  const RoundStatistics& f = stats.final_result;
  std::printf("%s -> %s: degree %d, %d knots, %d control points, %d rounds\n",
              path.c_str(), output.c_str(), options.degree, f.knots,
              f.control_points, static_cast<int>(stats.rounds.size()));
  std::printf(
      "  rmse %.4f%%  max error %.4f%%  (targets: rmse %.4f%%, max %.4f%%)  "
      "%.2f s\n",
      f.rmse_percent, f.max_error_percent, options.rmse_percent,
      MaxErrorTarget(options), result.timings.total);
  const StageTimings& t = result.timings;
  std::printf(
      "  stages: parameterization %.2f s, knot placement %.2f s, "
      "configurations %.2f s, basis %.2f s, solve %.2f s, measure %.2f s\n",
      t.parameterization, t.knot_placement, t.configurations, t.basis, t.solve,
      t.measure);
  const MeshFeatures& features = result.features;
  std::printf(
      "  sharp features (normals turning by > %g deg): %zu edges, %zu "
      "curves, %zu corners (%s)\n",
      features.angle_degrees, features.edges.size(), features.curves.size(),
      features.corners.size(),
      result.features_kept ? "kept: the surface is creased along them"
                           : "detected; the surface is smooth across them");
  const double lambda = result.model.statistics.options.lambda;
  if (lambda != options.lambda) {
    std::printf(
        "  map: lambda %g (fitted again with the area term weaker: it "
        "folded less%s)\n",
        lambda, result.reached_target() ? " and reached the targets" : "");
  }
  if (result.map_vertices != input_vertices) {
    std::printf(
        "  map: %s on the input split to %d vertices (the same surface)\n",
        result.split_retry_returned
            ? "better than the fit on its own triangles; fitted again"
            : "parameterized and fitted",
        result.map_vertices);
  }
  if (!quantization.lossless()) {
    std::printf(
        "  control points quantized to %d bits: the stored surface is "
        "within %.3g%% of the fitted one%s\n",
        quantization.bits, quantization.surface_error_bound_percent(),
        quantization.basis_sum_measured ? " (bound measured)" : "");
  }
}

}  // namespace

const std::vector<OptionSpec>& FitOptionSpecs() {
  static const std::vector<OptionSpec> specs = [] {
    std::vector<OptionSpec> all;
    const FitOptions defaults;
    for (const FitOptionDescriptor& d : FitOptionTable()) {
      if (d.flag == nullptr) continue;
      std::string help = d.help;
      if (d.value_name != nullptr) {
        help += " (default " +
                (d.default_text != nullptr
                     ? std::string(d.default_text)
                     : DefaultText(FitOptionValue(defaults, d))) +
                ")";
      }
      all.push_back(
          {d.flag, d.value_name != nullptr ? d.value_name : "", help});
    }
    const std::vector<OptionSpec>& own = OwnOptionSpecs();
    all.insert(all.end(), own.begin(), own.end());
    return all;
  }();
  return specs;
}

const CommandOptions& FitOptionNames() {
  static const CommandOptions names = [] {
    CommandOptions n = OptionNamesOf(FitOptionSpecs());
    n.values = Concat(Concat(n.values, {"output"}), kMeshValueOptions);
    n.flags = Concat(n.flags, kMeshFlagOptions);
    return n;
  }();
  return names;
}

std::string FitUsage() {
  return "  fit MESH -o MODEL.sdcb [options] [--repair]\n"
         "                             Fit one smooth spherical DCB-spline "
         "(--repair\n"
         "                             as for check); the options:\n" +
         OptionUsage(FitOptionSpecs());
}

int RunFit(const std::vector<std::string>& argv) {
  const Args args(argv, FitOptionNames().values, FitOptionNames().flags);
  args.RequirePositionals(
      1, "MESH (usage: sdcb fit MESH -o MODEL.sdcb [options])");
  const std::string& path = args.positionals()[0];
  const std::string output = args.Get("output");
  if (output.empty()) throw UsageError{"missing -o MODEL.sdcb"};
  FitOptions options;
  SdcbWriteOptions write_options;
  // --quantize auto: the coarsest grid whose bound is within a fraction of the
  // fit's rms. Any --quantize also snaps the knots to a grid (the default of
  // --knot-grid then), so that the file stores them in a few bytes, exactly
  // as fitted.
  write_options.quantize_bits =
      args.GetIntOrAuto("quantize", 0, 8, 30, kQuantizeBitsAuto);
  if (write_options.quantize_bits != 0) {
    options.knot_grid_bits = kQuantizedFitKnotGridBits;
  }
  // The rest by the table (core/fit/fit_options.h): --map-vertices N splits
  // (N > 0) or not (0) from the start, no second fit; auto (default): a
  // second fit split when the first folds or needs more control points than
  // the input has vertices. --store-parameters: the sphere point of every
  // input vertex is kept only on request, it is most of a file's bytes and
  // needed only to check the vertex errors.
  ParseFitOptionFlags(args, FitOptionTable(), &options);
  write_options.store_parameters = options.store_parameters;

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
      // (io/sdcb/control_point_quantization.h); the errors below are the fit's.
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
  if (!args.Has("quiet") && args.Get("json") != "-") {
    PrintFitSummary(path, output, options, *fit, mesh->num_vertices(),
                    quantization);
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
