// CPU seconds of the fit's inner kernels on one thread, the best of several
// repetitions (so that a shared machine's noise mostly cancels): the basis's
// construction, the design matrix at the mesh's vertices, the spline's
// position at a lattice of directions (in the basis's locality order) and at
// the same number of directions in random order; the least squares' normal
// matrix (the lower triangle of A^T A) of that design matrix.
//   fit_kernels_bench MODEL.sdcb [points=60000] [repetitions=5]
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <limits>

#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/spline/design_matrix.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/sdcb_file.h"
#include "testing/spline_model_fixture.h"

namespace {

double BestCpuSeconds(int repetitions, const std::function<void()>& run) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < repetitions; ++i) {
    const std::clock_t start = std::clock();
    run();
    best = std::min(best,
                    static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(
        stderr, "usage: fit_kernels_bench MODEL.sdcb [points] [repetitions]\n");
    return 2;
  }
  const int points = argc > 2 ? std::atoi(argv[2]) : 60000;
  const int repetitions = argc > 3 ? std::atoi(argv[3]) : 5;
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) {
    std::fprintf(stderr, "%s\n", model.status().message().c_str());
    return 1;
  }
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  std::printf("%s: degree %d, %lld knots, %d basis functions, %d points\n",
              argv[1], spline->degree(),
              static_cast<long long>(spline->knots().rows()),
              spline->basis().size(), points);
  const double create = BestCpuSeconds(repetitions, [&] {
    auto basis = sdcb::DcbBasis::Create(model->knots, model->configurations);
    if (!basis.ok()) std::abort();
  });
  const Eigen::MatrixX3d directions =
      sdcb::testing::RandomUnitVectors(points, 3);
  const double design = BestCpuSeconds(repetitions, [&] {
    const sdcb::DesignMatrix a =
        sdcb::BuildDesignMatrix(spline->basis(), directions);
    if (a.rows() != points) std::abort();
  });
  const sdcb::DesignMatrix a =
      sdcb::BuildDesignMatrix(spline->basis(), directions);
  const double normal = BestCpuSeconds(repetitions, [&] {
    if (sdcb::NormalMatrixLower(a).rows() != a.cols()) std::abort();
  });
  Eigen::MatrixX3d out;
  const double many = BestCpuSeconds(
      repetitions, [&] { out = spline->EvaluateMany(directions); });
  const double single = BestCpuSeconds(repetitions, [&] {
    for (Eigen::Index r = 0; r < directions.rows(); ++r) {
      out.row(r) = spline->Evaluate(directions.row(r).transpose()).transpose();
    }
  });
  std::printf("basis construction        %8.4f s\n", create);
  std::printf("design matrix             %8.4f s\n", design);
  std::printf("normal matrix (A^T A)     %8.4f s\n", normal);
  std::printf("positions, locality order %8.4f s\n", many);
  std::printf("positions, random order   %8.4f s\n", single);
  return 0;
}
