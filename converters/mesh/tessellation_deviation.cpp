#include "sdcb/converters/mesh/tessellation_deviation.h"

#include <Eigen/Dense>
#include <algorithm>
#include <limits>
#include <random>

#include "sdcb/core/measure/closest_surface_points.h"
#include "sdcb/core/mesh/mesh_distance.h"

namespace sdcb {
namespace {

// Surface -> mesh at random points of every face's domain triangle.
double SurfaceToMesh(const SurfaceSampler& surface, const Tessellation& t,
                     int per_face) {
  const Eigen::Index nf = t.faces.rows();
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::MatrixX3d directions(nf * per_face, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    for (int s = 0; s < per_face; ++s) {
      double a = uniform(rng), b = uniform(rng);
      if (a + b > 1.0) {
        a = 1.0 - a;
        b = 1.0 - b;
      }
      directions.row(f * per_face + s) =
          (a * t.directions.row(t.faces(f, 0)) +
           b * t.directions.row(t.faces(f, 1)) +
           (1.0 - a - b) * t.directions.row(t.faces(f, 2)))
              .normalized();
    }
  }
  Eigen::MatrixX3d points;
  surface.Sample(directions, &points, nullptr);
  TriangleMesh mesh;
  mesh.vertices = t.positions;
  mesh.faces = t.faces;
  // A tessellation without a usable triangle cannot be measured: infinite.
  const StatusOr<MeshDistance> distance = MeshDistance::Create(mesh);
  if (!distance.ok()) return std::numeric_limits<double>::infinity();
  return points.rows() > 0 ? distance->Distances(points).maxCoeff() : 0.0;
}

// Mesh -> surface: from each face's domain centroid to its flat centroid's
// foot point.
double MeshToSurface(const SurfaceSampler& surface, const Tessellation& t) {
  const Eigen::Index nf = t.faces.rows();
  Eigen::MatrixX3d x(nf, 3), u(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    x.row(f) =
        (t.positions.row(t.faces(f, 0)) + t.positions.row(t.faces(f, 1)) +
         t.positions.row(t.faces(f, 2))) /
        3.0;
    u.row(f) =
        (t.directions.row(t.faces(f, 0)) + t.directions.row(t.faces(f, 1)) +
         t.directions.row(t.faces(f, 2)))
            .normalized();
  }
  return nf > 0 ? ClosestSurfacePoints(surface, x, 4, &u).maxCoeff() : 0.0;
}

}  // namespace

TessellationDeviation MeasureTessellationDeviation(
    const SurfaceSampler& surface, const Tessellation& tessellation,
    int samples_per_face) {
  TessellationDeviation d;
  d.surface_to_mesh =
      SurfaceToMesh(surface, tessellation, std::max(samples_per_face, 0));
  d.mesh_to_surface = MeshToSurface(surface, tessellation);
  return d;
}

}  // namespace sdcb
