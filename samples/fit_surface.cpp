// Sample: fit a spherical DCB-spline to a mesh with the installed sdcb
// package, then evaluate the surface, its normal and curvature.
//   fit_surface MESH [RMSE_PERCENT]
#include <sdcb/core/fit/spline_fitter.h>
#include <sdcb/core/spline/spherical_spline.h>
#include <sdcb/io/mesh/mesh_reader.h>

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: fit_surface MESH [RMSE_PERCENT]\n");
    return 2;
  }
  sdcb::StatusOr<sdcb::TriangleMesh> mesh = sdcb::ReadMesh(argv[1]);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
    return 1;
  }
  sdcb::FitOptions options;  // degree 4, 100 knots per round, ...
  options.rmse_percent = argc > 2 ? std::atof(argv[2]) : 0.1;
  sdcb::StatusOr<sdcb::FitResult> fit =
      sdcb::FitSphericalSpline(*mesh, options);
  if (!fit.ok()) {
    std::fprintf(stderr, "%s: %s\n", argv[1], fit.status().message().c_str());
    return 1;
  }
  const sdcb::RoundStatistics& final_round = fit->model.statistics.final_result;
  std::printf("%d control points, rmse %.4f%%, max error %.4f%%\n",
              final_round.control_points, final_round.rmse_percent,
              final_round.max_error_percent);
  sdcb::StatusOr<sdcb::SphericalSpline> surface =
      sdcb::SurfaceFromModel(fit->model);
  if (!surface.ok()) return 1;
  // The surface point over the north pole, in the input's coordinates.
  const Eigen::Vector3d north(0, 0, 1);
  const sdcb::SurfacePoint s = surface->EvaluateDifferential(north);
  const Eigen::MatrixX3d position =
      fit->model.transform.ToInput(s.position.transpose());
  std::printf("F(north) = (%g, %g, %g), normal (%g, %g, %g), H = %g\n",
              position(0, 0), position(0, 1), position(0, 2), s.normal.x(),
              s.normal.y(), s.normal.z(),
              s.mean_curvature / fit->model.transform.scale);
  return 0;
}
