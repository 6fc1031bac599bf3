#include "sdcb/core/tessellate/sampled_certificate.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/measure/triangle_distance.h"

namespace sdcb {
namespace {

// A sample may be measured against a neighbour's triangle only within this
// fraction of the face's longest edge from its own triangle (farther, it is
// not a sideways shear but a face that does not fit).
constexpr double kShearFraction = 1.0;

// The index of the face (among `planes`, three edge planes per face) whose
// spherical triangle contains direction d; on rounding ties the face where
// d is least outside.
int ContainingFace(const std::vector<std::array<Eigen::Vector3d, 3>>& planes,
                   const Eigen::Vector3d& d) {
  int best = 0;
  double best_inside = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < planes.size(); ++k) {
    const double inside = std::min(
        {planes[k][0].dot(d), planes[k][1].dot(d), planes[k][2].dot(d)});
    if (inside >= 0.0) return static_cast<int>(k);
    if (inside > best_inside) {
      best_inside = inside;
      best = static_cast<int>(k);
    }
  }
  return best;
}

}  // namespace

struct SampledFaces::Geometry {
  Eigen::Vector3d pa, pb, pc;
  Eigen::Vector3d normal;  // unit flat normal
  double shear_limit = 0.0;
  bool angular = false;
  // The triangles across the edges, found when a sample first needs them:
  // of the change `change` (if not null) or the pattern's.
  const SphereTriangulation::Face* face = nullptr;
  const FaceChange* change = nullptr;
  bool across_found = false;
  std::array<std::array<Eigen::Vector3d, 3>, 3> across;
  std::array<bool, 3> has_across{{false, false, false}};
};

SampledFaces::SampledFaces(SurfaceSamples* samples,
                           const CertificateOptions& options)
    : samples_(samples),
      options_(options),
      cos_angle_(std::cos(options.angle_degrees * kPi / 180.0)),
      test_angle_(options.angle_degrees < 180.0) {
  Resize();
}

void SampledFaces::SetLattice(const SurfaceSampler* surface, int order) {
  lattice_surface_ = order > 0 ? surface : nullptr;
  lattice_weights_.clear();
  for (int i = 0; i <= order; ++i)
    for (int j = 0; i + j <= order; ++j) {
      const int k = order - i - j;
      if (i == order || j == order || k == order) continue;
      lattice_weights_.emplace_back(double(i) / order, double(j) / order,
                                    double(k) / order);
    }
}

void SampledFaces::StartFromCoarse() {
  SurfaceSamples& s = *samples_;
  const int nv = s.pattern.num_vertices();
  const int nf = static_cast<int>(s.coarse_faces.size());
  Eigen::MatrixX3d directions(nv, 3);
  for (int v = 0; v < nv; ++v) directions.row(v) = s.pattern.vertex(v);
  Eigen::MatrixX3i faces(nf, 3);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) faces(f, k) = s.coarse_faces[f][k];
  }
  // The coarse faces are a triangulation of the sphere (a pattern the
  // dense one refines): FromFaces accepts them.
  SphereTriangulation coarse =
      SphereTriangulation::FromFaces(directions, faces, true).value();
  if (s.pattern.has_features()) {
    // The coarse pattern refines the same arcs (splits keep them).
    std::vector<int> arc(nv);
    for (int v = 0; v < nv; ++v) arc[v] = s.pattern.vertex_arc(v);
    coarse.SetFeatures(s.pattern.arc_ends(), std::move(arc));
  }
  s.pattern = std::move(coarse);
  inside_.assign(nf, {});
  errors_.assign(nf, 0.0);
  worst_.assign(nf, -1);
  leans_.assign(nf, 0);
  std::vector<std::vector<int>> members(nf);
  for (int v = 0; v < nv; ++v) {
    if (s.coarse_face_of[v] >= 0) members[s.coarse_face_of[v]].push_back(v);
  }
  tbb::parallel_for(0, nf, [&](int f) {
    FaceChange change;
    change.faces = {s.pattern.face(f)};
    change.slots = {f};
    change.freed.swap(members[f]);
    ChangeResult result;
    Measure(change, std::numeric_limits<double>::infinity(), true, &result);
    inside_[f].swap(result.samples[0]);
    errors_[f] = result.errors[0];
    worst_[f] = result.worst_sample[0];
    leans_[f] = result.leans[0];
  });
}

