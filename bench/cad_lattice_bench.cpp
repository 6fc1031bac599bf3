// How much the CAD patches' fine lattice (order 3 n) finds above the coarse
// one (order n) per face, the ratio behind CadPatchOptions::fine_share
// (docs/CAD.md):
//
//   cad_lattice_bench MODEL.sdcb [TOLERANCE_PERCENT] [ANGLE_DEGREES]
//
// Fits the patches as `sdcb export MODEL -o x.step` does, then measures
// every patch on both lattices itself (the spline by PiecewiseSurface, as
// the fitter) and prints the largest fine / coarse ratios of the distance
// and of the normal angle, and the largest fine figures among the faces the
// fitter measured on the coarse lattice only (coarse below fine_share of
// the limits), as shares of the limits.
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "sdcb/converters/cad_patches.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/io/sdcb_file.h"

namespace {

struct LatticeMax {
  double distance = 0.0, angle = 0.0;
};

LatticeMax MeasureFace(const sdcb::PiecewiseSurface& surface,
                       const sdcb::SphereCage& layout,
                       const sdcb::BicubicPatch& patch, int f, int order) {
  LatticeMax m;
  for (int j = 0; j <= order; ++j) {
    for (int i = 0; i <= order; ++i) {
      const double u = double(i) / order, v = double(j) / order;
      Eigen::Vector3d du, dv, point, normal;
      const Eigen::Vector3d b = patch.Evaluate(u, v, &du, &dv);
      surface.EvaluateWithNormal(layout.SpherePoint(f, u, v), &point, &normal);
      m.distance = std::max(m.distance, (b - point).norm());
      const Eigen::Vector3d n = du.cross(dv);
      if (n.norm() > 0 && normal.norm() > 0) {
        const double c = std::clamp(n.normalized().dot(normal), -1.0, 1.0);
        m.angle = std::max(m.angle, std::acos(c) * 180.0 / M_PI);
      }
    }
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: cad_lattice_bench MODEL.sdcb [TOLERANCE_PERCENT] "
                 "[ANGLE_DEGREES]\n");
    return 2;
  }
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) return 1;
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  sdcb::CadPatchOptions options;
  if (argc > 2) options.tolerance_percent = std::stod(argv[2]);
  if (argc > 3) options.angle_degrees = std::stod(argv[3]);
  const auto start = std::chrono::steady_clock::now();
  auto fit = sdcb::FitCadPatches(*spline, options);
  if (!fit.ok()) return 1;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  const sdcb::PiecewiseSurface surface(*spline);
  const int nf = fit->layout.num_faces();
  const int n = std::max(
      options.check_samples_per_side,
      static_cast<int>(std::ceil(
          std::sqrt(static_cast<double>(options.measure_samples) / nf))));
  std::vector<LatticeMax> coarse(nf), fine(nf);
  tbb::parallel_for(0, nf, [&](int f) {
    coarse[f] = MeasureFace(surface, fit->layout, fit->patches[f], f, n);
    fine[f] = MeasureFace(surface, fit->layout, fit->patches[f], f, 3 * n);
  });
  const double tolerance = options.tolerance_percent / 100.0;
  double ratio_distance = 0, ratio_angle = 0, skipped_distance = 0,
         skipped_angle = 0;
  int skipped = 0;
  for (int f = 0; f < nf; ++f) {
    if (coarse[f].distance > 0.05 * tolerance) {
      ratio_distance =
          std::max(ratio_distance, fine[f].distance / coarse[f].distance);
    }
    if (coarse[f].angle > 0.05 * options.angle_degrees) {
      ratio_angle = std::max(ratio_angle, fine[f].angle / coarse[f].angle);
    }
    if (coarse[f].distance <= options.fine_share * tolerance &&
        coarse[f].angle <= options.fine_share * options.angle_degrees) {
      ++skipped;
      skipped_distance = std::max(skipped_distance, fine[f].distance);
      skipped_angle = std::max(skipped_angle, fine[f].angle);
    }
  }
  std::printf(
      "%s: %d patches in %.2f s (%d measured on the fine lattice), lattice "
      "orders %d and %d\n"
      "  fine / coarse, largest: distance %.3f, angle %.3f (faces above 5 %% "
      "of the limit)\n"
      "  %d faces below %.0f %% of both limits on the coarse lattice: on the "
      "fine one at most %.1f %% of the tolerance, %.1f %% of the angle\n",
      argv[1], nf, seconds, fit->fine_faces, n, 3 * n, ratio_distance,
      ratio_angle, skipped, 100 * options.fine_share,
      100 * skipped_distance / tolerance,
      100 * skipped_angle / options.angle_degrees);
  return 0;
}
