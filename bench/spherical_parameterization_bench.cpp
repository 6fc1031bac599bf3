// Prints time and the paper's Table-1 metrics of the spherical
// parameterization (Sec. 4.3) for meshes of CGAL's data set.
// Usage: spherical_parameterization_bench [MESH.off ...] [--lambda L ...]
//   [--threads T] [--level-sweeps N] [--finest-sweeps N] [--tolerance R]
//   [--finest-tolerance R] [--large-level-tolerance R]
//   [--lambda-growth G] [--coarse-lambda L] [--rising-levels N]
//   [--level-growth G] [--base-vertices N] [--base-sweeps N]
//   [--active-fraction F] [--verbose]
// Default: bunny00.off at lambda = 0.2, 1 and 10 (the paper's Bunny).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "sdcb/core/param/parameterization_distortion.h"
#include "sdcb/core/param/spherical_parameterization.h"
#include "sdcb/io/mesh/mesh_reader.h"

int main(int argc, char** argv) {
  std::vector<std::string> meshes;
  std::vector<double> lambdas;
  int threads = 0;
  bool verbose = false;
  const sdcb::SphericalParameterizationOptions defaults;
  int level_sweeps = defaults.level_sweeps,
      finest_sweeps = defaults.finest_sweeps,
      large_level_sweeps = defaults.large_level_sweeps;
  double tolerance = defaults.level_tolerance,
         finest_tolerance = defaults.finest_tolerance,
         large_level_tolerance = defaults.large_level_tolerance,
         lambda_growth = defaults.lambda_growth;
  double coarse_lambda = defaults.coarse_lambda;
  int rising_levels = defaults.rising_levels;
  double level_growth = defaults.level_growth;
  int base_vertices = defaults.base_vertices;
  int base_sweeps = defaults.base_sweeps;
  int global_iterations = defaults.global_iterations;
  double active_fraction = defaults.active_fraction;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--lambda" && i + 1 < argc) {
      lambdas.push_back(std::atof(argv[++i]));
    } else if (a == "--level-sweeps" && i + 1 < argc) {
      level_sweeps = std::atoi(argv[++i]);
    } else if (a == "--finest-sweeps" && i + 1 < argc) {
      finest_sweeps = std::atoi(argv[++i]);
    } else if (a == "--finest-tolerance" && i + 1 < argc) {
      finest_tolerance = std::atof(argv[++i]);
    } else if (a == "--large-level-tolerance" && i + 1 < argc) {
      large_level_tolerance = std::atof(argv[++i]);
    } else if (a == "--large-level-sweeps" && i + 1 < argc) {
      large_level_sweeps = std::atoi(argv[++i]);
    } else if (a == "--tolerance" && i + 1 < argc) {
      tolerance = std::atof(argv[++i]);
    } else if (a == "--global-iterations" && i + 1 < argc) {
      global_iterations = std::atoi(argv[++i]);
    } else if (a == "--base-sweeps" && i + 1 < argc) {
      base_sweeps = std::atoi(argv[++i]);
    } else if (a == "--level-growth" && i + 1 < argc) {
      level_growth = std::atof(argv[++i]);
    } else if (a == "--base-vertices" && i + 1 < argc) {
      base_vertices = std::atoi(argv[++i]);
    } else if (a == "--rising-levels" && i + 1 < argc) {
      rising_levels = std::atoi(argv[++i]);
    } else if (a == "--coarse-lambda" && i + 1 < argc) {
      coarse_lambda = std::atof(argv[++i]);
    } else if (a == "--lambda-growth" && i + 1 < argc) {
      lambda_growth = std::atof(argv[++i]);
    } else if (a == "--active-fraction" && i + 1 < argc) {
      active_fraction = std::atof(argv[++i]);
    } else if (a == "--verbose") {
      verbose = true;
    } else if (a == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else {
      meshes.push_back(a.find('/') == std::string::npos
                           ? std::string(SDCB_MESH_DIR) + "/" + a
                           : a);
    }
  }
  if (meshes.empty())
    meshes.push_back(std::string(SDCB_MESH_DIR) + "/bunny00.off");
  if (lambdas.empty()) lambdas = {0.2, 1.0, 10.0};
  std::printf("%-22s %7s %8s %8s %8s %9s %9s %7s %8s %12s\n", "mesh", "lambda",
              "faces", "seconds", "angleAvg", "angleMax", "areaAvg", "areaMax",
              "flipped", "energy");
  for (const std::string& path : meshes) {
    auto mesh = sdcb::ReadMesh(path);
    if (!mesh.ok()) {
      std::printf("%s\n", mesh.status().message().c_str());
      continue;
    }
    for (double lambda : lambdas) {
      sdcb::SphericalParameterizationOptions options;
      options.lambda = lambda;
      options.threads = threads;
      options.level_sweeps = level_sweeps;
      options.finest_sweeps = finest_sweeps;
      options.level_tolerance = tolerance;
      options.finest_tolerance = finest_tolerance;
      options.large_level_tolerance = large_level_tolerance;
      options.large_level_sweeps = large_level_sweeps;
      options.lambda_growth = lambda_growth;
      options.coarse_lambda = coarse_lambda;
      options.rising_levels = rising_levels;
      options.level_growth = level_growth;
      options.base_vertices = base_vertices;
      options.base_sweeps = base_sweeps;
      options.global_iterations = global_iterations;
      options.active_fraction = active_fraction;
      const auto start = std::chrono::steady_clock::now();
      if (verbose) {
        options.progress = [start](const std::string& stage, double fraction) {
          std::fprintf(stderr, "  %8.3f s  %-10s %5.1f%%\n",
                       std::chrono::duration<double>(
                           std::chrono::steady_clock::now() - start)
                           .count(),
                       stage.c_str(), 100.0 * fraction);
        };
      }
      auto param = sdcb::ParameterizeOnSphere(*mesh, options);
      const double seconds = std::chrono::duration<double>(
                                 std::chrono::steady_clock::now() - start)
                                 .count();
      const std::string name = path.substr(path.find_last_of('/') + 1);
      if (!param.ok()) {
        std::printf("%-22s %7.2f FAILED: %s\n", name.c_str(), lambda,
                    param.status().message().c_str());
        continue;
      }
      auto d = sdcb::MeasureParameterizationDistortion(*mesh, param->sphere);
      std::printf("%-22s %7.2f %8d %8.3f %8.3f %9.3f %9.3f %7.3g %8d %12.6g\n",
                  name.c_str(), lambda, mesh->num_faces(), seconds,
                  d->angle_distortion_avg, d->angle_distortion_max,
                  d->area_distortion_avg, d->area_distortion_max,
                  d->flipped_triangles, param->energy);
      std::fflush(stdout);
    }
  }
  return 0;
}