void SampledFaces::Resize() {
  const size_t n = samples_->pattern.num_face_slots();
  inside_.resize(n);
  errors_.resize(n, 0.0);
  worst_.resize(n, -1);
  leans_.resize(n, 0);
}

bool SampledFaces::MakeGeometry(const SphereTriangulation::Face& t,
                                Geometry* g) const {
  const auto& p = samples_->positions;
  const auto& n = samples_->normals;
  g->pa = p[t[0]];
  g->pb = p[t[1]];
  g->pc = p[t[2]];
  g->has_across = {false, false, false};
  g->across_found = false;
  g->face = &t;
  g->change = nullptr;
  const Eigen::Vector3d cross = (g->pb - g->pa).cross(g->pc - g->pa);
  const double area2 = cross.norm();
  const double longest = std::sqrt(
      std::max({(g->pa - g->pb).squaredNorm(), (g->pb - g->pc).squaredNorm(),
                (g->pc - g->pa).squaredNorm()}));
  g->angular = test_angle_ && longest > options_.tolerance;
  if (!(area2 > 0.0)) {
    g->normal.setZero();
    g->shear_limit = 0.0;
    return false;
  }
  g->normal = cross / area2;
  g->shear_limit = kShearFraction * longest;
  // The flat face must face the way the surface does at its corners, and
  // within the angle of it where the angular test applies.
  const double least = g->angular ? cos_angle_ : 0.0;
  for (int k = 0; k < 3; ++k) {
    const double c = g->normal.dot(n[t[k]]);
    if ((c <= 0.0 || c < least) && !n[t[k]].isZero(0.0)) return false;
  }
  return true;
}

void SampledFaces::FillAcross(Geometry* g) const {
  const SphereTriangulation& pattern = samples_->pattern;
  const SphereTriangulation::Face& t = *g->face;
  const FaceChange* change = g->change;
  g->across_found = true;
  for (int e = 0; e < 3; ++e) {
    const int p = t[e], q = t[(e + 1) % 3];
    const int* u = nullptr;
    if (change) {
      // A new face with q -> p, else the face across an old face's p -> q
      // (the change's boundary).
      for (const auto& x : change->faces) {
        for (int k = 0; k < 3 && !u; ++k) {
          if (x[k] == q && x[(k + 1) % 3] == p) u = x.data();
        }
        if (u) break;
      }
      for (size_t i = 0; i < change->old_faces.size() && !u; ++i) {
        const int f = change->old_faces[i];
        for (int k = 0; k < 3 && !u; ++k) {
          const int h = 3 * f + k;
          if (pattern.Origin(h) == p && pattern.Target(h) == q) {
            u = pattern.face(pattern.Twin(h) / 3).data();
          }
        }
      }
    }
    if (!u) {
      const int h = pattern.HalfEdge(q, p);
      if (h < 0) continue;
      u = pattern.face(h / 3).data();
    }
    g->has_across[e] = true;
    for (int c = 0; c < 3; ++c) g->across[e][c] = samples_->positions[u[c]];
  }
}

double SampledFaces::Distance(Geometry& g, const Eigen::Vector3d& q,
                              const Eigen::Vector3d* normal, double threshold,
                              bool* leaned) const {
  double d = PointTriangleDistance(q, g.pa, g.pb, g.pc);
  int nearest = -1;  // the own triangle, or the edge across which
  if (d > threshold && d <= g.shear_limit) {
    if (!g.across_found) FillAcross(&g);
    for (int e = 0; e < 3; ++e) {
      if (!g.has_across[e]) continue;
      const auto& u = g.across[e];
      const double across = PointTriangleDistance(q, u[0], u[1], u[2]);
      if (across < d) {
        d = across;
        nearest = e;
        *leaned = true;
      }
    }
  }
  // The normal test against the triangle the point is measured to.
  if (normal && g.angular && !normal->isZero(0.0)) {
    Eigen::Vector3d n = g.normal;
    if (nearest >= 0) {
      const auto& u = g.across[nearest];
      n = (u[1] - u[0]).cross(u[2] - u[0]).normalized();
    }
    if (!(n.dot(*normal) >= cos_angle_)) {
      return std::numeric_limits<double>::infinity();
    }
  }
  return d;
}

