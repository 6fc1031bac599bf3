#include "sdcb/converters/cage_deviation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "sdcb/core/fit/surface_deviation.h"

namespace sdcb {
namespace {

// The parameter lattice of level n in one face: points (u, v) and triangles
// counter-clockwise in the (u, v) plane (so outward on the limit surface).
struct FaceLattice {
  std::vector<Eigen::Vector2d> uv;
  std::vector<Eigen::Vector3i> triangles;
};

FaceLattice MakeFaceLattice(bool triangle, int n) {
  FaceLattice l;
  std::vector<std::vector<int>> at(n + 1);
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= (triangle ? n - i : n); ++j) {
      at[i].push_back(static_cast<int>(l.uv.size()));
      l.uv.emplace_back(static_cast<double>(j) / n, static_cast<double>(i) / n);
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < (triangle ? n - i : n); ++j) {
      if (triangle) {
        l.triangles.emplace_back(at[i][j], at[i][j + 1], at[i + 1][j]);
        if (i + j < n - 1) {
          l.triangles.emplace_back(at[i][j + 1], at[i + 1][j + 1],
                                   at[i + 1][j]);
        }
      } else {
        l.triangles.emplace_back(at[i][j], at[i][j + 1], at[i + 1][j + 1]);
        l.triangles.emplace_back(at[i][j], at[i + 1][j + 1], at[i + 1][j]);
      }
    }
  }
  return l;
}

// Barycentric coordinates of q (a point of triangle a, b, c) .
Eigen::Vector3d TriangleCoordinates(const Eigen::Vector3d& q,
                                    const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  const Eigen::Vector3d e0 = b - a, e1 = c - a, d = q - a;
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0)) return Eigen::Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3);
  const double v = (d11 * d.dot(e0) - d01 * d.dot(e1)) / det;
  const double w = (d00 * d.dot(e1) - d01 * d.dot(e0)) / det;
  return Eigen::Vector3d(1.0 - v - w, v, w);
}

// (u, v) clamped into the face's domain.
void ClampToDomain(bool triangle, double* u, double* v) {
  *u = std::clamp(*u, 0.0, 1.0);
  *v = std::clamp(*v, 0.0, 1.0);
  if (triangle && *u + *v > 1.0) {
    const double excess = 0.5 * (*u + *v - 1.0);
    *u = std::clamp(*u - excess, 0.0, 1.0);
    *v = 1.0 - *u;
  }
}

}  // namespace

