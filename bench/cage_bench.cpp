// What the adaptive cage fit buys, on one model (docs/CAGE.md, "Against the
// obvious alternatives"): for uniform cube-sphere / icosphere cages of
// several levels, the limit surface's two-sided distance to the spline when
// the cage vertices are
//   pulled: the spline at the vertices' sphere points (an interpolating
//           cage, what remeshing the surface and using it as a cage gives),
//   fitted: the least-squares fit of converters/cage/subdivision_cage,
// then the adaptive fit for the same face counts (--faces). Measured at
// >= 100K points each way (converters/cage/cage_deviation).
//   cage_bench MODEL.sdcb [--scheme catmark|loop] [--levels MAX]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sdcb/converters/cage/subdivision_cage.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/io/sdcb/sdcb_file.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: cage_bench MODEL.sdcb [--scheme catmark|loop] "
                 "[--levels MAX]\n");
    return 2;
  }
  sdcb::CageOptions options;
  int max_levels = 4;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scheme" && i + 1 < argc) {
      options.scheme = std::string(argv[++i]) == "loop"
                           ? sdcb::SubdivisionScheme::kLoop
                           : sdcb::SubdivisionScheme::kCatmullClark;
    } else if (a == "--levels" && i + 1 < argc) {
      max_levels = std::atoi(argv[++i]);
    }
  }
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) {
    std::fprintf(stderr, "%s\n", model.status().message().c_str());
    return 1;
  }
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  const sdcb::PiecewiseSurface pieces(*spline);
  const sdcb::PiecewiseSplineSampler sampler(*spline, pieces);
  const bool loop = options.scheme == sdcb::SubdivisionScheme::kLoop;
  std::printf("%s, %s\n", argv[1], loop ? "Loop" : "Catmull-Clark");
  std::printf("%-10s %7s %12s %12s %12s %12s %9s\n", "cage", "faces",
              "pulled rms", "pulled max", "fitted rms", "fitted max",
              "seconds");
  for (int levels = 2; levels <= max_levels; ++levels) {
    const auto start = std::chrono::steady_clock::now();
    const sdcb::SphereCage layout =
        sdcb::SphereCageTopology::Create(
            loop ? sdcb::CageCellShape::kTriangle : sdcb::CageCellShape::kQuad,
            levels)
            .cage();
    auto limit = sdcb::LimitSurface::Create(
        options.scheme, layout.num_vertices(), layout.faces);
    if (!limit.ok()) return 1;
    const Eigen::MatrixX3d pulled = spline->EvaluateMany(layout.sphere_points);
    auto fitted = sdcb::FitCagePositions(sampler, layout, *limit, options);
    if (!fitted.ok()) return 1;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    auto a = sdcb::MeasureCageDeviation(sampler, *limit, pulled, layout);
    auto b = sdcb::MeasureCageDeviation(sampler, *limit, *fitted, layout);
    if (!a.ok() || !b.ok()) return 1;
    std::printf("%-10s %7d %11.4f%% %11.4f%% %11.4f%% %11.4f%% %9.2f\n",
                ("uniform " + std::to_string(levels)).c_str(),
                layout.num_faces(), a->rms_percent, a->max_percent,
                b->rms_percent, b->max_percent, seconds);
    // The adaptive fit with the same face budget.
    options.max_faces = layout.num_faces();
    options.tolerance_percent = 1e-6;
    auto adaptive = sdcb::FitSubdivisionCage(*spline, options);
    if (!adaptive.ok()) return 1;
    std::printf("%-10s %7d %12s %12s %11.4f%% %11.4f%% %9.2f\n", "adaptive",
                adaptive->cage.layout.num_faces(), "", "",
                adaptive->deviation.rms_percent,
                adaptive->deviation.max_percent, adaptive->seconds);
    std::fflush(stdout);
  }
  return 0;
}
