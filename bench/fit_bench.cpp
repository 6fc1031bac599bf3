// Fits a mesh and prints per-round statistics (honest two-sided errors and
// the paper's vertex errors) and per-stage times.
//   fit_bench MESH [--degree K] [--rmse PCT] [--knots-per-round N]
//             [--max-rounds R] [--raw] [--fairness F] [--samples S]
//             [--lambda L] [--threads T] [--initial-knots N]
//             [--max-control-points M] [-o MODEL.sdcb]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/allocator_tuning.h"

int main(int argc, char** argv) {
  sdcb::cli::TuneAllocatorForRounds();  // as the sdcb command does
  std::string path = std::string(SDCB_MESH_DIR) + "/bunny00.off";
  sdcb::FitOptions options;
  std::string output;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? argv[++i] : "0"; };
    if (a == "--degree") {
      options.degree = std::atoi(next());
    } else if (a == "--rmse") {
      options.rmse_percent = std::atof(next());
    } else if (a == "--knots-per-round") {
      options.knots_per_round = std::atoi(next());
    } else if (a == "--initial-knots") {
      options.initial_knots = std::atoi(next());
    } else if (a == "--max-rounds") {
      options.max_rounds = std::atoi(next());
    } else if (a == "--max-control-points") {
      options.max_control_points = std::atoi(next());
    } else if (a == "--raw") {
      options.basis_form = sdcb::BasisForm::kRaw;
    } else if (a == "--fairness") {
      options.fairness = std::atof(next());
    } else if (a == "--lambda") {
      options.lambda = std::atof(next());
    } else if (a == "--samples") {
      options.samples_per_spacing = std::atof(next());
    } else if (a == "-o") {
      output = next();
    } else if (a == "--threads") {
      options.threads = std::atoi(next());
    } else {
      path = a;
    }
  }
  auto mesh = sdcb::ReadMesh(path);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
    return 1;
  }
  auto fit = sdcb::FitSphericalSpline(*mesh, options);
  if (!fit.ok()) {
    std::fprintf(stderr, "%s\n", fit.status().message().c_str());
    return 1;
  }
  const auto& s = fit->model.statistics;
  std::printf(
      "%s: %d vertices, degree %d, %s basis, fairness %g, samples/spacing "
      "%g, target rmse %.4f%%\n",
      path.c_str(), mesh->num_vertices(), options.degree,
      options.basis_form == sdcb::BasisForm::kRaw ? "raw" : "normalized",
      options.fairness, options.samples_per_spacing, options.rmse_percent);
  std::printf(
      "round knots ctrl  | rms%%     max%%     fold%% | vrms%%    vmax%%   | "
      "rows   split minS minV | s: knots  conf  basis  solve measure "
      "round\n");
  for (size_t i = 0; i < s.rounds.size(); ++i) {
    const auto& r = s.rounds[i];
    const auto& d = fit->round_details[i];
    std::printf(
        "%4d %5d %5d | %.5f %.5f %.4f | %.5f %.5f | %6d %5d %4d %4d%s | "
        "%6.3f %5.3f %6.3f %6.3f %6.3f %6.3f\n",
        r.round, r.knots, r.control_points, r.rmse_percent, r.max_error_percent,
        r.folded_area_percent, r.vertex_rmse_percent,
        r.vertex_max_error_percent, d.data_samples, d.split_triangles,
        d.min_samples_per_basis, d.min_vertices_per_basis,
        d.closest_points ? "*" : " ", d.timings.knot_placement,
        d.timings.configurations, d.timings.basis, d.timings.solve,
        d.timings.measure, d.timings.total);
  }
  const auto& f = s.final_result;
  const auto& t = fit->timings;
  std::printf(
      "final: %d control points, rms %.5f%%, max %.5f%%, folded %.4f%%, "
      "vertex rms %.5f%% max %.5f%%, reached %s%s%s\n",
      f.control_points, f.rmse_percent, f.max_error_percent,
      f.folded_area_percent, f.vertex_rmse_percent, f.vertex_max_error_percent,
      fit->reached_target() ? "yes" : "no", fit->shortfall.empty() ? "" : ": ",
      fit->shortfall.c_str());
  std::printf(
      "timings (s): parameterization %.3f, knot placement %.3f, "
      "configurations %.3f, basis %.3f, solve %.3f, measure %.3f, total "
      "%.3f\n",
      t.parameterization, t.knot_placement, t.configurations, t.basis, t.solve,
      t.measure, t.total);
  if (!output.empty()) {
    const sdcb::Status w = sdcb::WriteSdcbFile(fit->model, output);
    if (!w.ok()) std::fprintf(stderr, "%s\n", w.message().c_str());
  }
  return 0;
}
