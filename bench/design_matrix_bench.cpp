// Design-matrix assembly time (issue 5): 37,000 points (the bunny's vertex
// count), degree 4, about 5,000 basis functions. Prints numbers; never run
// by CI. Usage: design_matrix_bench [knots=1000] [points=37000] [degree=4]
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/design_matrix.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "testing/random_sphere_points.h"

namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since)
      .count();
}

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  const int num_points = argc > 2 ? std::atoi(argv[2]) : 37000;
  const int degree = argc > 3 ? std::atoi(argv[3]) : 4;
  const Eigen::MatrixX3d knots = sdcb::testing::FibonacciPoints(n, 1);
  const Eigen::MatrixX3d points =
      sdcb::testing::RandomUnitVectors(num_points, 7);

  auto t0 = std::chrono::steady_clock::now();
  auto configurations = sdcb::ComputeDelaunayConfigurations(knots, degree);
  if (!configurations.ok()) {
    std::fprintf(stderr, "%s\n", configurations.status().message().c_str());
    return 1;
  }
  const double t_config = Seconds(t0);
  t0 = std::chrono::steady_clock::now();
  auto basis = sdcb::DcbBasis::Create(knots, *configurations);
  if (!basis.ok()) {
    std::fprintf(stderr, "%s\n", basis.status().message().c_str());
    return 1;
  }
  const double t_basis = Seconds(t0);
  std::printf("knots %d, degree %d, basis functions %d, points %d\n", n, degree,
              basis->size(), num_points);
  double nodes = 0;
  for (int i = 0; i < basis->size(); ++i) {
    nodes += basis->simplex_spline(i).num_nodes();
  }
  std::printf(
      "configurations (stand-in) %.3f s, basis setup %.3f s, %.1f memoized "
      "subsets per simplex spline\n",
      t_config, t_basis, nodes / basis->size());
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              threads);
    double best = 1e9;
    sdcb::DesignMatrix a;
    double best_cpu = 1e9;
    for (int rep = 0; rep < 3; ++rep) {
      t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      a = sdcb::BuildDesignMatrix(*basis, points);
      const double t = Seconds(t0);
      best_cpu = std::min(best_cpu, double(std::clock() - c0) / CLOCKS_PER_SEC);
      if (t < best) best = t;
    }
    std::printf("threads %d: assembly CPU time %.3f s (best of 3)\n", threads,
                best_cpu);
    {
      double normal_cpu = 1e9;
      for (int rep = 0; rep < 3; ++rep) {
        const std::clock_t c0 = std::clock();
        const auto normal = sdcb::NormalMatrixLower(a);
        normal_cpu =
            std::min(normal_cpu, double(std::clock() - c0) / CLOCKS_PER_SEC);
      }
      std::printf("threads %d: normal matrix CPU time %.3f s (best of 3)\n",
                  threads, normal_cpu);
    }
    std::vector<int> candidates;
    long total_candidates = 0;
    for (int r = 0; r < num_points; ++r) {
      basis->Candidates(points.row(r).transpose(), &candidates);
      total_candidates += candidates.size();
    }
    std::printf(
        "threads %d: assembly %.3f s (best of 3), nonzeros %ld (%.1f per row), "
        "%.1f cap candidates per row, %.3f us per nonzero basis evaluation "
        "(thread-seconds)\n",
        threads, best, static_cast<long>(a.nonZeros()),
        double(a.nonZeros()) / num_points,
        double(total_candidates) / num_points,
        1e6 * best * threads / a.nonZeros());
  }
  // Surface evaluation with derivatives and curvature at every point.
  Eigen::MatrixX3d control(basis->size(), 3);
  for (int i = 0; i < basis->size(); ++i) {
    control.row(i) = knots.row(configurations->sets[i].knots[0]);
  }
  auto spline =
      sdcb::SphericalSpline::Create(std::move(basis).value(), control);
  if (!spline.ok()) return 1;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              threads);
    t0 = std::chrono::steady_clock::now();
    const Eigen::MatrixX3d f = spline->EvaluateMany(points);
    const double t_position = Seconds(t0);
    t0 = std::chrono::steady_clock::now();
    const auto d = spline->EvaluateDifferentialMany(points);
    const double t_curvature = Seconds(t0);
    std::printf(
        "threads %d: positions %.3f s (%.2f us/point), with derivatives and "
        "curvatures %.3f s (%.2f us/point)\n",
        threads, t_position, 1e6 * t_position / num_points, t_curvature,
        1e6 * t_curvature / num_points);
  }
  return 0;
}
