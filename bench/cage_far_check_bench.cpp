// The check of tests/tools/cage_cli_test.cpp for models too large for CI: a
// cage written by `sdcb cage` is re-read from its OBJ, refined by
// OpenSubdiv's Far (not the Bfr stencils the converter fits and measures
// with) LEVELS times, and its limit points measured against the spline by
// core/measure/surface_deviation (the fit's own honest measurement: exact
// evaluator, closest-point searches both ways); printed beside the
// report's figures.
//
//   cage_far_check_bench MODEL.sdcb CAGE.obj CAGE.json [LEVELS]
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/far_refinement.h"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: cage_far_check_bench MODEL.sdcb CAGE.obj CAGE.json "
                 "[LEVELS]\n");
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) return 1;
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  const int levels = argc > 4 ? std::stoi(argv[4]) : 3;
  // "v x y z" and "f a b c [d]" lines (1-based).
  std::ifstream in(argv[2]);
  std::vector<Eigen::RowVector3d> points;
  std::vector<std::vector<int>> faces;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      Eigen::RowVector3d p;
      s >> p[0] >> p[1] >> p[2];
      points.push_back(p);
    } else if (tag == "f") {
      std::vector<int> f;
      int i;
      while (s >> i) f.push_back(i - 1);
      faces.push_back(f);
    }
  }
  Eigen::MatrixX3d cage(points.size(), 3);
  for (size_t i = 0; i < points.size(); ++i) cage.row(i) = points[i];
  const bool loop = !faces.empty() && faces[0].size() == 3;
  const sdcb::testing::FarRefined far = sdcb::testing::RefineWithFar(
      loop, model->transform.ToNormalized(cage), faces, levels);
  sdcb::TriangleMesh mesh;
  mesh.vertices = far.limit;
  std::vector<Eigen::RowVector3i> triangles;
  for (const auto& f : far.faces) {
    triangles.emplace_back(f[0], f[1], f[2]);
    if (f.size() == 4) triangles.emplace_back(f[0], f[2], f[3]);
  }
  mesh.faces.resize(triangles.size(), 3);
  for (size_t t = 0; t < triangles.size(); ++t)
    mesh.faces.row(t) = triangles[t];
  auto d = sdcb::MeasureSurfaceDeviation(*spline, mesh);
  if (!d.ok()) {
    std::fprintf(stderr, "%s\n", d.status().message().c_str());
    return 1;
  }
  std::ifstream report_file(argv[3]);
  const nlohmann::json report = nlohmann::json::parse(report_file);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  std::printf(
      "%s: %zu faces; Far level %d (%lld limit points) vs spline:\n"
      "  limit -> spline rms %.5f%% max %.4f%% (report %.5f%%, %.4f%%)\n"
      "  two-sided rms %.5f%% (report %.5f%%), spline -> limit max %.4f%% "
      "(report %.4f%%; the Far side is a chord mesh)  %.1f s\n",
      argv[2], faces.size(), levels, static_cast<long long>(far.limit.rows()),
      d->mesh_to_surface_rms_percent, d->mesh_to_surface_max_percent,
      report["limit_to_spline_rms_percent"].get<double>(),
      report["limit_to_spline_max_percent"].get<double>(), d->rms_percent,
      report["limit_rmse_percent"].get<double>(),
      d->surface_to_mesh_max_percent,
      report["spline_to_limit_max_percent"].get<double>(), seconds);
  return 0;
}
