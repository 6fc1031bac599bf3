// Test meshes of open genus-0 parts: an ellipsoid (icosphere scaled) with
// caps cut out around given directions, so that the holes, their boundary
// loops and the kept region are known in closed form.
#ifndef SDCB_TESTS_TESTING_OPEN_SPHERE_H_
#define SDCB_TESTS_TESTING_OPEN_SPHERE_H_

#include <Eigen/Core>
#include <vector>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::testing {

struct Hole {
  Eigen::Vector3d direction;  // unit
  double cos_radius;          // faces whose centroid direction is closer cut
};

// The icosphere of `subdivisions` scaled by `axes`, without the faces whose
// centroid direction c has c . hole.direction > hole.cos_radius for some
// hole; the unreferenced vertices dropped (vertex order kept).
inline TriangleMesh OpenEllipsoid(int subdivisions, const Eigen::Vector3d& axes,
                                  const std::vector<Hole>& holes) {
  const TriangleMesh sphere = MakeIcosphere(subdivisions);
  std::vector<int> kept_faces;
  std::vector<int> used(sphere.num_vertices(), 0);
  for (int f = 0; f < sphere.num_faces(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) c += sphere.vertices.row(sphere.faces(f, k));
    c.normalize();
    bool cut = false;
    for (const Hole& h : holes) cut = cut || c.dot(h.direction) > h.cos_radius;
    if (cut) continue;
    kept_faces.push_back(f);
    for (int k = 0; k < 3; ++k) used[sphere.faces(f, k)] = 1;
  }
  std::vector<int> row(sphere.num_vertices(), -1);
  TriangleMesh out;
  int n = 0;
  for (int v = 0; v < sphere.num_vertices(); ++v) n += used[v];
  out.vertices.resize(n, 3);
  n = 0;
  for (int v = 0; v < sphere.num_vertices(); ++v) {
    if (!used[v]) continue;
    row[v] = n;
    out.vertices.row(n++) =
        sphere.vertices.row(v).cwiseProduct(axes.transpose());
  }
  out.faces.resize(static_cast<Eigen::Index>(kept_faces.size()), 3);
  for (size_t i = 0; i < kept_faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      out.faces(static_cast<Eigen::Index>(i), k) =
          row[sphere.faces(kept_faces[i], k)];
    }
  }
  return out;
}

// `a` and `b` side by side as one mesh (b's vertex rows after a's).
inline TriangleMesh Concatenated(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh out;
  out.vertices.resize(a.num_vertices() + b.num_vertices(), 3);
  out.vertices << a.vertices, b.vertices;
  out.faces.resize(a.num_faces() + b.num_faces(), 3);
  out.faces << a.faces, (b.faces.array() + a.num_vertices()).matrix();
  return out;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_OPEN_SPHERE_H_
