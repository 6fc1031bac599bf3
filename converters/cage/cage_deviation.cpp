#include "sdcb/converters/cage/cage_deviation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "sdcb/core/measure/closest_surface_points.h"
#include "sdcb/core/measure/sample_lattice.h"
#include "sdcb/core/measure/triangle_distance.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_distance.h"

namespace sdcb {
namespace {

// The parameter lattice of level n in one face (core/measure/sample_lattice.h,
// (u, v) = (j, i) / n): points (u, v) and triangles counter-clockwise in the
// (u, v) plane (so outward on the limit surface).
struct FaceLattice {
  std::vector<Eigen::Vector2d> uv;
  std::vector<Eigen::Vector3i> triangles;
};

FaceLattice MakeFaceLattice(bool triangle, int n) {
  FaceLattice l;
  const auto take = [&](const auto& lattice) {
    for (const Eigen::Vector2i& ij : lattice.points) {
      l.uv.emplace_back(static_cast<double>(ij[1]) / n,
                        static_cast<double>(ij[0]) / n);
    }
    l.triangles = lattice.triangles;
  };
  if (triangle) {
    take(TriangleLattice(n, LatticeOrientation::kJI));
  } else {
    take(SquareLattice(n));
  }
  return l;
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

double ClosestOnLimitFace(const PreparedLimit& limit, int f,
                          const Eigen::Vector3d& x, int iterations, double* u,
                          double* v) {
  const bool triangle = limit.limit().scheme() == SubdivisionScheme::kLoop;
  ClampToDomain(triangle, u, v);
  ChartPoint start;
  start.position = limit.Evaluate(f, *u, *v, &start.du, &start.dv);
  double nu = *u, nv = *v;
  return GaussNewtonClosest(
      x, start, iterations, 0.0,
      [&](const Eigen::Vector2d& step, ChartPoint* point) {
        nu = *u + step[0];
        nv = *v + step[1];
        ClampToDomain(triangle, &nu, &nv);
        point->position = limit.Evaluate(f, nu, nv, &point->du, &point->dv);
      },
      [&] {
        *u = nu;
        *v = nv;
      });
}

StatusOr<SplineImage> SplineImage::Create(const SurfaceSampler& spline,
                                          int level) {
  if (level < 0 || level > 9) {
    return InvalidArgumentError("spline image: the level must be in 0..9");
  }
  TriangleMesh sphere = MakeIcosphere(level);
  const Eigen::Index nv = sphere.vertices.rows();
  const Eigen::Index nt = sphere.faces.rows();
  // The vertices and the triangles' centroids' sphere points.
  Eigen::MatrixX3d directions(nv + nt, 3);
  directions.topRows(nv) = sphere.vertices;
  for (Eigen::Index t = 0; t < nt; ++t) {
    directions.row(nv + t) = (sphere.vertices.row(sphere.faces(t, 0)) +
                              sphere.vertices.row(sphere.faces(t, 1)) +
                              sphere.vertices.row(sphere.faces(t, 2)))
                                 .normalized();
  }
  Eigen::MatrixX3d points;
  spline.Sample(directions, &points, nullptr);
  TriangleMesh image;
  image.vertices = points.topRows(nv);
  image.faces = sphere.faces;
  Eigen::VectorXd chord(nt);
  for (Eigen::Index t = 0; t < nt; ++t) {
    chord[t] = (points.row(nv + t) - (image.vertices.row(image.faces(t, 0)) +
                                      image.vertices.row(image.faces(t, 1)) +
                                      image.vertices.row(image.faces(t, 2))) /
                                         3.0)
                   .norm();
  }
  SDCB_ASSIGN_OR_RETURN(MeshDistance tree, MeshDistance::Create(image));
  return SplineImage(std::move(sphere), std::move(image), std::move(tree),
                     std::move(chord));
}

Eigen::Vector3d SplineImage::NearestDirection(const Eigen::Vector3d& x,
                                              double* distance,
                                              double* chord) const {
  const MeshDistance::Closest c = tree_.Find(x);
  *distance = c.distance;
  *chord = chord_[c.face];
  Eigen::Vector3d corner[3];
  for (int k = 0; k < 3; ++k)
    corner[k] = image_.vertices.row(image_.faces(c.face, k));
  const Eigen::Vector3d w =
      TriangleCoordinates(c.point, corner[0], corner[1], corner[2]);
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    d += w[k] * sphere_.vertices.row(sphere_.faces(c.face, k)).transpose();
  }
  return d.normalized();
}

namespace {

// Both lattices of level n in every face, unwelded (every face its own
// points): the limit points, the sphere points and the spline there with
// its normals; the triangles are shared.
struct CageLattices {
  FaceLattice lattice;  // per face
  int level = 0;
  TriangleMesh limit_mesh, spline_mesh;
  Eigen::MatrixX3d directions, spline_normals;
};

CageLattices BuildLattices(const SurfaceSampler& spline,
                           const PreparedLimit& prepared,
                           const SphereCage& sphere, bool triangle, int nf,
                           int min_samples) {
  CageLattices l;
  int n = 1;
  auto per_face = [&](int level) {
    return triangle ? TriangleLattice::NumPoints(level)
                    : SquareLattice::NumPoints(level);
  };
  while (static_cast<int64_t>(per_face(n)) * nf < min_samples) ++n;
  l.level = n;
  l.lattice = MakeFaceLattice(triangle, n);
  const FaceLattice& lattice = l.lattice;
  const int np = static_cast<int>(lattice.uv.size());
  const int nt = static_cast<int>(lattice.triangles.size());
  const Eigen::Index ns = static_cast<Eigen::Index>(nf) * np;
  l.limit_mesh.vertices.resize(ns, 3);
  l.limit_mesh.faces.resize(static_cast<Eigen::Index>(nf) * nt, 3);
  l.directions.resize(ns, 3);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, nf, 16),
      [&](const tbb::blocked_range<int>& range) {
        for (int f = range.begin(); f < range.end(); ++f) {
          const Eigen::Index base = static_cast<Eigen::Index>(f) * np;
          for (int k = 0; k < np; ++k) {
            const Eigen::Vector2d& uv = lattice.uv[k];
            l.limit_mesh.vertices.row(base + k) =
                prepared.Evaluate(f, uv[0], uv[1]);
            l.directions.row(base + k) = sphere.SpherePoint(f, uv[0], uv[1]);
          }
          for (int t = 0; t < nt; ++t) {
            l.limit_mesh.faces.row(static_cast<Eigen::Index>(f) * nt + t) =
                (lattice.triangles[t].array() + base)
                    .cast<int>()
                    .matrix()
                    .transpose();
          }
        }
      });
  spline.Sample(l.directions, &l.spline_mesh.vertices, &l.spline_normals);
  l.spline_mesh.faces = l.limit_mesh.faces;
  return l;
}

// Limit -> spline (length units): searches from the sample's sphere point,
// then, where that ends more than 1 % farther than the nearest point y of
// the spline's image plus half the image's chord there, or farther than
// the spline at y's sphere point, from that sphere point. Sets
// `*searches_from_image`.
Eigen::VectorXd LimitToSpline(const SurfaceSampler& spline,
                              const SplineImage& image, const CageLattices& l,
                              int iterations, int64_t* searches_from_image) {
  const Eigen::MatrixX3d& limit_points = l.limit_mesh.vertices;
  const Eigen::Index ns = limit_points.rows();
  Eigen::MatrixX3d starts = l.directions;
  Eigen::VectorXd limit_distance =
      ClosestSurfacePoints(spline, limit_points, iterations, &starts);
  Eigen::MatrixX3d image_starts(ns, 3);
  Eigen::VectorXd image_distance(ns), chord(ns);
  tbb::parallel_for(
      tbb::blocked_range<Eigen::Index>(0, ns, 256),
      [&](const tbb::blocked_range<Eigen::Index>& range) {
        for (Eigen::Index i = range.begin(); i < range.end(); ++i) {
          image_starts.row(i) = image.NearestDirection(
              limit_points.row(i).transpose(), &image_distance[i], &chord[i]);
        }
      });
  Eigen::MatrixX3d image_points;
  spline.Sample(image_starts, &image_points, nullptr);
  std::vector<Eigen::Index> again;
  for (Eigen::Index i = 0; i < ns; ++i) {
    if (limit_distance[i] > 1.01 * image_distance[i] + 0.5 * chord[i] ||
        (image_points.row(i) - limit_points.row(i)).norm() <
            limit_distance[i]) {
      again.push_back(i);
    }
  }
  if (!again.empty()) {
    const Eigen::Index m = static_cast<Eigen::Index>(again.size());
    Eigen::MatrixX3d x(m, 3), retry(m, 3);
    for (Eigen::Index j = 0; j < m; ++j) {
      x.row(j) = limit_points.row(again[j]);
      retry.row(j) = image_starts.row(again[j]);
    }
    const Eigen::VectorXd d =
        ClosestSurfacePoints(spline, x, 2 * iterations, &retry);
    for (Eigen::Index j = 0; j < m; ++j) {
      limit_distance[again[j]] = std::min(limit_distance[again[j]], d[j]);
    }
  }
  *searches_from_image = static_cast<int64_t>(again.size());
  return limit_distance;
}

// The limit -> spline fields and figures of `out` from the samples'
// distances (percent), with the per-face ones.
void SummarizeLimitSide(const CageLattices& l, int nf,
                        const Eigen::VectorXd& limit_distance,
                        CageDeviation* out) {
  // A third of each lattice triangle's area to each of its corners.
  const Eigen::VectorXd limit_weight = VertexAreas(l.limit_mesh);
  const Eigen::Index ns = limit_distance.size();
  const int np = static_cast<int>(l.lattice.uv.size());
  out->lattice_level = l.level;
  out->limit_samples = ns;
  out->spline_samples = ns;
  const double limit_area = limit_weight.sum();
  out->limit_to_spline_rms_percent =
      limit_area > 0
          ? std::sqrt(limit_weight.dot(limit_distance.cwiseAbs2()) / limit_area)
          : 0;
  out->limit_to_spline_max_percent = limit_distance.maxCoeff();
  out->limit_sample_points = l.limit_mesh.vertices;
  out->limit_sample_distance_percent = limit_distance;
  out->limit_sample_face.resize(ns);
  out->limit_sample_uv.resize(ns, 2);
  out->face_rms_percent = Eigen::VectorXd::Zero(nf);
  out->face_max_percent = Eigen::VectorXd::Zero(nf);
  out->face_squared_error = Eigen::VectorXd::Zero(nf);
  for (int f = 0; f < nf; ++f) {
    double area = 0;
    for (int k = 0; k < np; ++k) {
      const Eigen::Index i = static_cast<Eigen::Index>(f) * np + k;
      out->limit_sample_face[i] = f;
      out->limit_sample_uv.row(i) = l.lattice.uv[k].transpose();
      out->face_squared_error[f] +=
          limit_weight[i] * limit_distance[i] * limit_distance[i];
      area += limit_weight[i];
    }
    out->face_rms_percent[f] =
        area > 0 ? std::sqrt(out->face_squared_error[f] / area) : 0;
    out->face_max_percent[f] =
        limit_distance.segment(static_cast<Eigen::Index>(f) * np, np)
            .maxCoeff();
  }
}

// Spline -> limit: from the nearest point of the limit lattice to the foot
// point on the limit surface; folded where the limit's normal there opposes
// the spline's. Sets the spline side's fields and figures of `out` (whose
// limit samples' (u, v) are set) and the two-sided ones.
Status SplineToLimit(const PreparedLimit& prepared, const CageLattices& l,
                     const CageDeviationOptions& options, CageDeviation* out) {
  SDCB_ASSIGN_OR_RETURN(const MeshDistance to_limit_image,
                        MeshDistance::Create(l.limit_mesh));
  const FaceLattice& lattice = l.lattice;
  const int np = static_cast<int>(lattice.uv.size());
  const int nt = static_cast<int>(lattice.triangles.size());
  const Eigen::Index ns = l.spline_mesh.vertices.rows();
  const double to_percent = 100.0 / options.length_unit;
  Eigen::VectorXd distance(ns);
  std::vector<char> folded(ns, 0);
  tbb::parallel_for(
      tbb::blocked_range<Eigen::Index>(0, ns, 256),
      [&](const tbb::blocked_range<Eigen::Index>& range) {
        for (Eigen::Index i = range.begin(); i < range.end(); ++i) {
          const Eigen::Vector3d x = l.spline_mesh.vertices.row(i).transpose();
          const MeshDistance::Closest c = to_limit_image.Find(x);
          const int f = c.face / nt;
          const Eigen::Vector3i& t = lattice.triangles[c.face % nt];
          const Eigen::Index base = static_cast<Eigen::Index>(f) * np;
          const Eigen::Vector3d w = TriangleCoordinates(
              c.point, l.limit_mesh.vertices.row(base + t[0]),
              l.limit_mesh.vertices.row(base + t[1]),
              l.limit_mesh.vertices.row(base + t[2]));
          Eigen::Vector2d uv = Eigen::Vector2d::Zero();
          for (int k = 0; k < 3; ++k) uv += w[k] * lattice.uv[t[k]];
          double u = uv[0], v = uv[1];
          const double d = ClosestOnLimitFace(
              prepared, f, x, options.newton_iterations, &u, &v);
          const double own =
              (l.limit_mesh.vertices.row(i).transpose() - x).norm();
          Eigen::Vector3d du, dv;
          if (own < d) {
            distance[i] = to_percent * own;
            const Eigen::Index at = i / np;
            prepared.Evaluate(static_cast<int>(at), out->limit_sample_uv(i, 0),
                              out->limit_sample_uv(i, 1), &du, &dv);
          } else {
            distance[i] = to_percent * d;
            prepared.Evaluate(f, u, v, &du, &dv);
          }
          folded[i] = du.cross(dv).dot(l.spline_normals.row(i).transpose()) < 0;
        }
      });
  const Eigen::VectorXd weight = VertexAreas(l.spline_mesh);
  const double area = weight.sum();
  double folded_area = 0;
  for (Eigen::Index i = 0; i < ns; ++i) {
    if (folded[i]) folded_area += weight[i];
  }
  out->folded_area_percent = area > 0 ? 100.0 * folded_area / area : 0;
  out->spline_to_limit_rms_percent =
      area > 0 ? std::sqrt(weight.dot(distance.cwiseAbs2()) / area) : 0;
  out->spline_to_limit_max_percent = ns > 0 ? distance.maxCoeff() : 0;
  out->spline_sample_points = l.spline_mesh.vertices;
  out->spline_sample_distance_percent = distance;
  out->rms_percent = std::sqrt(
      0.5 *
      (out->limit_to_spline_rms_percent * out->limit_to_spline_rms_percent +
       out->spline_to_limit_rms_percent * out->spline_to_limit_rms_percent));
  out->max_percent = std::max(out->limit_to_spline_max_percent,
                              out->spline_to_limit_max_percent);
  return Status::Ok();
}

}  // namespace

