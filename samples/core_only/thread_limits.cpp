// Sample: a program that sets its own TBB limits and links only sdcb::core.
// The fit runs in its own arena (FitOptions::threads): the program's
// process-wide limit stays what the program set, during and after the fit.
//   thread_limits
#include <sdcb/core/fit/spline_fitter.h>
#include <sdcb/core/mesh/icosphere.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdio>

int main() {
  using tbb::global_control;
  const size_t kProgramLimit = 3;
  global_control limit(global_control::max_allowed_parallelism, kProgramLimit);

  // An ellipsoid: a unit icosphere stretched along x.
  sdcb::TriangleMesh mesh = sdcb::MakeIcosphere(3);
  mesh.vertices.col(0) *= 1.5;
  sdcb::FitOptions options;
  options.threads = 1;
  options.max_rounds = 1;
  options.knots_per_round = 40;
  size_t smallest_limit = kProgramLimit;
  int largest_arena = 0, calls = 0;
  options.progress = [&](const sdcb::FitProgress& p) {
    ++calls;
    smallest_limit = std::min(
        smallest_limit,
        global_control::active_value(global_control::max_allowed_parallelism));
    if (p.stage != sdcb::FitStage::kParameterization &&
        p.stage != sdcb::FitStage::kDone) {
      largest_arena =
          std::max(largest_arena, tbb::this_task_arena::max_concurrency());
    }
  };
  sdcb::StatusOr<sdcb::FitResult> fit = sdcb::FitSphericalSpline(mesh, options);
  if (!fit.ok()) {
    std::fprintf(stderr, "fit failed: %s\n", fit.status().message().c_str());
    return 1;
  }
  const size_t after =
      global_control::active_value(global_control::max_allowed_parallelism);
  std::printf(
      "program limit %zu: smallest seen during the fit %zu, after %zu; the "
      "fit's arena had %d thread(s) (%d progress calls)\n",
      kProgramLimit, smallest_limit, after, largest_arena, calls);
  const bool ok = calls > 0 && smallest_limit == kProgramLimit &&
                  after == kProgramLimit && largest_arena == 1;
  std::printf("%s\n", ok ? "thread limits respected" : "FAILED");
  return ok ? 0 : 1;
}