bool SampledFaces::Evaluate(const FaceChange& change, double threshold,
                            ChangeResult* result) const {
  return Measure(change, threshold, false, result);
}

void SampledFaces::Reassign(const FaceChange& change) {
  ChangeResult result;
  Measure(change, std::numeric_limits<double>::infinity(), true, &result);
  result.outer.clear();
  Apply(change, &result);
}

bool SampledFaces::Measure(const FaceChange& change, double threshold,
                           bool force, ChangeResult* result) const {
  const SphereTriangulation& pattern = samples_->pattern;
  const size_t nk = change.faces.size();
  thread_local std::vector<Geometry> geometry;
  thread_local std::vector<std::array<Eigen::Vector3d, 3>> planes;
  geometry.resize(nk);
  planes.resize(nk);
  result->failed_at = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < nk; ++k) {
    const SphereTriangulation::Face& t = change.faces[k];
    if (!MakeGeometry(t, &geometry[k]) && !force) return false;
    geometry[k].change = &change;
    for (int e = 0; e < 3; ++e) {
      planes[k][e] = pattern.vertex(t[e]).cross(pattern.vertex(t[(e + 1) % 3]));
    }
  }
  result->errors.assign(nk, 0.0);
  result->worst_sample.assign(nk, -1);
  result->leans.assign(nk, 0);
  result->samples.resize(nk);
  for (auto& s : result->samples) s.clear();
  const auto measure = [&](int s) {
    const int k = ContainingFace(planes, pattern.vertex(s));
    bool leaned = false;
    const double d = Distance(geometry[k], samples_->positions[s],
                              &samples_->normals[s], threshold, &leaned);
    if (!(d <= threshold) && !force) {
      result->failed_at = d;
      return false;
    }
    result->samples[k].push_back(s);
    if (d > result->errors[k] || result->worst_sample[k] < 0) {
      result->errors[k] = std::max(result->errors[k], d);
      result->worst_sample[k] = s;
    }
    if (leaned) result->leans[k] = 1;
    return true;
  };
  // Fail fast: the freed vertices and each old face's worst sample first.
  for (int s : change.freed) {
    if (!measure(s)) return false;
  }
  for (int f : change.old_faces) {
    if (worst_[f] >= 0 && !measure(worst_[f])) return false;
  }
  for (int f : change.old_faces) {
    for (int s : inside_[f]) {
      if (s != worst_[f] && !measure(s)) return false;
    }
  }
  result->worst = 0.0;
  for (double e : result->errors) result->worst = std::max(result->worst, e);

  // The lattice between the samples, for a change about to be made.
  if (lattice_surface_ && !force) {
    const size_t per_face = lattice_weights_.size();
    thread_local Eigen::MatrixX3d directions, points, normals;
    directions.resize(nk * per_face, 3);
    for (size_t k = 0; k < nk; ++k) {
      const SphereTriangulation::Face& t = change.faces[k];
      for (size_t j = 0; j < per_face; ++j) {
        const Eigen::Vector3d& w = lattice_weights_[j];
        directions.row(k * per_face + j) =
            (w[0] * pattern.vertex(t[0]) + w[1] * pattern.vertex(t[1]) +
             w[2] * pattern.vertex(t[2]))
                .normalized()
                .transpose();
      }
    }
    lattice_surface_->Sample(directions, &points,
                             test_angle_ ? &normals : nullptr);
    for (size_t k = 0; k < nk; ++k) {
      for (size_t j = 0; j < per_face; ++j) {
        const Eigen::Index row = static_cast<Eigen::Index>(k * per_face + j);
        const Eigen::Vector3d q = points.row(row).transpose();
        Eigen::Vector3d n;
        if (test_angle_) n = normals.row(row).transpose();
        bool leaned = false;
        const double d = Distance(geometry[k], q, test_angle_ ? &n : nullptr,
                                  threshold, &leaned);
        if (!(d <= threshold)) {
          result->failed_at = d;
          return false;
        }
        result->errors[k] = std::max(result->errors[k], d);
        if (leaned) result->leans[k] = 1;
      }
    }
    for (double e : result->errors) result->worst = std::max(result->worst, e);
  }

  // Faces across the change's boundary that leaned on the old faces:
  // measured again with the new ones across their edges.
  result->outer.clear();
  for (int f : change.old_faces) {
    for (int e = 0; e < 3; ++e) {
      const int g = pattern.Twin(3 * f + e) / 3;
      if (leans_[g] &&
          std::find(change.old_faces.begin(), change.old_faces.end(), g) ==
              change.old_faces.end()) {
        result->outer.push_back(g);
      }
    }
  }
  std::sort(result->outer.begin(), result->outer.end());
  result->outer.erase(std::unique(result->outer.begin(), result->outer.end()),
                      result->outer.end());
  result->outer_errors.assign(result->outer.size(), 0.0);
  for (size_t i = 0; i < result->outer.size(); ++i) {
    const int g = result->outer[i];
    Geometry og;
    MakeGeometry(pattern.face(g), &og);
    og.change = &change;
    const double allowed = std::max(threshold, errors_[g]);
    bool leaned = false;
    double worst = 0.0;
    for (int s : inside_[g]) {
      const double d = Distance(og, samples_->positions[s],
                                &samples_->normals[s], allowed, &leaned);
      if (!(d <= allowed) && !force) {
        result->failed_at = d;
        return false;
      }
      worst = std::max(worst, d);
    }
    result->outer_errors[i] = worst;
  }
  return true;
}

