// Where an adaptive tessellation's triangles go, against the asymptotic
// optimum N_opt (core/tessellate/optimal_triangle_count.h):
//   tessellation_efficiency_bench MODEL.sdcb TOLERANCE_PCT
// Tessellates the model at the tolerance, then for each face: its share of
// N_opt (area times the optimum's density at its centroid, eta), its
// largest distance to its own flat triangle on an order-24 lattice (err, a
// fraction of the tolerance; sheared faces read high), and its shape
// efficiency eta / err (1 for a metric-equilateral face of a quadratic
// surface). N / N_opt = (N / sum err) * (sum err / sum eta): the first
// factor is the tolerance the faces leave unused, the second their shapes.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "sdcb/core/measure/triangle_distance.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"
#include "sdcb/core/tessellate/optimal_triangle_count.h"
#include "sdcb/io/sdcb_file.h"

namespace {

constexpr int kOrder = 24;

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: %s MODEL.sdcb TOLERANCE_PCT\n",
                 argv[0]);
    return 2;
  }
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) {
    std::fprintf(stderr, "%s\n", model.status().message().c_str());
    return 1;
  }
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  const sdcb::PiecewiseSurface pieces(*spline);
  const sdcb::PiecewiseSplineSampler sampler(*spline, pieces);
  sdcb::TessellationOptions options;
  options.tolerance = std::atof(argv[2]) / 100.0;
  const double eps = options.tolerance;
  const auto start = std::chrono::steady_clock::now();
  auto t = sdcb::TessellateAdaptively(sampler, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  if (!t.ok()) return 1;
  const Eigen::Index nf = t->faces.rows();

  // Curvature at the face centroids.
  Eigen::MatrixX3d centroids(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    centroids.row(f) =
        (t->directions.row(t->faces(f, 0)) + t->directions.row(t->faces(f, 1)) +
         t->directions.row(t->faces(f, 2)))
            .normalized();
  }
  Eigen::VectorXd gaussian, mean;
  sampler.SampleCurvature(centroids, &gaussian, &mean);

  // Lattice points (interior and edges, corners excluded).
  std::vector<Eigen::Vector3d> bary;
  for (int i = 0; i <= kOrder; ++i)
    for (int j = 0; i + j <= kOrder; ++j) {
      const int k = kOrder - i - j;
      if (i == kOrder || j == kOrder || k == kOrder) continue;
      bary.emplace_back(i, j, k);
    }
  const Eigen::Index per = static_cast<Eigen::Index>(bary.size());
  Eigen::MatrixX3d dirs(nf * per, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = t->directions.row(t->faces(f, 0)).transpose();
    const Eigen::Vector3d b = t->directions.row(t->faces(f, 1)).transpose();
    const Eigen::Vector3d c = t->directions.row(t->faces(f, 2)).transpose();
    for (Eigen::Index s = 0; s < per; ++s) {
      const Eigen::Vector3d& w = bary[s];
      dirs.row(f * per + s) = (w[0] * a + w[1] * b + w[2] * c).normalized();
    }
  }
  Eigen::MatrixX3d points;
  sampler.Sample(dirs, &points, nullptr);

  // Faces around each vertex: a point's distance to the mesh near its face
  // is the least over the faces around the face's corners.
  std::vector<std::vector<int>> around(t->directions.rows());
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) around[t->faces(f, k)].push_back(int(f));
  // The corner prediction's largest error on the lattice (exact for a
  // quadratic surface), for the shape alone.
  auto predicted = [&](Eigen::Index f) {
    Eigen::Vector3d p[3], n[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = t->positions.row(t->faces(f, k)).transpose();
      n[k] = t->normals.row(t->faces(f, k)).transpose();
    }
    const double q01 = (n[1] - n[0]).dot(p[1] - p[0]);
    const double q12 = (n[2] - n[1]).dot(p[2] - p[1]);
    const double q02 = (n[2] - n[0]).dot(p[2] - p[0]);
    double e = 0;
    for (const Eigen::Vector3d& w3 : bary) {
      const Eigen::Vector3d w = w3 / kOrder;
      e = std::max(e, 0.5 * std::abs(w[0] * w[1] * q01 + w[1] * w[2] * q12 +
                                     w[0] * w[2] * q02));
    }
    return e;
  };
  double sum_shape_convex = 0, sum_shape_saddle = 0;
  int n_shape_convex = 0, n_shape_saddle = 0;
  double sum_eta = 0, sum_err = 0;
  const std::array<double, 8> edges = {0.5,  0.7, 0.8,  0.9,
                                       0.95, 1.0, 1.05, 1e300};
  std::array<int, 8> count{};
  std::array<double, 8> bin_eta{}, bin_err{};
  std::array<int, 6> low_eta{};  // eta < 0.1, 0.2, 0.4, ...
  std::array<double, 6> low_eta_share{};
  const std::array<double, 6> eta_edges = {0.1, 0.2, 0.4, 0.6, 0.8, 1e300};
  int convex = 0, saddle = 0;
  double convex_eta = 0, saddle_eta = 0, convex_err = 0, saddle_err = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d p0 = t->positions.row(t->faces(f, 0)).transpose();
    const Eigen::Vector3d p1 = t->positions.row(t->faces(f, 1)).transpose();
    const Eigen::Vector3d p2 = t->positions.row(t->faces(f, 2)).transpose();
    const double area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    const double k = gaussian[f];
    double density = 0;
    if (std::isfinite(k)) {
      density = k > 0 ? sdcb::kConvexTriangleConstant * std::sqrt(k)
                      : sdcb::kSaddleTriangleConstant * std::sqrt(-k);
    }
    const double eta = area * density / eps;
    double err = 0;
    for (Eigen::Index s = 0; s < per; ++s) {
      const Eigen::Vector3d x = points.row(f * per + s).transpose();
      double d = sdcb::PointTriangleDistance(x, p0, p1, p2);
      if (d > 0.5 * eps) {
        for (int c = 0; c < 3; ++c)
          for (int g : around[t->faces(f, c)]) {
            d = std::min(d, sdcb::PointTriangleDistance(
                                x, t->positions.row(t->faces(g, 0)).transpose(),
                                t->positions.row(t->faces(g, 1)).transpose(),
                                t->positions.row(t->faces(g, 2)).transpose()));
          }
      }
      err = std::max(err, d);
    }
    err /= eps;
    const double pred = predicted(f);
    if (pred > 0 && std::isfinite(k) && k != 0) {
      // Area per unit error against the optimum's: 1 for the best shape.
      const double shape = area * std::sqrt(std::abs(k)) / pred;
      if (k > 0) {
        sum_shape_convex += shape / (1.5 * std::sqrt(3.0));
        ++n_shape_convex;
      } else {
        sum_shape_saddle += shape / (2 * std::sqrt(5.0));
        ++n_shape_saddle;
      }
    }
    sum_eta += eta;
    sum_err += err;
    int b = 0;
    while (err > edges[b]) ++b;
    ++count[b];
    bin_eta[b] += eta;
    bin_err[b] += err;
    int e = 0;
    while (eta > eta_edges[e]) ++e;
    ++low_eta[e];
    low_eta_share[e] += err;
    if (k > 0) {
      ++convex;
      convex_eta += eta;
      convex_err += std::min(err, 1.0);
    } else {
      ++saddle;
      saddle_eta += eta;
      saddle_err += std::min(err, 1.0);
    }
  }
  std::printf(
      "faces %lld  sum eta (N_opt, centroid rule) %.1f  N/N_opt %.3f"
      "  evaluations %lld  tessellation %.1f s\n",
      static_cast<long long>(nf), sum_eta, nf / sum_eta,
      static_cast<long long>(t->evaluations), seconds);
  std::printf(
      "unused tolerance N/sum(err) %.3f   shapes sum(err)/sum(eta) %.3f\n",
      nf / sum_err, sum_err / sum_eta);
  std::printf(
      "convex faces %d: N/eta %.3f, err/eta %.3f | saddle %d: %.3f, "
      "%.3f\n",
      convex, convex / convex_eta, convex_err / convex_eta, saddle,
      saddle / saddle_eta, saddle_err / saddle_eta);
  std::printf(
      "predicted shape quality (1 = optimal): convex %.3f, saddle "
      "%.3f\n",
      sum_shape_convex / std::max(1, n_shape_convex),
      sum_shape_saddle / std::max(1, n_shape_saddle));
  std::printf("err/eps bin   faces   share   mean err  N/eta in bin\n");
  double lo = 0;
  for (int b = 0; b < 8; ++b) {
    std::printf("(%4.2f,%5.2f]  %7d  %5.1f%%  %7.3f  %7.3f\n", lo,
                std::min(edges[b], 9.99), count[b], 100.0 * count[b] / nf,
                count[b] ? bin_err[b] / count[b] : 0.0,
                bin_eta[b] > 0 ? count[b] / bin_eta[b] : 0.0);
    lo = edges[b];
  }
  std::printf("eta bin (face's share of N_opt)  faces  share  mean err\n");
  lo = 0;
  for (int e = 0; e < 6; ++e) {
    std::printf("(%4.2f,%5.2f]  %7d  %5.1f%%  %7.3f\n", lo,
                std::min(eta_edges[e], 9.99), low_eta[e],
                100.0 * low_eta[e] / nf,
                low_eta[e] ? low_eta_share[e] / low_eta[e] : 0.0);
    lo = eta_edges[e];
  }
  return 0;
}
