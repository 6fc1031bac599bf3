// Test meshes of open genus-0 parts: an ellipsoid (icosphere scaled) with
// caps cut out around given directions, so that the holes, their boundary
// loops and the kept region are known in closed form.
#ifndef SDCB_TESTS_TESTING_OPEN_SPHERE_H_
#define SDCB_TESTS_TESTING_OPEN_SPHERE_H_

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "testing/icosphere_patches.h"

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
  TriangleMesh out =
      Submesh(sphere, FacesWhere(sphere, [&](const Eigen::Vector3d& c) {
                for (const Hole& h : holes) {
                  if (c.dot(h.direction) > h.cos_radius) return false;
                }
                return true;
              }));
  out.vertices = out.vertices * axes.asDiagonal();
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

// A torus (genus 1) of n x m quads, each cut into two triangles, oriented
// outward: tube radius 1 around a circle of radius `major` centred at
// (shift_x, 0, 0) in the xy plane.
inline TriangleMesh GridTorus(int n, int m, double major, double shift_x) {
  TriangleMesh torus;
  torus.vertices.resize(n * m, 3);
  torus.faces.resize(2 * n * m, 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double a = 2 * kPi * i / n, b = 2 * kPi * j / m;
      torus.vertices.row(i * m + j)
          << shift_x + (major + std::cos(b)) * std::cos(a),
          (major + std::cos(b)) * std::sin(a), std::sin(b);
      const int v00 = i * m + j, v10 = ((i + 1) % n) * m + j;
      const int v01 = i * m + (j + 1) % m,
                v11 = ((i + 1) % n) * m + (j + 1) % m;
      torus.faces.row(2 * (i * m + j)) << v00, v10, v11;
      torus.faces.row(2 * (i * m + j) + 1) << v00, v11, v01;
    }
  }
  return torus;
}

// Three triangles on one edge (not manifold), around (x, 0, 0), with
// coordinates no float holds exactly.
inline TriangleMesh NonManifoldFan(double x) {
  TriangleMesh fan;
  fan.vertices.resize(5, 3);
  fan.vertices << x, 0, 0, x + 1.1, 0, 0, x + 0.3, 0.9, 0.1, x + 0.7, -0.3, 0.7,
      x + 0.6, -0.2, -0.9;
  fan.faces.resize(3, 3);
  fan.faces << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  return fan;
}

// Part 1 a closed ellipsoid (axes 1, 0.8, 0.6; fittable), part 2 a torus of
// 96 triangles around it (genus 1), part 3 NonManifoldFan(10).
inline TriangleMesh SphereTorusFan() {
  const TriangleMesh ellipsoid =
      OpenEllipsoid(2, Eigen::Vector3d(1.0, 0.8, 0.6), {});
  return Concatenated(Concatenated(ellipsoid, GridTorus(8, 6, 3.0, 0.0)),
                      NonManifoldFan(10.0));
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_OPEN_SPHERE_H_
