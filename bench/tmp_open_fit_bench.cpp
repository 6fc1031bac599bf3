#include <cstdio>
#include "sdcb/core/fit/fit_model.h"
#include "sdcb/core/common/stopwatch.h"
#include "sdcb/io/mesh/mesh_reader.h"
int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    auto mesh = sdcb::ReadMesh(argv[i]);
    if (!mesh.ok()) { std::printf("%s: %s\n", argv[i], mesh.status().message().c_str()); continue; }
    sdcb::ModelFitOptions o; o.fit.rmse_percent = 0.1;
    sdcb::Stopwatch clock;
    auto fit = sdcb::FitModel(*mesh, o);
    if (!fit.ok()) { std::printf("%s: %s (%.1f s)\n", argv[i], fit.status().message().c_str(), clock.Seconds()); continue; }
    int cps = 0, reached = 0; double worst_h = 0, worst_rms = 0, folded = 0;
    for (auto& p : fit->parts) { auto& f = p.fit.model.statistics.final_result; cps += f.control_points; reached += p.fit.reached_target();
      worst_h = std::max(worst_h, f.max_error_percent); worst_rms = std::max(worst_rms, f.rmse_percent); folded = std::max(folded, f.folded_area_percent);}
    std::printf("%s: parts %zu reached %d cps %d rms %.4f H %.4f folded %.3f %.1f s %s\n", argv[i], fit->parts.size(), reached, cps, worst_rms, worst_h, folded, clock.Seconds(),
       fit->parts[0].fit.shortfall.substr(0,200).c_str());
    std::fflush(stdout);
  }
}
