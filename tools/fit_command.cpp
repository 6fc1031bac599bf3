// sdcb fit MESH -o MODEL.sdcb [options]: the options of its FitOptions come
// from FitOptionTable (core/fit/fit_options.h), the others from
// OwnOptionSpecs below; FitUsage() is its usage text.
#include <tbb/task_arena.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "sdcb/core/fit/fit_model.h"
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
      {"max-parts", "N",
       "refuse a mesh of more than N parts before fitting any (default "
       "1000; 0: no limit)"},
      {"keep-unfittable", "",
       "keep a part sdcb cannot fit (genus > 0, not manifold, a fit that "
       "fails or misses folded) as its input triangles, instead of refusing "
       "the mesh; the report says why (always so for .gltf / .glb: an asset "
       "is never refused for one part)"},
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

// An open part's line of the summary: its boundary loops and the fill.
void PrintOpenPartLine(const PartFit& part) {
  if (part.report.closed || part.kept()) return;
  std::printf(
      "  open: %d boundary loop%s, trimmed there; holes filled with %d "
      "triangles (%.2f s) that only keep the surface smooth\n",
      part.report.topology.boundary_loops,
      part.report.topology.boundary_loops == 1 ? "" : "s", part.fill_faces,
      part.fill_seconds);
}

// A kept part's line: its triangles and why it was not fitted.
void PrintKeptPartLine(const PartFit& part) {
  std::printf("  part %d: %d triangles, kept as a mesh: %s\n",
              part.report.number, part.report.topology.faces,
              part.kept_reason.c_str());
}

// The summary of a model of several parts: one line per part.
void PrintPartsSummary(const std::string& path, const std::string& output,
                       const ModelFit& fit) {
  int reached = 0, kept = 0;
  for (const PartFit& part : fit.parts) {
    kept += part.kept();
    reached += !part.kept() && part.fit.reached_target();
  }
  std::printf("%s -> %s: %zu parts, %d reached the targets%s\n", path.c_str(),
              output.c_str(), fit.parts.size(), reached,
              kept == 0 ? "" : (", " + std::to_string(kept) + " kept").c_str());
  for (const PartFit& part : fit.parts) {
    if (part.kept()) {
      PrintKeptPartLine(part);
      continue;
    }
    const RoundStatistics& f = part.fit.model.statistics.final_result;
    const int loops = part.report.topology.boundary_loops;
    std::printf(
        "  part %d: %d triangles, %s, %d control points, rmse %.4f%%, max "
        "%.4f%%, %.2f s%s\n",
        part.report.number, part.report.topology.faces,
        loops == 0 ? "closed"
                   : (std::to_string(loops) + " boundary loop" +
                      (loops == 1 ? "" : "s"))
                         .c_str(),
        f.control_points, f.rmse_percent, f.max_error_percent,
        part.fit.timings.total + part.fill_seconds,
        part.fit.reached_target() ? "" : " (missed)");
  }
}

// A part's entry of the report's "parts" (docs/CLI.md): its intake, its fill
// and its fit's report; a kept part's reason instead of a fit.
nlohmann::ordered_json PartJson(const PartFit& part) {
  nlohmann::ordered_json j;
  j["number"] = part.report.number;
  j["triangles"] = part.report.topology.faces;
  j["vertices"] = part.report.topology.vertices;
  j["closed"] = part.report.closed;
  j["boundary_loops"] = part.report.topology.boundary_loops;
  j["fill_faces"] = part.fill_faces;
  j["fill_seconds"] = part.fill_seconds;
  j["kept"] = part.kept();
  if (part.kept()) {
    j["reason"] = part.kept_reason;
    return j;
  }
  const nlohmann::ordered_json fit_report = FitReportToJson(part.fit);
  for (const auto& [key, value] : fit_report.items()) j[key] = value;
  return j;
}

