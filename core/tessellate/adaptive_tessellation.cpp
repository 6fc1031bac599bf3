#include "sdcb/core/tessellate/adaptive_tessellation.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/tessellate/sphere_triangulation.h"
#include "sdcb/core/tessellate/triangle_distance.h"

namespace sdcb {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Result of certifying one face.
struct FaceCheck {
  double distance = 0.0;  // largest sampled distance surface -> triangle
  double angle = 0.0;     // largest normal angle (radians), if tested
  bool pass = true;
};

// The lattice points (i, j, k) / m, i + j + k = m, without the corners.
std::vector<Eigen::Vector3d> LatticeWeights(int m) {
  std::vector<Eigen::Vector3d> w;
  for (int i = 0; i <= m; ++i)
    for (int j = 0; i + j <= m; ++j) {
      const int k = m - i - j;
      if (i == m || j == m || k == m) continue;
      w.emplace_back(i, j, k);
    }
  return w;
}

// The tessellator's state: the domain triangulation plus the surface at its
// vertices.
class Tessellator {
 public:
  Tessellator(const SurfaceSampler& surface, const TessellationOptions& options)
      : surface_(surface),
        options_(options),
        weights_(LatticeWeights(options.lattice)),
        accept_(options.tolerance *
                (1.0 - 4.0 / (3.0 * options.lattice * options.lattice))),
        cos_angle_(std::cos(options.angle_degrees * kPi / 180.0)),
        test_angle_(options.angle_degrees < 180.0) {}

  Status Run(Tessellation* out);

 private:
  double EdgeLength(int a, int b) const {
    // Chord on the surface; the domain angle (scaled to be negligible)
    // keeps edges of folded or singular parts ordered by domain size.
    return (positions_[a] - positions_[b]).norm() +
           1e-6 * (triangulation_.vertex(a) - triangulation_.vertex(b)).norm();
  }
  void AddVertex(int v) {
    Eigen::MatrixX3d d(1, 3), p, n;
    d.row(0) = triangulation_.vertex(v);
    surface_.Sample(d, &p, &n);
    ++evaluations_;
    if (static_cast<int>(positions_.size()) <= v) {
      positions_.resize(v + 1);
      normals_.resize(v + 1);
    }
    positions_[v] = p.row(0).transpose();
    normals_[v] = n.row(0).transpose();
  }
  // Certifies `faces` (alive face slots) in one batch.
  std::vector<FaceCheck> Check(const std::vector<int>& faces);
  double ShortestDomainEdge(int f) const {
    const auto& t = triangulation_.face(f);
    double s = 4.0;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d& a = triangulation_.vertex(t[i]);
      const Eigen::Vector3d& b = triangulation_.vertex(t[(i + 1) % 3]);
      s = std::min(s, std::atan2(a.cross(b).norm(), a.dot(b)));
    }
    return s;
  }

  const SurfaceSampler& surface_;
  const TessellationOptions options_;
  const std::vector<Eigen::Vector3d> weights_;
  const double accept_;
  const double cos_angle_;
  const bool test_angle_;
  SphereTriangulation triangulation_;
  std::vector<Eigen::Vector3d> positions_, normals_;
  int64_t evaluations_ = 0;
  double max_distance_ = 0.0, max_angle_ = 0.0;
  int uncertified_ = 0;
};

std::vector<FaceCheck> Tessellator::Check(const std::vector<int>& faces) {
  const size_t s = weights_.size();
  Eigen::MatrixX3d directions(faces.size() * s, 3);
  tbb::parallel_for(size_t{0}, faces.size(), [&](size_t i) {
    const auto& t = triangulation_.face(faces[i]);
    const Eigen::Vector3d& a = triangulation_.vertex(t[0]);
    const Eigen::Vector3d& b = triangulation_.vertex(t[1]);
    const Eigen::Vector3d& c = triangulation_.vertex(t[2]);
    for (size_t k = 0; k < s; ++k) {
      const Eigen::Vector3d& w = weights_[k];
      directions.row(i * s + k) = (w[0] * a + w[1] * b + w[2] * c).normalized();
    }
  });
  Eigen::MatrixX3d positions, normals;
  surface_.Sample(directions, &positions, test_angle_ ? &normals : nullptr);
  evaluations_ += directions.rows();
  std::vector<FaceCheck> checks(faces.size());
  tbb::parallel_for(size_t{0}, faces.size(), [&](size_t i) {
    const auto& t = triangulation_.face(faces[i]);
    const Eigen::Vector3d& pa = positions_[t[0]];
    const Eigen::Vector3d& pb = positions_[t[1]];
    const Eigen::Vector3d& pc = positions_[t[2]];
    FaceCheck& check = checks[i];
    for (size_t k = 0; k < s; ++k) {
      const Eigen::Vector3d q = positions.row(i * s + k).transpose();
      check.distance =
          std::max(check.distance, PointTriangleDistance(q, pa, pb, pc));
    }
    check.pass = check.distance <= accept_;
    const double diameter =
        std::max({(pa - pb).norm(), (pb - pc).norm(), (pc - pa).norm()});
    if (!test_angle_ || diameter <= options_.tolerance) return;
    const Eigen::Vector3d cross = (pb - pa).cross(pc - pa);
    const double area2 = cross.norm();
    if (!(area2 > 0.0)) {
      check.angle = kPi;
      check.pass = false;
      return;
    }
    const Eigen::Vector3d n = cross / area2;
    double min_cos = 1.0;
    for (size_t k = 0; k < s; ++k) {
      min_cos = std::min(min_cos, n.dot(normals.row(i * s + k).transpose()));
    }
    for (int v : t) min_cos = std::min(min_cos, n.dot(normals_[v]));
    check.angle = std::acos(std::clamp(min_cos, -1.0, 1.0));
    if (min_cos < cos_angle_) check.pass = false;
  });
  return checks;
}

