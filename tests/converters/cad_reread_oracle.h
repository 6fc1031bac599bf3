// The oracle of the CAD export's tests and of bench/cad_reread_bench: a STEP
// or IGES file re-read by OpenCASCADE (testing/occt_reread.h) against the
// spline it came from, by closest-point searches instead of a fine adaptive
// tessellation.
#ifndef SDCB_TESTS_CONVERTERS_CAD_REREAD_ORACLE_H_
#define SDCB_TESTS_CONVERTERS_CAD_REREAD_ORACLE_H_

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "testing/occt_reread.h"

namespace sdcb::testing {

struct RereadComparison {
  bool ok = false;
  double spline_volume = 0.0, spline_area = 0.0;
  double to_spline_percent = 0.0, from_spline_percent = 0.0;
  int64_t surface_points = 0, spline_points = 0;
};

// The re-read surfaces against the spline, in the frame
// `transform` maps the spline to (the input's, for a model's file);
// distances in percent of transform.scale, volume and area in that frame:
// - the spline's volume (unsigned) and area from its uniform tessellation of
//   `level` (6: 40,962 vertices by the exact evaluator; relative error ~1e-4
//   on a smooth model, 1e-3 on the bunny's ears, 4 times less per level);
// - re-read surfaces -> spline at >= `surface_points` exact points x of the
//   re-read surfaces: the closest point of that tessellation gives a sphere
//   direction, from which Gauss-Newton steps (finite differences on
//   PiecewiseSurface) go to a foot point u; |x - S(u)|, S by the exact
//   evaluator, is the distance to a point of the spline, an upper bound of
//   the true distance;
// - spline -> re-read surfaces at `spline_points` vertices of the
//   tessellation: the nearest re-read lattice triangle names a face, and
//   OpenCASCADE projects the point onto that face's surface (or the
//   triangle's nearest lattice vertex, an exact surface point, is nearer).
inline RereadComparison CompareRereadWithSpline(
    const RereadShape& r, const SphericalSpline& spline, int64_t surface_points,
    int64_t spline_points,
    const NormalizingTransform& transform = NormalizingTransform(),
    int level = 6) {
  RereadComparison c;
  const TriangleMesh sphere = MakeIcosphere(level);
  TriangleMesh tessellation;
  tessellation.vertices =
      transform.ToInput(spline.EvaluateMany(sphere.vertices));
  tessellation.faces = sphere.faces;
  for (Eigen::Index k = 0; k < sphere.faces.rows(); ++k) {
    const Eigen::Vector3d a = tessellation.vertices.row(sphere.faces(k, 0));
    const Eigen::Vector3d b = tessellation.vertices.row(sphere.faces(k, 1));
    const Eigen::Vector3d d = tessellation.vertices.row(sphere.faces(k, 2));
    c.spline_volume += a.dot(b.cross(d)) / 6.0;
    c.spline_area += 0.5 * (b - a).cross(d - a).norm();
  }
  // A model fitted to a mesh whose faces point inward has a mirrored sphere
  // map; the solid is outward either way.
  c.spline_volume = std::abs(c.spline_volume);
  const int n = static_cast<int>(
      std::ceil(std::sqrt(static_cast<double>(surface_points) / r.faces)));
  const SurfaceLattice lattice = SampleSurfaces(r, n);
  const Eigen::MatrixX3d& x = lattice.mesh.vertices;  // the frame's
  c.surface_points = x.rows();
  auto spline_mesh = MeshDistance::Create(tessellation);
  if (!spline_mesh.ok()) return c;
  Eigen::MatrixX3d u(x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const MeshDistance::Closest closest = spline_mesh->Find(x.row(i));
    Eigen::Vector3d corner[3], direction[3];
    for (int k = 0; k < 3; ++k) {
      corner[k] = tessellation.vertices.row(sphere.faces(closest.face, k));
      direction[k] = sphere.vertices.row(sphere.faces(closest.face, k));
    }
    // Barycentric coordinates of the closest point.
    const Eigen::Vector3d e0 = corner[1] - corner[0],
                          e1 = corner[2] - corner[0];
    const Eigen::Vector3d q = closest.point - corner[0];
    const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
    const double det = d00 * d11 - d01 * d01;
    const double b1 = det > 0 ? (d11 * q.dot(e0) - d01 * q.dot(e1)) / det : 0;
    const double b2 = det > 0 ? (d00 * q.dot(e1) - d01 * q.dot(e0)) / det : 0;
    u.row(i) =
        ((1 - b1 - b2) * direction[0] + b1 * direction[1] + b2 * direction[2])
            .normalized();
  }
  const PiecewiseSurface pieces(spline);
  const double h = 1e-6;
  for (int iteration = 0; iteration < 5; ++iteration) {
    Eigen::MatrixX3d probe(3 * x.rows(), 3), eu(x.rows(), 3), ev(x.rows(), 3);
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      Eigen::Vector3d a, b;
      TangentFrame(u.row(i).transpose(), &a, &b);
      eu.row(i) = a;
      ev.row(i) = b;
      probe.row(3 * i) = u.row(i);
      probe.row(3 * i + 1) = (u.row(i).transpose() + h * a).normalized();
      probe.row(3 * i + 2) = (u.row(i).transpose() + h * b).normalized();
    }
    Eigen::MatrixX3d s;
    pieces.EvaluateMany(probe, &s, nullptr);
    s = transform.ToInput(s);
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      const Eigen::Vector3d s0 = s.row(3 * i).transpose();
      Eigen::Matrix<double, 3, 2> j;
      j.col(0) = (s.row(3 * i + 1).transpose() - s0) / h;
      j.col(1) = (s.row(3 * i + 2).transpose() - s0) / h;
      const Eigen::Vector2d step =
          (j.transpose() * j)
              .ldlt()
              .solve(j.transpose() * (x.row(i).transpose() - s0));
      if (!step.allFinite() || step.norm() > 0.1) continue;
      u.row(i) = (u.row(i).transpose() + step[0] * eu.row(i).transpose() +
                  step[1] * ev.row(i).transpose())
                     .normalized();
    }
  }
  const double percent = 100.0 / transform.scale;
  c.to_spline_percent =
      percent * (transform.ToInput(spline.EvaluateMany(u)) - x)
                    .rowwise()
                    .norm()
                    .maxCoeff();

  auto surface_mesh = MeshDistance::Create(lattice.mesh);
  if (!surface_mesh.ok()) return c;
  const Eigen::Index stride =
      std::max<Eigen::Index>(1, tessellation.vertices.rows() / spline_points);
  for (Eigen::Index s = 0; s < tessellation.vertices.rows(); s += stride) {
    const Eigen::Vector3d p = tessellation.vertices.row(s);
    const MeshDistance::Closest closest = surface_mesh->Find(p);
    double best = DistanceToFace(r, lattice.triangle_face[closest.face], p);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d v =
          lattice.mesh.vertices.row(lattice.mesh.faces(closest.face, k));
      best = std::min(best, (v - p).norm());
    }
    c.from_spline_percent = std::max(c.from_spline_percent, percent * best);
    ++c.spline_points;
  }
  c.ok = true;
  return c;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_CONVERTERS_CAD_REREAD_ORACLE_H_
