// For bench/decimation_bench: the input mesh decimated by CGAL's
// Garland-Heckbert (plane quadrics) edge collapse, and the two-sided
// distance between two triangle meshes measured by dense area-weighted
// samples (the alternative a user would pick instead of a spline, measured
// as the spline is: both ways, where nothing was fitted). Header-only; bench
// programs only.
#ifndef SDCB_BENCH_GARLAND_HECKBERT_H_
#define SDCB_BENCH_GARLAND_HECKBERT_H_

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb_bench {

// `input` (closed, manifold) collapsed until at most `edges` edges are left
// (a closed genus-0 mesh has 3V - 6 edges and 3F / 2).
inline sdcb::TriangleMesh DecimateToEdges(const sdcb::TriangleMesh& input,
                                          std::size_t edges) {
  using Kernel = CGAL::Simple_cartesian<double>;
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  namespace SMS = CGAL::Surface_mesh_simplification;
  Mesh mesh;
  std::vector<Mesh::Vertex_index> v;
  for (Eigen::Index i = 0; i < input.vertices.rows(); ++i) {
    v.push_back(mesh.add_vertex(Kernel::Point_3(
        input.vertices(i, 0), input.vertices(i, 1), input.vertices(i, 2))));
  }
  for (Eigen::Index f = 0; f < input.faces.rows(); ++f) {
    mesh.add_face(v[input.faces(f, 0)], v[input.faces(f, 1)],
                  v[input.faces(f, 2)]);
  }
  SMS::Count_stop_predicate<Mesh> stop(edges);
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

// Mean square and max distance from `samples` area-weighted random points
// of `a` (fixed seed: the same points every run) to `b`.
inline void OneSidedDistance(const sdcb::TriangleMesh& a,
                             const sdcb::MeshDistance& b, int samples,
                             double* mean_square, double* max) {
  std::vector<double> area(a.faces.rows());
  for (Eigen::Index f = 0; f < a.faces.rows(); ++f) {
    const Eigen::Vector3d p = a.vertices.row(a.faces(f, 0));
    const Eigen::Vector3d q = a.vertices.row(a.faces(f, 1));
    const Eigen::Vector3d r = a.vertices.row(a.faces(f, 2));
    area[f] = 0.5 * (q - p).cross(r - p).norm();
  }
  std::mt19937 rng(1);
  std::discrete_distribution<int> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> unit(0, 1);
  Eigen::MatrixX3d points(samples, 3);
  for (int i = 0; i < samples; ++i) {
    const int f = pick(rng);
    double s = unit(rng), t = unit(rng);
    if (s + t > 1) s = 1 - s, t = 1 - t;
    points.row(i) = (1 - s - t) * a.vertices.row(a.faces(f, 0)) +
                    s * a.vertices.row(a.faces(f, 1)) +
                    t * a.vertices.row(a.faces(f, 2));
  }
  const Eigen::VectorXd d = b.Distances(points);
  *mean_square = d.squaredNorm() / samples;
  *max = d.maxCoeff();
}

struct TwoSidedDistance {
  double rms = 0;  // sqrt of the mean of the two mean squares
  double max = 0;  // the larger of the two maxima (sampled Hausdorff)
};

// Both ways between `a` and `b`, `samples` points on each.
inline TwoSidedDistance MeasureTwoSided(const sdcb::TriangleMesh& a,
                                        const sdcb::MeshDistance& to_a,
                                        const sdcb::TriangleMesh& b,
                                        const sdcb::MeshDistance& to_b,
                                        int samples) {
  double ms1, max1, ms2, max2;
  OneSidedDistance(a, to_b, samples, &ms1, &max1);
  OneSidedDistance(b, to_a, samples, &ms2, &max2);
  return {std::sqrt(0.5 * (ms1 + ms2)), std::max(max1, max2)};
}

}  // namespace sdcb_bench

#endif  // SDCB_BENCH_GARLAND_HECKBERT_H_
