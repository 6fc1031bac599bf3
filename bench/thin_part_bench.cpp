// Thin parts, controlled: a unit sphere with a round-tipped finger of radius
// r and length L along +z (the two radius profiles joined by a smooth
// maximum, a surface of revolution triangulated with edges of about h), for
// several L / r. For each: the sphere map's anisotropy on the finger (the
// ratio of the singular values of the map's Jacobian per triangle, median
// and 90th percentile over the finger's triangles, and the finger's share of
// the sphere's area against its share of the surface's), then the fit at the
// rms target: reached or not, control points, rms, Hausdorff distance,
// folded area, seconds.
//   thin_part_bench [L/r ...] [--radius R] [--edge H] [--rmse PCT]
//                   [--lambda L] [--max-rounds N] [--one-fit] [--write DIR]
// Default: L/r = 2.5 5 10 20 40, R = 0.1, H = 0.025, --rmse 0.1, lambda 1.
// --one-fit: the first fit alone (FitOptions::retry_map_vertices 0: below
// 20,000 vertices FitSphericalSpline would otherwise fit again, split or
// with a smaller lambda, where it folds). --write DIR also writes each mesh
// as DIR/finger_<L/r>.off.
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/param/spherical_parameterization.h"
#include "sdcb/io/mesh/mesh_writer.h"
#include "testing/finger_mesh.h"

namespace {

// A triangle's edge vectors in an orthonormal frame of its plane (columns).
Eigen::Matrix2d PlanarEdges(const Eigen::Vector3d& p0,
                            const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& p2) {
  const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
  const Eigen::Vector3d u = e1.normalized();
  const Eigen::Vector3d w = e1.cross(e2).normalized().cross(u);
  Eigen::Matrix2d m;
  m << e1.dot(u), e2.dot(u), e1.dot(w), e2.dot(w);
  return m;
}

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  const size_t k = static_cast<size_t>(q * (values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> ratios;
  double r = 0.1, h = 0.025;
  sdcb::FitOptions options;
  options.rmse_percent = 0.1;
  std::string write_dir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? argv[++i] : "0"; };
    if (a == "--radius") {
      r = std::atof(next());
    } else if (a == "--edge") {
      h = std::atof(next());
    } else if (a == "--rmse") {
      options.rmse_percent = std::atof(next());
    } else if (a == "--lambda") {
      options.lambda = std::atof(next());
    } else if (a == "--max-rounds") {
      options.max_rounds = std::atoi(next());
    } else if (a == "--one-fit") {
      options.retry_map_vertices = 0;  // no second fits (FitSphericalSpline)
    } else if (a == "--write") {
      write_dir = next();
    } else {
      ratios.push_back(std::atof(a.c_str()));
    }
  }
  if (ratios.empty()) ratios = {2.5, 5, 10, 20, 40};
  if (!(r > 0 && r < 0.5 && h > 0 && h < r)) {
    std::fprintf(stderr, "need 0 < --edge < --radius < 0.5\n");
    return 1;
  }
  std::printf(
      "finger radius %g, edge %g, lambda %g, --rmse %g, %s\n"
      "| L/r | vertices | anisotropy median / p90 on the finger | finger's "
      "sphere area / surface area share | reached | lambda returned | "
      "control points | rms %% | Hausdorff %% | folded %% | seconds |\n"
      "|---|---:|---|---:|---|---:|---:|---:|---:|---:|---:|\n",
      r, h, options.lambda, options.rmse_percent,
      options.retry_map_vertices == 0 ? "one fit" : "second fits as sdcb fit");
  for (double ratio : ratios) {
    const sdcb::TriangleMesh mesh = sdcb::testing::FingerMesh(r, ratio * r, h);
    if (!write_dir.empty()) {
      char name[64];
      std::snprintf(name, sizeof(name), "/finger_%g.off", ratio);
      const sdcb::Status w = sdcb::WriteMesh(mesh, write_dir + name);
      if (!w.ok()) std::fprintf(stderr, "%s\n", w.message().c_str());
    }
    sdcb::SphericalParameterizationOptions map_options;
    map_options.lambda = options.lambda;
    const auto map = sdcb::ParameterizeOnSphere(mesh, map_options);
    if (!map.ok()) {
      std::printf("| %g | %d | map failed: %s |\n", ratio, mesh.num_vertices(),
                  map.status().message().c_str());
      continue;
    }
    // The finger: triangles above the sphere's cap where the finger starts.
    const double base = std::sqrt(1 - r * r);
    std::vector<double> anisotropy;
    double finger_area = 0, finger_sphere = 0, area = 0, sphere_area = 0;
    for (int t = 0; t < mesh.num_faces(); ++t) {
      const Eigen::Vector3i f = mesh.faces.row(t);
      const Eigen::Matrix2d a =
          PlanarEdges(mesh.vertices.row(f[0]), mesh.vertices.row(f[1]),
                      mesh.vertices.row(f[2]));
      const Eigen::Matrix2d b = PlanarEdges(
          map->sphere.row(f[0]), map->sphere.row(f[1]), map->sphere.row(f[2]));
      const double ta = 0.5 * std::abs(a.determinant());
      const double tb = 0.5 * std::abs(b.determinant());
      area += ta;
      sphere_area += tb;
      const double z = (mesh.vertices(f[0], 2) + mesh.vertices(f[1], 2) +
                        mesh.vertices(f[2], 2)) /
                       3;
      if (z < base) continue;
      finger_area += ta;
      finger_sphere += tb;
      const Eigen::Vector2d sv =
          Eigen::JacobiSVD<Eigen::Matrix2d>(b * a.inverse()).singularValues();
      anisotropy.push_back(sv[0] / sv[1]);
    }
    const auto start = std::chrono::steady_clock::now();
    const auto fit = sdcb::FitSphericalSpline(mesh, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    if (!fit.ok()) {
      std::printf("| %g | %d | fit failed: %s |\n", ratio, mesh.num_vertices(),
                  fit.status().message().c_str());
      continue;
    }
    const sdcb::RoundStatistics& s = fit->model.statistics.final_result;
    std::printf(
        "| %g | %d | %.1f / %.1f | %.3f | %s | %g | %d | %.4f | %.3f | %.2g | "
        "%.1f |\n",
        ratio, mesh.num_vertices(), Percentile(anisotropy, 0.5),
        Percentile(anisotropy, 0.9),
        (finger_sphere / sphere_area) / (finger_area / area),
        fit->reached_target() ? "yes" : "no",
        fit->model.statistics.options.lambda, s.control_points, s.rmse_percent,
        s.max_error_percent, s.folded_area_percent, seconds);
    std::fflush(stdout);
  }
  return 0;
}
