// Re-reads a STEP / IGES file written by `sdcb export` with OpenCASCADE's
// readers and compares it with the model's spline, as the CAD tests do
// (tests/testing/occt_reread.h), for models too large for CI:
//
//   cad_reread_bench MODEL.sdcb OUT.step|OUT.igs [SURFACE_POINTS]
//
// Prints solids, shells, free edges, validity, faces, volume and area
// against the spline's uniform tessellation, and the distances both ways
// (tests/converters/cad_reread_oracle.h)
// (percent of the input's largest bounding-box side): at SURFACE_POINTS
// (default 100000) points of the re-read surfaces, and from 20000 spline
// points (each an OpenCASCADE projection); and the largest jump of the
// normal across the re-read edges, at 32 points of each (pcurves and
// surface derivatives of the re-read faces).
#include <chrono>
#include <cstdio>
#include <string>

#include "converters/cad_reread_oracle.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/occt_reread.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: cad_reread_bench MODEL.sdcb OUT.step|OUT.igs "
                 "[SURFACE_POINTS]\n");
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) return 1;
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  const std::string path = argv[2];
  const bool iges =
      path.size() > 4 && (path.substr(path.size() - 4) == ".igs" ||
                          path.substr(path.size() - 5) == ".iges");
  const int64_t points = argc > 3 ? std::stoll(argv[3]) : 100000;
  const sdcb::testing::RereadShape r = sdcb::testing::Reread(path, iges);
  if (!r.read) {
    std::fprintf(stderr, "%s: OpenCASCADE could not read it\n", path.c_str());
    return 1;
  }
  const sdcb::testing::RereadComparison c =
      sdcb::testing::CompareRereadWithSpline(r, *spline, points, 20000,
                                             model->transform, /*level=*/8);
  const sdcb::testing::NormalJumps jumps =
      sdcb::testing::MeasureNormalJumps(r, 32);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  std::printf(
      "%s: solids %d shells %d free_edges %d valid %d faces %d\n"
      "  volume %.9g (spline %.9g, rel %.2e)  area %.9g (spline %.9g, rel "
      "%.2e)\n"
      "  re-read -> spline max %.5f%% at %lld points; spline -> re-read max "
      "%.5f%% at %lld points\n"
      "  normal jump across %d edges max %.4f deg at %lld points  %.1f s\n",
      path.c_str(), r.solids, r.shells, r.free_edges, r.valid ? 1 : 0, r.faces,
      r.volume, c.spline_volume, r.volume / c.spline_volume - 1.0, r.area,
      c.spline_area, r.area / c.spline_area - 1.0, c.to_spline_percent,
      static_cast<long long>(c.surface_points), c.from_spline_percent,
      static_cast<long long>(c.spline_points), jumps.edges, jumps.max_degrees,
      static_cast<long long>(jumps.points), seconds);
  return c.ok && r.solids == 1 && r.free_edges == 0 && r.valid ? 0 : 1;
}
