// Fits sample meshes and prints per-round statistics and per-stage times.
//   fit_bench [MESH [DEGREE [RMSE_PERCENT [KNOTS_PER_ROUND [MAX_ROUNDS]]]]]
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/io/mesh_reader.h"

int main(int argc, char** argv) {
  const std::string path =
      argc > 1 ? argv[1] : std::string(SDCB_MESH_DIR) + "/bunny00.off";
  sdcb::FitOptions options;
  if (argc > 2) options.degree = std::atoi(argv[2]);
  if (argc > 3) options.rmse_percent = std::atof(argv[3]);
  if (argc > 4) options.knots_per_round = std::atoi(argv[4]);
  if (argc > 5) options.max_rounds = std::atoi(argv[5]);
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
  std::printf("%s: %d vertices, degree %d, target rmse %.4f%%\n", path.c_str(),
              mesh->num_vertices(), options.degree, options.rmse_percent);
  std::printf(
      "round  knots  ctrl_pts   rmse%%     max%%  | seconds: knots  configs  "
      "basis   solve   round | cvt energy (iters) | reused basis\n");
  for (size_t i = 0; i < s.rounds.size(); ++i) {
    const auto& r = s.rounds[i];
    const auto& d = fit->round_details[i];
    std::printf(
        "%5d %6d %9d  %.5f  %.5f |        %6.3f  %6.3f  %6.3f  %6.3f  %6.3f | "
        "%.4g -> %.4g (%d) | %d\n",
        r.round, r.knots, r.control_points, r.rmse_percent, r.max_error_percent,
        d.timings.knot_placement, d.timings.configurations, d.timings.basis,
        d.timings.solve, d.timings.total, d.cvt_initial_energy,
        d.cvt_final_energy, d.cvt_iterations, d.reused_basis_functions);
  }
  const auto& t = fit->timings;
  std::printf(
      "timings (s): parameterization %.3f, knot placement %.3f, "
      "configurations %.3f, basis %.3f, solve %.3f, total %.3f\n",
      t.parameterization, t.knot_placement, t.configurations, t.basis, t.solve,
      t.total);
  std::printf("reached target: %s\n", fit->reached_target() ? "yes" : "no");
  return 0;
}
