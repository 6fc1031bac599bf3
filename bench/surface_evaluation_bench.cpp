// Evaluated surface points per second per core: the reference evaluator
// (SphericalSpline::Evaluate) against the per-piece polynomials
// (PiecewiseSurface), one thread, random directions.
//   surface_evaluation_bench [MODEL.sdcb]   (default out/bunny00.sdcb)
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>

#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/io/sdcb_file.h"
#include "testing/spline_model_fixture.h"

using Clock = std::chrono::steady_clock;
static double Seconds(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

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
  Clock::time_point t = Clock::now();
  double sink = 0;
  for (Eigen::Index r = 0; r < few.rows(); ++r) {
    sink += spline->Evaluate(few.row(r).transpose())[0];
  }
  const double reference = Seconds(t) / few.rows();
  std::printf(
      "reference evaluator : %8.3f us/point  %8.3f M points/s per core\n",
      reference * 1e6, 1e-6 / reference);
  t = Clock::now();
  const sdcb::PiecewiseSurface pieces(*spline);
  std::printf("piecewise build     : %8.3f s (grid %d)\n", Seconds(t),
              pieces.grid());
  const Eigen::MatrixX3d many = sdcb::testing::RandomUnitVectors(2000000, 2);
  Eigen::MatrixX3d out, normals;
  t = Clock::now();
  pieces.EvaluateMany(many, &out, nullptr);
  std::printf(
      "piecewise first pass: %8.3f s for %lld points (builds %lld regions)\n",
      Seconds(t), static_cast<long long>(many.rows()),
      static_cast<long long>(pieces.num_regions()));
  t = Clock::now();
  pieces.EvaluateMany(many, &out, nullptr);
  const double fast = Seconds(t) / many.rows();
  std::printf(
      "piecewise positions : %8.3f us/point  %8.3f M points/s per core\n",
      fast * 1e6, 1e-6 / fast);
  t = Clock::now();
  pieces.EvaluateMany(many, &out, &normals);
  const double with_normals = Seconds(t) / many.rows();
  std::printf(
      "piecewise + normals : %8.3f us/point  %8.3f M points/s per core\n",
      with_normals * 1e6, 1e-6 / with_normals);
  return sink == 12345.678 ? 1 : 0;
}
