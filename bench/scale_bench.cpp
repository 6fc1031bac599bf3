// Time and peak memory of every stage of a fit, for meshes of growing size,
// and the exponent of time against the vertex count (least squares on
// log t = a + b log n). Inputs: bench/scale_meshes (bunny00 refined to
// 108K .. 3.9M vertices) or any closed genus-0 meshes.
//   scale_bench [--rmse PCT] [--threads T] [--max-rounds R] MESH...
// Stages: "intake" (read + closed genus-0 check), then the fitter's stages
// as its progress callback reports them (core/fit/spline_fitter.h:
// parameterization, knot placement, configurations, basis = sampling and
// basis evaluation, solve = assembly of the normal equations and the sparse
// solve, measure = the dense two-sided error), summed over the rounds.
// CPU: user + system seconds of all threads (getrusage), which a loaded
// machine does not inflate as it does wall time.
// Peak memory: the process's peak resident set (VmHWM) during the stage,
// reset at each stage start (/proc/self/clear_refs); all meshes run in one
// process, freed memory returned between them (malloc_trim).
#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "tools/allocator_tuning.h"

namespace {

using Clock = std::chrono::steady_clock;

double PeakMb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024;
  }
  return 0;
}

void ResetPeak() { std::ofstream("/proc/self/clear_refs") << "5"; }

// User + system CPU seconds of the process (all threads).
double CpuSeconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec +
         1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Per-stage wall time and peak memory, fed by stage transitions.
class StageClock {
 public:
  void Enter(const std::string& stage) {
    Leave();
    current_ = stage;
    start_ = Clock::now();
    cpu_start_ = CpuSeconds();
    ResetPeak();
    if (std::find(order_.begin(), order_.end(), stage) == order_.end()) {
      order_.push_back(stage);
    }
  }
  void Leave() {
    if (current_.empty()) return;
    const double wall =
        std::chrono::duration<double>(Clock::now() - start_).count();
    const double cpu = CpuSeconds() - cpu_start_;
    seconds_[current_] += wall;
    cpu_seconds_[current_] += cpu;
    peak_mb_[current_] = std::max(peak_mb_[current_], PeakMb());
    // Live, on stderr: a long run shows where it is.
    std::fprintf(stderr, "  [%s: %.2f s wall, %.2f s cpu, %.0f MB]\n",
                 current_.c_str(), wall, cpu, PeakMb());
    current_.clear();
  }
  const std::vector<std::string>& order() const { return order_; }
  double seconds(const std::string& s) const { return Get(seconds_, s); }
  double peak_mb(const std::string& s) const { return Get(peak_mb_, s); }
  double cpu_seconds(const std::string& s) const {
    return Get(cpu_seconds_, s);
  }

 private:
  static double Get(const std::map<std::string, double>& m,
                    const std::string& s) {
    auto it = m.find(s);
    return it == m.end() ? 0.0 : it->second;
  }
  std::string current_;
  Clock::time_point start_;
  double cpu_start_ = 0;
  std::vector<std::string> order_;
  std::map<std::string, double> seconds_, cpu_seconds_, peak_mb_;
};

// Slope b of log y = a + b log x (least squares).
double Exponent(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(std::max(y[i], 1e-6));
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

int main(int argc, char** argv) {
  sdcb::cli::TuneAllocatorForRounds();       // as the sdcb command does
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // lines appear as stages end
  sdcb::FitOptions options;
  options.rmse_percent = 0.1;
  std::vector<std::string> meshes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--rmse" && i + 1 < argc) {
      options.rmse_percent = std::atof(argv[++i]);
    } else if (a == "--threads" && i + 1 < argc) {
      options.threads = std::atoi(argv[++i]);
    } else if (a == "--max-rounds" && i + 1 < argc) {
      options.max_rounds = std::atoi(argv[++i]);
    } else {
      meshes.push_back(a);
    }
  }
  if (meshes.empty()) {
    std::fprintf(stderr,
                 "usage: scale_bench [--rmse PCT] [--threads T] "
                 "[--max-rounds R] MESH...\n");
    return 2;
  }
  std::printf("target rmse %.3g %%, degree %d, threads %d (0 = all)\n",
              options.rmse_percent, options.degree, options.threads);
  std::vector<double> vertices, totals, total_cpus;
  std::map<std::string, std::vector<double>> stage_seconds, stage_cpu;
  std::vector<std::string> stage_order;
  for (const std::string& path : meshes) {
    malloc_trim(0);
    StageClock clock;
    const Clock::time_point start = Clock::now();
    clock.Enter("intake");
    auto mesh = sdcb::ReadMesh(path);
    if (!mesh.ok()) {
      std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
      return 1;
    }
    const sdcb::Status closed = sdcb::RequireClosedGenusZero(*mesh);
    if (!closed.ok()) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(), closed.message().c_str());
      return 1;
    }
    options.progress = [&clock](const sdcb::FitProgress& p) {
      clock.Enter(sdcb::FitStageName(p.stage));
    };
    auto fit = sdcb::FitSphericalSpline(*mesh, options);
    clock.Leave();
    const double total =
        std::chrono::duration<double>(Clock::now() - start).count();
    if (!fit.ok()) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(),
                   fit.status().message().c_str());
      return 1;
    }
    const auto& f = fit->model.statistics.final_result;
    std::printf(
        "\n%s: %d vertices: %.1f s, rmse %.4f %% (max %.3f %%), %d control "
        "points, %zu rounds, target %s\n",
        path.c_str(), mesh->num_vertices(), total, f.rmse_percent,
        f.max_error_percent, f.control_points,
        fit->model.statistics.rounds.size(),
        fit->reached_target() ? "reached" : "NOT reached");
    std::printf("  %-18s %10s %10s %12s\n", "stage", "seconds", "cpu s",
                "peak MB");
    double overall_peak = 0, total_cpu = 0;
    for (const std::string& s : clock.order()) {
      if (s == "done") continue;
      std::printf("  %-18s %10.2f %10.2f %12.0f\n", s.c_str(), clock.seconds(s),
                  clock.cpu_seconds(s), clock.peak_mb(s));
      total_cpu += clock.cpu_seconds(s);
      overall_peak = std::max(overall_peak, clock.peak_mb(s));
      if (std::find(stage_order.begin(), stage_order.end(), s) ==
          stage_order.end()) {
        stage_order.push_back(s);
      }
      stage_seconds[s].resize(vertices.size(), 0.0);
      stage_seconds[s].push_back(clock.seconds(s));
      stage_cpu[s].resize(vertices.size(), 0.0);
      stage_cpu[s].push_back(clock.cpu_seconds(s));
    }
    std::printf("  %-18s %10.2f %10.2f %12.0f\n", "total", total, total_cpu,
                overall_peak);
    vertices.push_back(mesh->num_vertices());
    totals.push_back(total);
    total_cpus.push_back(total_cpu);
  }
  if (vertices.size() >= 2) {
    std::printf(
        "\nexponent b of time ~ n^b over %.0f .. %.0f vertices (wall, cpu):\n",
        vertices.front(), vertices.back());
    for (const std::string& s : stage_order) {
      std::vector<double> t = stage_seconds[s], c = stage_cpu[s];
      t.resize(vertices.size(), 0.0);
      c.resize(vertices.size(), 0.0);
      std::printf("  %-18s %6.2f %6.2f\n", s.c_str(), Exponent(vertices, t),
                  Exponent(vertices, c));
    }
    std::printf("  %-18s %6.2f %6.2f\n", "total", Exponent(vertices, totals),
                Exponent(vertices, total_cpus));
  }
  return 0;
}