double SampledFaces::MeasurePoints(int f, const Eigen::MatrixX3d& points,
                                   const Eigen::MatrixX3d* normals,
                                   Eigen::Index first, Eigen::Index count,
                                   double threshold, bool* angle_ok,
                                   double* angle,
                                   Eigen::Index* worst_row) const {
  const SphereTriangulation::Face& t = samples_->pattern.face(f);
  Geometry g;
  const bool ok = MakeGeometry(t, &g);
  // Orientation and angle matter where the angular test applies: on
  // smaller faces a normal error is invisible, and at a fold of the
  // surface no face would pass.
  *angle_ok = ok || !g.angular;
  double least_cos = 1.0;
  const auto see = [&](const Eigen::Vector3d& n) {
    if (g.angular && !n.isZero(0.0)) {
      least_cos = std::min(least_cos, g.normal.dot(n));
    }
  };
  for (int k = 0; k < 3; ++k) see(samples_->normals[t[k]]);
  double worst = 0.0;
  bool leaned = false;
  *worst_row = first;
  bool angle_failed = false;
  for (Eigen::Index k = first; k < first + count; ++k) {
    const Eigen::Vector3d q = points.row(k).transpose();
    Eigen::Vector3d n;
    if (normals) {
      n = normals->row(k).transpose();
      see(n);
    }
    const double d = Distance(g, q, normals ? &n : nullptr, threshold, &leaned);
    if (std::isinf(d) && g.angular) {
      *angle_ok = false;
      if (!angle_failed) *worst_row = k;
      angle_failed = true;
      continue;
    }
    if (d > worst) {
      worst = d;
      if (!angle_failed) *worst_row = k;
    }
  }
  *angle = std::acos(std::clamp(least_cos, -1.0, 1.0));
  return worst;
}

void SampledFaces::Apply(const FaceChange& change, ChangeResult* result) {
  Resize();
  for (int f : change.old_faces) {
    inside_[f].clear();
    errors_[f] = 0.0;
    worst_[f] = -1;
    leans_[f] = 0;
  }
  for (size_t k = 0; k < change.slots.size(); ++k) {
    const int f = change.slots[k];
    inside_[f].swap(result->samples[k]);
    errors_[f] = result->errors[k];
    worst_[f] = result->worst_sample[k];
    leans_[f] = result->leans[k];
  }
  for (size_t i = 0; i < result->outer.size(); ++i) {
    errors_[result->outer[i]] = result->outer_errors[i];
  }
}

}  // namespace sdcb
