// The tangent-continuous CAD network (converters/cad_network.h) on a model,
// round by round:
//
//   cad_network_bench MODEL.sdcb [TOLERANCE_PERCENT] [SMOOTHNESS_DEGREES]
//                     [MAX_CONTROL_POINTS] [TANGENT_WEIGHT] [FACE_GRID]
//                     [INITIAL_SPANS]
//
// Prints, per round, the knot cells of all faces, the free poles, the tangent
// rows' weight, the sampled max and rms parametric distance to the spline
// (percent of the model's normalized frame), the largest normal jump across the
// six faces' edges and the largest angle between a face's normal and the
// spline's, and the seconds; then the outcome and the STEP size a pole costs
// (about 110 bytes).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sdcb/converters/cad_network.h"
#include "sdcb/io/sdcb_file.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: cad_network_bench MODEL.sdcb [TOLERANCE_PERCENT] "
                 "[SMOOTHNESS_DEGREES] [MAX_CONTROL_POINTS] "
                 "[TANGENT_WEIGHT] [FACE_GRID] [INITIAL_SPANS]\n");
    return 2;
  }
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) {
    std::fprintf(stderr, "%s\n", model.status().message().c_str());
    return 1;
  }
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) {
    std::fprintf(stderr, "%s\n", spline.status().message().c_str());
    return 1;
  }
  sdcb::CadNetworkOptions options;
  if (argc > 2) options.tolerance_percent = std::atof(argv[2]);
  if (argc > 3) options.smoothness_degrees = std::atof(argv[3]);
  if (argc > 4) options.max_control_points = std::atoi(argv[4]);
  if (argc > 5) options.tangent_weight = std::atof(argv[5]);
  if (argc > 6) options.face_grid = std::atoi(argv[6]);
  if (argc > 7) options.initial_spans = std::atoi(argv[7]);
  auto net = sdcb::FitCadNetwork(*spline, options);
  if (!net.ok()) {
    std::fprintf(stderr, "%s\n", net.status().message().c_str());
    return 1;
  }
  std::printf(
      "round  knot cells    poles  weight    max %%     rms %%  jump deg  "
      "angle deg  folded  seconds\n");
  for (size_t r = 0; r < net->history.size(); ++r) {
    const sdcb::CadNetwork::Round& h = net->history[r];
    std::printf(
        "%5zu  %10d  %7d  %6.3g  %8.4g  %8.4g  %8.3g  %9.3g  %6lld  "
        "%7.2f\n",
        r + 1, h.knot_cells, h.control_points, h.tangent_weight,
        h.max_distance_percent, h.rms_distance_percent,
        h.max_normal_jump_degrees, h.max_normal_angle_degrees,
        static_cast<long long>(h.folded_points), h.seconds);
  }
  std::printf(
      "%s: %zu faces, %s after %d rounds, %d poles (~%.1f MB of STEP at ~110 B "
      "per "
      "pole), max %.4g %%, jump %.3g deg; fit %.2f s, measure %.2f s\n",
      argv[1], net->faces.size(),
      net->within_tolerance ? "met" : net->stop_reason.c_str(), net->rounds,
      net->control_points, net->control_points * 110e-6,
      net->max_distance_percent, net->max_normal_jump_degrees, net->fit_seconds,
      net->measure_seconds);
  return 0;
}
