// The alternative a user would pick instead of a spline: the input mesh
// decimated by CGAL's Garland-Heckbert (quadric) edge collapse to as many
// vertices as the spline has control points. Prints both objects' two-sided
// distance to the input, measured the same way: dense area-weighted samples
// of one surface, distances to the other by CGAL's AABB tree, rms as the
// root of the mean of the two mean squares, max as the Hausdorff distance;
// percent of the input's largest bounding-box side.
//   decimation_bench MESH MODEL.sdcb [SAMPLES]
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "sdcb/core/fit/surface_deviation.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace SMS = CGAL::Surface_mesh_simplification;

sdcb::TriangleMesh Decimate(const sdcb::TriangleMesh& input, int vertices) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> v;
  for (int i = 0; i < input.num_vertices(); ++i) {
    v.push_back(mesh.add_vertex(Kernel::Point_3(
        input.vertices(i, 0), input.vertices(i, 1), input.vertices(i, 2))));
  }
  for (int f = 0; f < input.num_faces(); ++f) {
    mesh.add_face(v[input.faces(f, 0)], v[input.faces(f, 1)],
                  v[input.faces(f, 2)]);
  }
  // A closed genus-0 mesh with V vertices has 3V - 6 edges.
  SMS::Count_stop_predicate<Mesh> stop(std::max(6, 3 * vertices - 6));
  SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> policies(mesh);
  SMS::edge_collapse(mesh, stop,
                     CGAL::parameters::get_cost(policies.get_cost())
                         .get_placement(policies.get_placement()));
  mesh.collect_garbage();
  sdcb::TriangleMesh out;
  out.vertices.resize(mesh.number_of_vertices(), 3);
  for (auto vi : mesh.vertices()) {
    const auto& p = mesh.point(vi);
    out.vertices.row(vi.idx()) << p.x(), p.y(), p.z();
  }
  out.faces.resize(mesh.number_of_faces(), 3);
  int row = 0;
  for (auto f : mesh.faces()) {
    int k = 0;
    for (auto vi : vertices_around_face(mesh.halfedge(f), mesh)) {
      out.faces(row, k++) = static_cast<int>(vi.idx());
    }
    ++row;
  }
  return out;
}

// Mean square and max distance from area-weighted random points of `a` to
// `b`.
void OneSided(const sdcb::TriangleMesh& a, const sdcb::MeshDistance& b,
              int samples, double* mean_square, double* max) {
  std::vector<double> area(a.num_faces());
  double total = 0;
  for (int f = 0; f < a.num_faces(); ++f) {
    const Eigen::Vector3d p = a.vertices.row(a.faces(f, 0));
    const Eigen::Vector3d q = a.vertices.row(a.faces(f, 1));
    const Eigen::Vector3d r = a.vertices.row(a.faces(f, 2));
    total += area[f] = 0.5 * (q - p).cross(r - p).norm();
  }
  std::mt19937 rng(1);
  std::discrete_distribution<int> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> unit(0, 1);
  double squares = 0;
  *max = 0;
  for (int i = 0; i < samples; ++i) {
    const int f = pick(rng);
    double s = unit(rng), t = unit(rng);
    if (s + t > 1) s = 1 - s, t = 1 - t;
    const Eigen::Vector3d x =
        (1 - s - t) * a.vertices.row(a.faces(f, 0)).transpose() +
        s * a.vertices.row(a.faces(f, 1)).transpose() +
        t * a.vertices.row(a.faces(f, 2)).transpose();
    const double d = b.Find(x).distance;
    squares += d * d;
    *max = std::max(*max, d);
  }
  *mean_square = squares / samples;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: decimation_bench MESH MODEL.sdcb [SAMPLES]\n");
    return 2;
  }
  const int samples = argc > 3 ? std::atoi(argv[3]) : 200000;
  auto mesh = sdcb::ReadMesh(argv[1]);
  auto model = sdcb::ReadSdcbFile(argv[2]);
  if (!mesh.ok() || !model.ok()) {
    std::fprintf(stderr, "%s\n", (!mesh.ok() ? mesh.status() : model.status())
                                     .message()
                                     .c_str());
    return 1;
  }
  const double side = (mesh->vertices.colwise().maxCoeff() -
                       mesh->vertices.colwise().minCoeff())
                          .maxCoeff();
  const int target = static_cast<int>(model->control_points.rows());
  const auto start = std::chrono::steady_clock::now();
  const sdcb::TriangleMesh decimated = Decimate(*mesh, target);
  const double seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start)
                             .count();
  auto to_input = sdcb::MeshDistance::Create(*mesh);
  auto to_decimated = sdcb::MeshDistance::Create(decimated);
  double ms1, max1, ms2, max2;
  OneSided(decimated, *to_input, samples, &ms1, &max1);
  OneSided(*mesh, *to_decimated, samples, &ms2, &max2);
  const double rms = 100 * std::sqrt(0.5 * (ms1 + ms2)) / side;
  const double hausdorff = 100 * std::max(max1, max2) / side;

  // The spline, measured by the library against the same input.
  auto surface = sdcb::SurfaceFromModel(*model);
  sdcb::TriangleMesh normalized = *mesh;
  normalized.vertices = model->transform.ToNormalized(mesh->vertices);
  sdcb::DeviationOptions options;
  options.length_unit = side / model->transform.scale;
  options.min_surface_samples = samples;
  auto d = sdcb::MeasureSurfaceDeviation(*surface, normalized, options);
  if (!surface.ok() || !d.ok()) return 1;
  std::printf(
      "%s: spline %d control points: rms %.4f%% Hausdorff %.3f%% | "
      "Garland-Heckbert %d vertices (%d faces, %.2f s): rms %.4f%% Hausdorff "
      "%.3f%%\n",
      argv[1], target, d->rms_percent, d->hausdorff_percent,
      decimated.num_vertices(), decimated.num_faces(), seconds, rms,
      hausdorff);
  return 0;
}