double ClosestOnLimitFace(const LimitSurface& limit,
                          const Eigen::MatrixX3d& cage, int f,
                          const Eigen::Vector3d& x, int iterations, double* u,
                          double* v) {
  const bool triangle = limit.scheme() == SubdivisionScheme::kLoop;
  ClampToDomain(triangle, u, v);
  Eigen::Vector3d pu, pv;
  Eigen::Vector3d p = limit.Evaluate(f, *u, *v, cage, &pu, &pv);
  double best = (p - x).norm();
  for (int it = 0; it < iterations && best > 0; ++it) {
    const Eigen::Vector3d r = p - x;
    Eigen::Matrix2d jtj;
    jtj << pu.dot(pu), pu.dot(pv), pu.dot(pv), pv.dot(pv);
    const double det = jtj.determinant();
    if (!(std::abs(det) > 1e-300)) break;
    Eigen::Vector2d step =
        -jtj.inverse() * Eigen::Vector2d(pu.dot(r), pv.dot(r));
    bool improved = false;
    for (int halving = 0; halving < 4; ++halving, step *= 0.5) {
      double nu = *u + step[0], nv = *v + step[1];
      ClampToDomain(triangle, &nu, &nv);
      Eigen::Vector3d qu, qv;
      const Eigen::Vector3d q = limit.Evaluate(f, nu, nv, cage, &qu, &qv);
      const double d = (q - x).norm();
      if (d < best) {
        best = d;
        *u = nu;
        *v = nv;
        p = q;
        pu = qu;
        pv = qv;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  return best;
}

StatusOr<CageDeviation> MeasureCageDeviation(
    const SphericalSpline& spline, const LimitSurface& limit,
    const Eigen::MatrixX3d& cage, const SphereCage* sphere,
    const CageDeviationOptions& options) {
  const int nf = limit.num_faces();
  if (cage.rows() != limit.num_vertices() ||
      (sphere && sphere->num_faces() != nf)) {
    return InvalidArgumentError(
        "cage deviation: the cage positions or the sphere layout do not "
        "match the limit surface");
  }
  if (!(options.length_unit > 0) || options.min_samples < 1 ||
      options.newton_iterations < 0) {
    return InvalidArgumentError(
        "cage deviation: the length unit must be > 0 and the sample count "
        ">= 1");
  }
  const bool triangle = limit.scheme() == SubdivisionScheme::kLoop;
  int n = 1;
  auto per_face = [&](int level) {
    return triangle ? (level + 1) * (level + 2) / 2 : (level + 1) * (level + 1);
  };
  while (static_cast<int64_t>(per_face(n)) * nf < options.min_samples) ++n;
  const FaceLattice lattice = MakeFaceLattice(triangle, n);
  const int np = static_cast<int>(lattice.uv.size());
  const int nt = static_cast<int>(lattice.triangles.size());
  const double to_percent = 100.0 / options.length_unit;

  // The limit lattice: exact limit points, unwelded (every face its own).
  TriangleMesh tessellation;
  tessellation.vertices.resize(static_cast<Eigen::Index>(nf) * np, 3);
  tessellation.faces.resize(static_cast<Eigen::Index>(nf) * nt, 3);
  Eigen::MatrixX3d candidates;
  if (sphere) candidates.resize(tessellation.vertices.rows(), 3);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, nf, 16),
      [&](const tbb::blocked_range<int>& range) {
        for (int f = range.begin(); f < range.end(); ++f) {
          const Eigen::Index base = static_cast<Eigen::Index>(f) * np;
          for (int k = 0; k < np; ++k) {
            const Eigen::Vector2d& uv = lattice.uv[k];
            tessellation.vertices.row(base + k) =
                limit.Evaluate(f, uv[0], uv[1], cage);
            if (sphere) {
              candidates.row(base + k) =
                  spline.Evaluate(sphere->SpherePoint(f, uv[0], uv[1]));
            }
          }
          for (int t = 0; t < nt; ++t) {
            tessellation.faces.row(static_cast<Eigen::Index>(f) * nt + t) =
                (lattice.triangles[t].array() + base)
                    .cast<int>()
                    .matrix()
                    .transpose();
          }
        }
      });

  DeviationOptions measure;
  measure.length_unit = options.length_unit;
  measure.min_surface_samples = options.min_samples;
  SDCB_ASSIGN_OR_RETURN(
      const SurfaceDeviation d,
      MeasureSurfaceDeviation(spline, tessellation, measure,
                              sphere ? &candidates : nullptr));

  CageDeviation out;
  out.lattice_level = n;
  out.limit_samples = tessellation.vertices.rows();
  out.spline_samples = d.surface_samples;
  out.limit_to_spline_rms_percent = d.mesh_to_surface_rms_percent;
  out.limit_to_spline_max_percent = d.mesh_to_surface_max_percent;
  out.folded_area_percent = d.folded_area_percent;
  out.limit_sample_points = tessellation.vertices;
  out.limit_sample_distance_percent = d.vertex_distance_percent;
  out.limit_sample_face.resize(out.limit_samples);
  out.limit_sample_uv.resize(out.limit_samples, 2);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < np; ++k) {
      const Eigen::Index i = static_cast<Eigen::Index>(f) * np + k;
      out.limit_sample_face[i] = f;
      out.limit_sample_uv.row(i) = lattice.uv[k].transpose();
    }
  }

  // Per face: area-weighted squared limit -> spline distances.
  out.face_rms_percent = Eigen::VectorXd::Zero(nf);
  out.face_max_percent = Eigen::VectorXd::Zero(nf);
  out.face_squared_error = Eigen::VectorXd::Zero(nf);
  {
    Eigen::VectorXd face_area = Eigen::VectorXd::Zero(nf);
    for (Eigen::Index t = 0; t < tessellation.faces.rows(); ++t) {
      const int f = static_cast<int>(t / nt);
      const Eigen::Vector3d a =
          tessellation.vertices.row(tessellation.faces(t, 0));
      const Eigen::Vector3d b =
          tessellation.vertices.row(tessellation.faces(t, 1));
      const Eigen::Vector3d c =
          tessellation.vertices.row(tessellation.faces(t, 2));
      const double area = 0.5 * (b - a).cross(c - a).norm();
      face_area[f] += area;
      for (int k = 0; k < 3; ++k) {
        const double e = d.vertex_distance_percent[tessellation.faces(t, k)];
        out.face_squared_error[f] += area / 3 * e * e;
      }
    }
    for (int f = 0; f < nf; ++f) {
      out.face_rms_percent[f] =
          face_area[f] > 0 ? std::sqrt(out.face_squared_error[f] / face_area[f])
                           : 0;
      out.face_max_percent[f] =
          d.vertex_distance_percent
              .segment(static_cast<Eigen::Index>(f) * np, np)
              .maxCoeff();
    }
  }

  // Spline -> limit: from the nearest point of the limit lattice (found by
  // the measurement above) to the foot point on the limit surface.
  const Eigen::MatrixX3d& spline_points = d.surface_sample_positions;
  const Eigen::Index ns = spline_points.rows();
  Eigen::VectorXd distance(ns);
  tbb::parallel_for(
      tbb::blocked_range<Eigen::Index>(0, ns, 256),
      [&](const tbb::blocked_range<Eigen::Index>& range) {
        for (Eigen::Index i = range.begin(); i < range.end(); ++i) {
          const Eigen::Vector3d x = spline_points.row(i).transpose();
          const int face = d.surface_sample_mesh_face[i];
          const int f = face / nt;
          const Eigen::Vector3i& t = lattice.triangles[face % nt];
          const Eigen::Index base = static_cast<Eigen::Index>(f) * np;
          const Eigen::Vector3d w = TriangleCoordinates(
              d.surface_sample_mesh_point.row(i).transpose(),
              tessellation.vertices.row(base + t[0]),
              tessellation.vertices.row(base + t[1]),
              tessellation.vertices.row(base + t[2]));
          Eigen::Vector2d uv = Eigen::Vector2d::Zero();
          for (int k = 0; k < 3; ++k) uv += w[k] * lattice.uv[t[k]];
          double u = uv[0], v = uv[1];
          distance[i] = to_percent *
                        ClosestOnLimitFace(limit, cage, f, x,
                                           options.newton_iterations, &u, &v);
        }
      });
  const Eigen::VectorXd& weight = d.surface_sample_weight;
  const double area = weight.sum();
  out.spline_to_limit_rms_percent =
      area > 0 ? std::sqrt(weight.dot(distance.cwiseAbs2()) / area) : 0;
  out.spline_to_limit_max_percent = ns > 0 ? distance.maxCoeff() : 0;
  out.spline_sample_points = spline_points;
  out.spline_sample_distance_percent = distance;
  out.rms_percent = std::sqrt(
      0.5 *
      (out.limit_to_spline_rms_percent * out.limit_to_spline_rms_percent +
       out.spline_to_limit_rms_percent * out.spline_to_limit_rms_percent));
  out.max_percent = std::max(out.limit_to_spline_max_percent,
                             out.spline_to_limit_max_percent);
  return out;
}

}  // namespace sdcb
