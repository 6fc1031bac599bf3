// Prints the time of ComputeDelaunayConfigurations for uniform random knots
// (fixed seed) at n = 1,000 / 5,000 / 20,000 and degrees 3, 4, 5, plus a
// clustered set (90 % of the knots in a 10-degree cap). Target (issue 4):
// <= 50 ms for 1,000 knots at degree 5, growth close to n log n.
// Usage: delaunay_configurations_bench [repetitions] [threads]
// (threads: run inside a TBB arena of that many threads; default: all).
#include <tbb/task_arena.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>

#include "sdcb/core/spline/delaunay_configurations.h"
#include "testing/random_knots.h"

namespace {

using sdcb::testing::ClusteredKnots;
using sdcb::testing::UniformKnots;

// Best of `reps` wall-clock times in milliseconds; *cpu_ms: process CPU
// time (all threads) of that run, which other load on the machine does not
// inflate.
double TimeMs(const Eigen::MatrixX3d& knots, int degree, int reps, long* sets,
              double* cpu_ms) {
  double best = 1e300;
  for (int r = 0; r < reps; ++r) {
    sdcb::DelaunayConfigurationStats stats;
    const std::clock_t cpu_start = std::clock();
    const auto start = std::chrono::steady_clock::now();
    const auto result = sdcb::ComputeDelaunayConfigurations(
        knots, degree, sdcb::DelaunayConfigurationOptions(), &stats);
    const auto end = std::chrono::steady_clock::now();
    const double cpu = 1000.0 * (std::clock() - cpu_start) / CLOCKS_PER_SEC;
    if (!result.ok()) {
      std::fprintf(stderr, "failed: %s\n", result.status().message().c_str());
      std::exit(1);
    }
    *sets = static_cast<long>(result->sets.size());
    const double ms =
        std::chrono::duration<double, std::milli>(end - start).count();
    if (ms < best) {
      best = ms;
      *cpu_ms = cpu;
    }
  }
  return best;
}

void Run(int reps) {
  std::printf("%-10s %7s %6s %10s %10s %10s %14s\n", "knots", "n", "degree",
              "wall_ms", "cpu_ms", "sets", "ns/(n log2 n)");
  // uniform; clustered: 90 % in a 10-degree cap; crowded: all in a
  // 30-degree cap.
  for (const char* kind : {"uniform", "clustered", "crowded"}) {
    for (int n : {1000, 5000, 20000}) {
      const std::string k = kind;
      const Eigen::MatrixX3d knots = k == "uniform" ? UniformKnots(n, 12345)
                                     : k == "clustered"
                                         ? ClusteredKnots(n, 0.9, 10, 12345)
                                         : ClusteredKnots(n, 1.0, 30, 12345);
      for (int degree : {3, 4, 5}) {
        long sets = 0;
        double cpu_ms = 0;
        const double ms = TimeMs(knots, degree, reps, &sets, &cpu_ms);
        std::printf("%-10s %7d %6d %10.1f %10.1f %10ld %14.1f\n", kind, n,
                    degree, ms, cpu_ms, sets, 1e6 * ms / (n * std::log2(n)));
        std::fflush(stdout);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int reps = argc > 1 ? std::atoi(argv[1]) : 3;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 0;
  if (threads > 0) {
    tbb::task_arena arena(threads);
    arena.execute([&] { Run(reps); });
  } else {
    Run(reps);
  }
  return 0;
}