// The sentence of a glTF input's refused part, led by the name of the part
// (its primitive's, PartNames): "part \"Duck\": part 1 (...) is not ...".
// Other refusals and inputs as they are.
Status NameRefusedPrimitive(const Status& refused, const TriangleMesh& mesh,
                            const MeshOrigin& origin,
                            const ModelFitOptions& options) {
  if (origin.face_primitive.empty() ||
      refused.code() != StatusCode::kUnsupported) {
    return refused;
  }
  StatusOr<std::vector<MeshPart>> parts =
      SplitIntoParts(mesh, options.max_parts);
  if (!parts.ok()) return refused;
  const std::vector<std::string> names = PartNames(*parts, origin);
  for (size_t i = 0; i < parts->size(); ++i) {
    StatusOr<PartReport> report =
        ReportPart((*parts)[i], static_cast<int>(i) + 1);
    if (report.ok() && !report->fittable()) {
      return Status(refused.code(),
                    "part \"" + names[i] + "\": " + refused.message());
    }
  }
  return refused;
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

  // Outputs are checked before the work; the mesh is read and repaired if
  // asked (tools/cli.h); FitModel checks every part before it fits any.
  const Status outputs =
      PrepareOutputs({output, args.Get("json"), args.Get("plot")});
  if (!outputs.ok()) return ReportError(outputs);
  // The checks run on --threads threads too; the self-intersection search
  // beside the fit, in its idle cycles.
  tbb::task_arena arena(options.threads > 0 ? options.threads
                                            : int{tbb::task_arena::automatic});
  MeshIntakeNotes notes;
  MeshOrigin origin;
  StatusOr<TriangleMesh> mesh =
      arena.execute([&] { return ReadMeshToFit(args, path, &notes, &origin); });
  if (!mesh.ok()) return ReportError(mesh.status());
  ModelFitOptions model_options;
  model_options.max_parts =
      args.GetInt("max-parts", model_options.max_parts, 0, INT_MAX);
  model_options.keep_unfittable =
      args.Has("keep-unfittable") || IsGltfPath(path);
  // Every part checked before any work, with the sentences of `sdcb check`
  // (core/mesh/mesh_parts.h).
  StatusOr<PartsIntake> intake = arena.execute([&] {
    return TakeInParts(*mesh, model_options.max_parts,
                       model_options.keep_unfittable);
  });
  if (!intake.ok()) {
    return ReportError(
        NameRefusedPrimitive(
            Status(intake.status().code(),
                   WithSeamHint(intake.status().message(), notes.seams)),
            *mesh, origin, model_options)
            .WithPrefix(path));
  }
  // A glTF input's primitives are in their own local frames: pairs of
  // different parts are not searched.
  std::optional<SelfIntersectionsBeside> intersections;
  if (origin.face_primitive.empty()) {
    intersections.emplace(*mesh);
  } else {
    intersections.emplace(intake->parts, mesh->num_faces());
  }

  ProgressBar progress("sdcb fit", args.Has("quiet"));
  options.progress = [bar = progress.Callback()](const FitProgress& p) {
    bar((p.retry.empty() ? "" : p.retry + ", ") + FitStageName(p.stage),
        p.fraction);
  };
  model_options.fit = options;
  // A glTF input's textures are baked from the parts' maps to the sphere
  // (KeptGltfAsset): kept in memory, written only on request.
  if (!origin.face_primitive.empty()) model_options.fit.store_parameters = true;
  model_options.part_done = [bar = progress.Callback()](int done, int total) {
    bar("parts fitted " + std::to_string(done) + "/" + std::to_string(total),
        static_cast<double>(done) / total);
  };
  StatusOr<ModelFit> fit =
      arena.execute([&] { return FitModel(*mesh, *intake, model_options); });
  progress.Finish();
  const long long intersecting_pairs = intersections->Warn(path);
  if (!fit.ok()) return ReportError(fit.status().WithPrefix(path));
  if (intersecting_pairs > 0) {
    // Where the input passes through itself, so does any surface that
    // follows it: its folds may be the mesh's (in the report's shortfall
    // and the warning alike).
    for (PartFit& part : fit->parts) {
      if (part.kept() || part.fit.reached_target()) continue;
      part.fit.shortfall += "; the input intersects itself (" +
                            IntersectingPairsText(intersecting_pairs) +
                            "), which a surface that follows it does too";
    }
  }
  // Where the input turns back on itself, a surface that follows it faces
  // against the turned triangles: a missed part whose rounds folded says so.
  for (size_t i = 0; i < fit->parts.size(); ++i) {
    PartFit& part = fit->parts[i];
    if (part.kept() || part.fit.reached_target()) continue;
    const std::vector<RoundStatistics>& rounds =
        part.fit.model.statistics.rounds;
    if (std::none_of(rounds.begin(), rounds.end(),
                     [](const RoundStatistics& r) {
                       return r.folded_area_percent > 0;
                     })) {
      continue;
    }
    const long long turn_backs = CountTurnBackEdges(intake->parts[i].mesh);
    if (turn_backs > 0) {
      part.fit.shortfall += "; " + TurnBackEdgesText(turn_backs) +
                            ", where a surface that follows it faces against "
                            "some of them, which counts as folded";
    }
  }
  // A glTF input's parts are named after their primitives.
  const std::vector<std::string> names = PartNames(intake->parts, origin);
  for (size_t i = 0; i < names.size(); ++i) fit->model.parts[i].name = names[i];
  // ... and the asset around them is kept, to be written back by export.
  std::vector<std::string> asset_warnings;
  StatusOr<std::string> asset =
      KeptGltfAsset(intake->parts, fit->model.parts, origin, &asset_warnings);
  if (!asset.ok()) return ReportError(asset.status().WithPrefix(path));
  for (const std::string& w : asset_warnings) {
    std::cerr << "sdcb: " << path << ": warning: " << w << "\n";
  }
  fit->model.asset = std::move(asset).value();
  const std::string file_name = std::filesystem::path(path).filename().string();
  fit->model.source.file_name = file_name;
  for (ModelPart& part : fit->model.parts) {
    part.spline.source.file_name = file_name;
  }
  for (PartFit& part : fit->parts) part.fit.model.source.file_name = file_name;

  SdcbFileInfo file_info;
  Status written =
      WriteSdcbModelFile(fit->model, output, write_options, &file_info);
  if (!written.ok()) return ReportError(written);
  const ControlPointQuantization& quantization = file_info.quantization;
  const bool one_part = fit->parts.size() == 1;
  if (args.Has("json")) {
    nlohmann::ordered_json report;
    report["input"] = path;
    report["output"] = output;
    report["vertices"] = mesh->num_vertices();
    report["faces"] = mesh->num_faces();
    report["seam_vertices_merged"] = notes.seams.merged_vertices;
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
    // One closed part: its report's keys at the top, as for every model of
    // one part; otherwise a "parts" array of them (docs/CLI.md).
    if (one_part && fit->parts[0].report.closed && !fit->parts[0].kept()) {
      const nlohmann::ordered_json fit_report =
          FitReportToJson(fit->parts[0].fit);
      for (const auto& [key, value] : fit_report.items()) report[key] = value;
    } else {
      report["reached_target"] = fit->reached_target();
      nlohmann::ordered_json parts = nlohmann::ordered_json::array();
      for (const PartFit& part : fit->parts) parts.push_back(PartJson(part));
      report["parts"] = std::move(parts);
    }
    written = WriteTextOutput(args.Get("json"), report.dump(2) + "\n");
    if (!written.ok()) return ReportError(written);
  }
  const PartFit* plotted = nullptr;  // the first fitted part
  for (const PartFit& part : fit->parts) {
    if (!part.kept()) {
      plotted = &part;
      break;
    }
  }
  if (args.Has("plot") && plotted != nullptr) {
    // The first fitted part's rounds (the plot is of one fit).
    written = WriteConvergencePlot(
        plotted->fit.model.statistics,
        file_name + ", degree " + std::to_string(options.degree) +
            (one_part ? ""
                      : ", part " + std::to_string(plotted->report.number)),
        args.Get("plot"));
    if (!written.ok()) return ReportError(written);
  }
  if (!args.Has("quiet") && args.Get("json") != "-") {
    if (one_part && fit->parts[0].kept()) {
      std::printf("%s -> %s: 1 part\n", path.c_str(), output.c_str());
      PrintKeptPartLine(fit->parts[0]);
    } else if (one_part) {
      PrintFitSummary(path, output, options, fit->parts[0].fit,
                      mesh->num_vertices(), quantization);
      PrintOpenPartLine(fit->parts[0]);
    } else {
      PrintPartsSummary(path, output, *fit);
    }
  }
  for (const PartFit& part : fit->parts) {
    if (part.kept() || part.fit.reached_target()) continue;
    // Where a returned surface folds, the measurement's picture shows it.
    const std::string where =
        part.fit.model.statistics.final_result.folded_area_percent > 0
            ? "; `sdcb compare " + output + " " + path +
                  " --picture folds.ply` shows where (blue)"
            : "";
    const std::string which =
        one_part ? "" : "part " + std::to_string(part.report.number) + ": ";
    std::fprintf(
        stderr,
        "sdcb: %s: warning: %sthe targets (rmse %.4f%%, max %.4f%%) were not "
        "reached: %s%s\n",
        path.c_str(), which.c_str(), options.rmse_percent,
        MaxErrorTarget(options), part.fit.shortfall.c_str(), where.c_str());
  }
  return kExitOk;
}

}  // namespace sdcb::cli
