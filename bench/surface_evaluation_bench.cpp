// Evaluated surface points per second per core: the reference evaluator
// (SphericalSpline::Evaluate) against the per-piece polynomials
// (PiecewiseSurface), one thread, random directions; then curvature through
// PiecewiseSplineSampler and shapes (PiecewiseSurface::EvaluateShapeMany),
// and the whole-surface curvature quadrature of export
// (IntegrateCurvatureOverSurface, level 6) on a fresh surface and on one
// whose regions are built. Wall and CPU seconds are both printed (on a
// shared machine the CPU time is the per-core cost).
//
// Region building: the first pass over 2 M points builds every region they
// touch; its CPU time minus the second pass's, per region built, is the
// cost of building a region (the output is allocated before either pass).
// Run it in a fresh process: a second surface in the same process reuses the
// first one's freed memory and builds its regions faster than a first one.
//   surface_evaluation_bench [MODEL.sdcb [GRID [regions]]]
// (default out/bunny00.sdcb; GRID: cells per cube-face side, 0 =
// PiecewiseSurface's choice; "regions": stop after the region building, for
// profiling and A/B runs)
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/tessellate/optimal_triangle_count.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/spline_model_fixture.h"

namespace {

// Wall and process CPU seconds since construction.
struct Timer {
  std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
  std::clock_t cpu = std::clock();
  double Wall() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         wall)
        .count();
  }
  double Cpu() const {
    return static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
  }
};

void PrintRate(const char* what, const Timer& timer, Eigen::Index points) {
  const double wall = timer.Wall() / points, cpu = timer.Cpu() / points;
  std::printf(
      "%-20s: %8.3f us/point (CPU %8.3f)  %8.3f M points/s per core (CPU "
      "%8.3f)\n",
      what, wall * 1e6, cpu * 1e6, 1e-6 / wall, 1e-6 / cpu);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "out/bunny00.sdcb";
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  auto model = sdcb::ReadSdcbFile(path);
  if (!model.ok()) {
    std::fprintf(stderr, "%s\n", model.status().message().c_str());
    return 1;
  }
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  std::printf("%s: degree %d, %lld knots, %d basis functions\n", path.c_str(),
              spline->degree(), static_cast<long long>(spline->knots().rows()),
              spline->basis().size());
  const Eigen::MatrixX3d few = sdcb::testing::RandomUnitVectors(20000, 1);
  Eigen::MatrixX3d reference(few.rows(), 3);
  Timer timer;
  for (Eigen::Index r = 0; r < few.rows(); ++r) {
    reference.row(r) = spline->Evaluate(few.row(r).transpose()).transpose();
  }
  PrintRate("reference evaluator", timer, few.rows());
  const int grid = argc > 2 ? std::atoi(argv[2]) : 0;
  const Eigen::MatrixX3d many = sdcb::testing::RandomUnitVectors(2000000, 2);
  Eigen::MatrixX3d out = Eigen::MatrixX3d::Zero(many.rows(), 3), normals;
  timer = Timer();
  const auto pieces = std::make_unique<sdcb::PiecewiseSurface>(*spline, grid);
  std::printf("piecewise build     : %8.3f s (CPU %.3f s), grid %d\n",
              timer.Wall(), timer.Cpu(), pieces->grid());
  timer = Timer();
  pieces->EvaluateMany(many, &out, nullptr);
  const double first_cpu = timer.Cpu();
  const int64_t regions = pieces->num_regions();
  std::printf(
      "piecewise first pass: %8.3f s (CPU %.3f s) for %lld points, builds "
      "%lld regions\n",
      timer.Wall(), first_cpu, static_cast<long long>(many.rows()),
      static_cast<long long>(regions));
  timer = Timer();
  pieces->EvaluateMany(many, &out, nullptr);
  PrintRate("piecewise positions", timer, many.rows());
  std::printf("region building     : %8.3f us CPU per region\n",
              1e6 * (first_cpu - timer.Cpu()) / std::max<int64_t>(1, regions));
  if (argc > 3 && std::string(argv[3]) == "regions") return 0;
  timer = Timer();
  pieces->EvaluateMany(many, &out, &normals);
  PrintRate("piecewise + normals", timer, many.rows());
  {
    // Curvature as the tessellator asks for it.
    const sdcb::PiecewiseSplineSampler sampler(*spline, *pieces);
    const Eigen::MatrixX3d some = many.topRows(100000);
    Eigen::VectorXd gaussian, mean;
    timer = Timer();
    sampler.SampleCurvature(some, &gaussian, &mean);
    PrintRate("sampler curvature", timer, some.rows());
    std::vector<sdcb::SurfaceShape> shapes;
    timer = Timer();
    pieces->EvaluateShapeMany(some, &shapes);
    PrintRate("piecewise shapes", timer, some.rows());
    timer = Timer();
    auto warm = sdcb::IntegrateCurvatureOverSurface(sampler, 6);
    std::printf("quadrature, built   : %8.3f s (CPU %.3f s)\n", timer.Wall(),
                timer.Cpu());
    timer = Timer();
    const sdcb::PiecewiseSurface fresh(*spline, grid);
    const sdcb::PiecewiseSplineSampler cold_sampler(*spline, fresh);
    auto cold = sdcb::IntegrateCurvatureOverSurface(cold_sampler, 6);
    std::printf(
        "quadrature, fresh   : %8.3f s (CPU %.3f s) with the surface's "
        "construction; %lld regions built\n",
        timer.Wall(), timer.Cpu(), static_cast<long long>(fresh.num_regions()));
    if (warm.ok() && cold.ok()) {
      std::printf("  integrals: convex %.9g saddle %.9g area %.9g\n",
                  cold->convex, cold->saddle, cold->area);
    }
  }
  // Agreement with the reference on the first sample.
  pieces->EvaluateMany(few, &out, nullptr);
  double worst = 0.0;
  for (Eigen::Index r = 0; r < few.rows(); ++r) {
    worst = std::max(worst, (out.row(r) - reference.row(r)).norm() /
                                std::max(1.0, reference.row(r).norm()));
  }
  std::printf("max relative deviation from the reference: %.3g (%lld points)\n",
              worst, static_cast<long long>(few.rows()));
  return 0;
}