Status Tessellator::Run(Tessellation* out) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  const auto on_vertex = [this](int v) { AddVertex(v); };
  // The icosahedron's vertices are evaluated before its edges are ordered.
  {
    SphereTriangulation probe =
        SphereTriangulation::Icosahedron([](int, int) { return 0.0; });
    triangulation_ = std::move(probe);
    for (int v = 0; v < triangulation_.num_vertices(); ++v) AddVertex(v);
    triangulation_ = SphereTriangulation::Icosahedron(length);
  }
  std::vector<int> pending;
  for (int f = 0; f < triangulation_.num_face_slots(); ++f)
    pending.push_back(f);
  while (!pending.empty()) {
    const std::vector<FaceCheck> checks = Check(pending);
    const int first_new = triangulation_.num_face_slots();
    for (size_t i = 0; i < pending.size(); ++i) {
      const int f = pending[i];
      if (checks[i].pass || !triangulation_.alive(f)) continue;
      if (ShortestDomainEdge(f) < options_.min_edge_radians) continue;
      triangulation_.Bisect(f, length, on_vertex);
      if (triangulation_.num_faces() > options_.max_faces) {
        return InvalidInputError("the tolerance needs more than " +
                                 std::to_string(options_.max_faces) +
                                 " triangles");
      }
    }
    pending.clear();
    for (int f = first_new; f < triangulation_.num_face_slots(); ++f) {
      if (triangulation_.alive(f)) pending.push_back(f);
    }
  }
  // Final certificate of every face (the numbers reported).
  std::vector<int> all;
  for (int f = 0; f < triangulation_.num_face_slots(); ++f) {
    if (triangulation_.alive(f)) all.push_back(f);
  }
  const std::vector<FaceCheck> checks = Check(all);
  const double scale =
      1.0 / (1.0 - 4.0 / (3.0 * options_.lattice * options_.lattice));
  for (const FaceCheck& c : checks) {
    max_distance_ = std::max(max_distance_, c.distance * scale);
    max_angle_ = std::max(max_angle_, c.angle);
    if (!c.pass) ++uncertified_;
  }

  out->directions = triangulation_.Vertices();
  out->faces = triangulation_.Faces();
  const int nv = triangulation_.num_vertices();
  out->positions.resize(nv, 3);
  out->normals.resize(nv, 3);
  for (int v = 0; v < nv; ++v) {
    out->positions.row(v) = positions_[v].transpose();
    out->normals.row(v) = normals_[v].transpose();
  }
  out->certified_distance = max_distance_;
  out->max_normal_angle_degrees = max_angle_ * 180.0 / kPi;
  out->uncertified_faces = uncertified_;
  out->evaluations = evaluations_;
  return Status::Ok();
}

}  // namespace

StatusOr<Tessellation> TessellateAdaptively(
    const SurfaceSampler& surface, const TessellationOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    return InvalidArgumentError("tessellation tolerance must be > 0");
  }
  if (!(options.angle_degrees > 0.0 && options.angle_degrees <= 180.0)) {
    return InvalidArgumentError("tessellation angle must be in (0, 180]");
  }
  if (options.lattice < 2 || options.lattice > 16) {
    return InvalidArgumentError("tessellation lattice order must be in 2..16");
  }
  Tessellator tessellator(surface, options);
  Tessellation out;
  SDCB_RETURN_IF_ERROR(tessellator.Run(&out));
  return out;
}

Tessellation TessellateUniformly(const SurfaceSampler& surface,
                                 int subdivisions) {
  const TriangleMesh sphere = MakeIcosphere(std::clamp(subdivisions, 0, 9));
  Tessellation out;
  out.directions = sphere.vertices;
  out.faces = sphere.faces;
  surface.Sample(out.directions, &out.positions, &out.normals);
  out.evaluations = out.directions.rows();
  return out;
}

int UniformLevelForVertices(int64_t vertices) {
  int best = 0;
  double best_gap = 1e300;
  for (int s = 0; s <= 9; ++s) {
    const double count = 10.0 * std::pow(4.0, s) + 2.0;
    const double gap =
        std::abs(std::log(count) - std::log(std::max<double>(1, vertices)));
    if (gap < best_gap) {
      best_gap = gap;
      best = s;
    }
  }
  return best;
}

}  // namespace sdcb
