// The alternative a user would pick instead of a spline: the input mesh
// decimated by CGAL's Garland-Heckbert (quadric) edge collapse to as many
// vertices as the spline has control points. Prints both objects' two-sided
// distance to the input, measured the same way: dense area-weighted samples
// of one surface, distances to the other by CGAL's AABB tree, rms as the
// root of the mean of the two mean squares, max as the Hausdorff distance;
// percent of the input's largest bounding-box side.
//   decimation_bench MESH MODEL.sdcb [SAMPLES]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench/garland_heckbert.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: decimation_bench MESH MODEL.sdcb [SAMPLES]\n");
    return 2;
  }
  const int samples = argc > 3 ? std::atoi(argv[3]) : 200000;
  auto mesh = sdcb::ReadMesh(argv[1]);
  auto model = sdcb::ReadSdcbFile(argv[2]);
  if (!mesh.ok() || !model.ok()) {
    std::fprintf(
        stderr, "%s\n",
        (!mesh.ok() ? mesh.status() : model.status()).message().c_str());
    return 1;
  }
  const double side = (mesh->vertices.colwise().maxCoeff() -
                       mesh->vertices.colwise().minCoeff())
                          .maxCoeff();
  const int target = static_cast<int>(model->control_points.rows());
  const auto start = std::chrono::steady_clock::now();
  // A closed genus-0 mesh with V vertices has 3V - 6 edges.
  const sdcb::TriangleMesh decimated =
      sdcb_bench::DecimateToEdges(*mesh, std::max(6, 3 * target - 6));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  auto to_input = sdcb::MeshDistance::Create(*mesh);
  auto to_decimated = sdcb::MeshDistance::Create(decimated);
  const sdcb_bench::TwoSidedDistance two_sided = sdcb_bench::MeasureTwoSided(
      decimated, *to_decimated, *mesh, *to_input, samples);
  const double rms = 100 * two_sided.rms / side;
  const double hausdorff = 100 * two_sided.max / side;

  // The spline, measured by the library against the same input.
  auto surface = sdcb::SurfaceFromModel(*model);
  sdcb::TriangleMesh normalized = *mesh;
  normalized.vertices = model->transform.ToNormalized(mesh->vertices);
  sdcb::DeviationOptions options;
  options.length_unit = side / model->transform.scale;
  options.min_surface_samples = samples;
  options.mesh_samples = samples;  // the input's triangles too, as sdcb compare
  auto d = sdcb::MeasureSurfaceDeviation(*surface, normalized, options);
  if (!surface.ok() || !d.ok()) return 1;
  std::printf(
      "%s: spline %d control points: rms %.4f%% Hausdorff %.3f%% | "
      "Garland-Heckbert %d vertices (%d faces, %.2f s): rms %.4f%% Hausdorff "
      "%.3f%%\n",
      argv[1], target, d->rms_percent, d->hausdorff_percent,
      decimated.num_vertices(), decimated.num_faces(), seconds, rms, hausdorff);
  return 0;
}
