// Evaluated surface points per second per core: the reference evaluator
// (SphericalSpline::Evaluate) against the per-piece polynomials
// (PiecewiseSurface), one thread, random directions. Wall and CPU seconds
// are both printed (on a shared machine the CPU time is the per-core cost).
// The first pass over the points builds every region they touch; its CPU
// time minus the second pass's, per region built, is the cost of building
// a region.
//   surface_evaluation_bench [MODEL.sdcb [GRID [first]]]   (default
//   out/bunny00.sdcb; GRID: cells per cube-face side, 0 = PiecewiseSurface's
//   choice; "first": stop after the first pass, for profiling it)
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/io/sdcb_file.h"
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
  timer = Timer();
  const sdcb::PiecewiseSurface pieces(*spline,
                                      argc > 2 ? std::atoi(argv[2]) : 0);
  std::printf("piecewise build     : %8.3f s (CPU %.3f s), grid %d\n",
              timer.Wall(), timer.Cpu(), pieces.grid());
  const Eigen::MatrixX3d many = sdcb::testing::RandomUnitVectors(2000000, 2);
  Eigen::MatrixX3d out, normals;
  timer = Timer();
  pieces.EvaluateMany(many, &out, nullptr);
  const double first_cpu = timer.Cpu();
  const int64_t regions = pieces.num_regions();
  std::printf(
      "piecewise first pass: %8.3f s (CPU %.3f s) for %lld points, builds "
      "%lld regions\n",
      timer.Wall(), first_cpu, static_cast<long long>(many.rows()),
      static_cast<long long>(regions));
  if (argc > 3 && std::string(argv[3]) == "first") return 0;
  timer = Timer();
  pieces.EvaluateMany(many, &out, nullptr);
  PrintRate("piecewise positions", timer, many.rows());
  std::printf("region building     : %8.3f us CPU per region\n",
              1e6 * (first_cpu - timer.Cpu()) / std::max<int64_t>(1, regions));
  timer = Timer();
  pieces.EvaluateMany(many, &out, &normals);
  PrintRate("piecewise + normals", timer, many.rows());
  // Agreement with the reference on the first sample.
  pieces.EvaluateMany(few, &out, nullptr);
  double worst = 0.0;
  for (Eigen::Index r = 0; r < few.rows(); ++r) {
    worst = std::max(worst, (out.row(r) - reference.row(r)).norm() /
                                std::max(1.0, reference.row(r).norm()));
  }
  std::printf("max relative deviation from the reference: %.3g (%lld points)\n",
              worst, static_cast<long long>(few.rows()));
  return 0;
}