StatusOr<CageDeviation> MeasureCageDeviation(
    const SurfaceSampler& spline, const LimitSurface& limit,
    const Eigen::MatrixX3d& cage, const SphereCage& sphere,
    const CageDeviationOptions& options, const SplineImage* image) {
  const int nf = limit.num_faces();
  if (cage.rows() != limit.num_vertices() || sphere.num_faces() != nf) {
    return InvalidArgumentError(
        "cage deviation: the cage positions or the sphere layout do not "
        "match the limit surface");
  }
  if (!(options.length_unit > 0) || options.min_samples < 1 ||
      options.newton_iterations < 0 || options.spline_iterations < 0) {
    return InvalidArgumentError(
        "cage deviation: the length unit must be > 0 and the sample count "
        ">= 1");
  }
  const bool triangle = limit.scheme() == SubdivisionScheme::kLoop;
  const PreparedLimit prepared(limit, cage);
  const CageLattices lattices = BuildLattices(
      spline, prepared, sphere, triangle, nf, options.min_samples);
  StatusOr<SplineImage> own_image = InvalidArgumentError("not made");
  if (image == nullptr) {
    own_image = SplineImage::Create(spline);
    if (!own_image.ok()) return own_image.status();
    image = &*own_image;
  }
  CageDeviation out;
  Eigen::VectorXd limit_distance =
      LimitToSpline(spline, *image, lattices, options.spline_iterations,
                    &out.limit_searches_from_image);
  limit_distance *= 100.0 / options.length_unit;
  SummarizeLimitSide(lattices, nf, limit_distance, &out);
  SDCB_RETURN_IF_ERROR(SplineToLimit(prepared, lattices, options, &out));
  return out;
}

}  // namespace sdcb
