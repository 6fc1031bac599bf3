// The fit with FitOptions::keep_features (corner knot clusters,
// core/knots/feature_knots.h) against the default fit, per mesh: whether the
// clusters were kept, control points, the dense two-sided rms and Hausdorff
// distance and folded area the fit reports, the spline's normal at 1 % of
// the largest side from every feature edge against the triangle's
// (tests/testing/feature_normals.h), and seconds. One Markdown row per fit.
//
//   feature_fit_bench MESH... [--rmse PCT]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "testing/feature_normals.h"

int main(int argc, char** argv) {
  std::vector<std::string> meshes;
  double rmse = 0.1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--rmse") == 0 && i + 1 < argc) {
      rmse = std::atof(argv[++i]);
    } else {
      meshes.push_back(argv[i]);
    }
  }
  if (meshes.empty()) {
    std::fprintf(stderr, "usage: feature_fit_bench MESH... [--rmse PCT]\n");
    return 2;
  }
  std::printf(
      "| mesh | fit | features kept | control points | rms %% | Hausdorff %% "
      "| folded %% | normal beside the edges (max, deg) | seconds |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& path : meshes) {
    auto mesh = sdcb::ReadMesh(path);
    if (!mesh.ok()) {
      std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
      return 1;
    }
    for (const bool keep : {true, false}) {
      sdcb::FitOptions options;
      options.rmse_percent = rmse;
      options.keep_features = keep;
      const auto start = std::chrono::steady_clock::now();
      auto fit = sdcb::FitSphericalSpline(*mesh, options);
      const double seconds = std::chrono::duration<double>(
                                 std::chrono::steady_clock::now() - start)
                                 .count();
      if (!fit.ok()) {
        std::printf("| %s | %s | - | - | - | - | - | %s | %.1f |\n",
                    path.c_str(), keep ? "kept" : "smooth",
                    fit.status().message().c_str(), seconds);
        continue;
      }
      auto spline = sdcb::SurfaceFromModel(fit->model);
      if (!spline.ok()) return 1;
      const sdcb::testing::FeatureNormals normals =
          sdcb::testing::MeasureFeatureNormals(
              *spline, fit->model.transform.ToNormalized(mesh->vertices),
              mesh->faces, fit->features, 0.01, 1000000);
      const sdcb::RoundStatistics& f = fit->model.statistics.final_result;
      std::printf(
          "| %s | %s | %s | %d | %.4f | %.3f | %.4f | %.3f (%zu points) | "
          "%.1f |\n",
          path.c_str(), keep ? "kept" : "smooth",
          fit->features_kept ? "yes" : "no", f.control_points, f.rmse_percent,
          f.max_error_percent, f.folded_area_percent, normals.max_degrees,
          normals.angles_degrees.size(), seconds);
      std::fflush(stdout);
    }
  }
  return 0;
}
