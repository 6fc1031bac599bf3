#include "sdcb/core/tessellate/adaptive_tessellation.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
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
    // The domain (chord) length orders bisections: a median is shorter than
    // the longest edge, so LEPP paths end. A surface length would not: where
    // the surface spikes, a midpoint's image can be farther from the
    // opposite corner than the split edge was long, and the path never ends.
    return (triangulation_.vertex(a) - triangulation_.vertex(b)).norm();
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
  // Splits faces until every face reachable from `pending` is certified.
  Status Refine(std::vector<int> pending);
  double PredictedError(int a, int b, int c) const;
  // Edge collapses and flips guided by PredictedError.
  void Optimize();
  int Smooth(double target);
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

Status Tessellator::Refine(std::vector<int> pending) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  const auto on_vertex = [this](int v) { AddVertex(v); };
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
  return Status::Ok();
}

// Chordal error of face (a, b, c) predicted from its corners' positions and
// normals: for a quadratic surface over the triangle, linear interpolation
// misses by (1/2) |sum_{i<j} l_i l_j Q_ij| at barycentric point l, with
// Q_ij = (n_j - n_i) . (p_j - p_i) = d_ij^T H d_ij exactly. Infinite where a
// normal is missing (singular point) or the normal test fails.
double Tessellator::PredictedError(int a, int b, int c) const {
  const Eigen::Vector3d& pa = positions_[a];
  const Eigen::Vector3d& pb = positions_[b];
  const Eigen::Vector3d& pc = positions_[c];
  const Eigen::Vector3d& na = normals_[a];
  const Eigen::Vector3d& nb = normals_[b];
  const Eigen::Vector3d& nc = normals_[c];
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (na.isZero(0.0) || nb.isZero(0.0) || nc.isZero(0.0)) return kInf;
  const Eigen::Vector3d cross = (pb - pa).cross(pc - pa);
  const double area2 = cross.norm();
  if (!(area2 > 0.0)) return kInf;
  const Eigen::Vector3d n = cross / area2;
  // The image must not turn over against the surface normals.
  const double min_cos = std::min({n.dot(na), n.dot(nb), n.dot(nc)});
  if (min_cos <= 0.0) return kInf;
  if (test_angle_ && min_cos < cos_angle_) {
    const double diameter =
        std::max({(pa - pb).norm(), (pb - pc).norm(), (pc - pa).norm()});
    if (diameter > options_.tolerance) return kInf;
  }
  const double qab = (nb - na).dot(pb - pa), qbc = (nc - nb).dot(pc - pb),
               qca = (na - nc).dot(pa - pc);
  double worst = 0.0;
  constexpr int kOrder = 8;
  for (int i = 0; i <= kOrder; ++i)
    for (int j = 0; i + j <= kOrder; ++j) {
      const double la = double(i) / kOrder, lb = double(j) / kOrder,
                   lc = 1.0 - la - lb;
      worst = std::max(worst,
                       std::abs(la * lb * qab + lb * lc * qbc + lc * la * qca));
    }
  return 0.5 * worst;
}

void Tessellator::Optimize() {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  // Predictions are checked by the final certificate; aim a little lower
  // so that few faces fail it.
  const double target = 0.85 * accept_;
  std::vector<SphereTriangulation::Face> faces, old_faces;
  auto worst = [&](const std::vector<SphereTriangulation::Face>& fs) {
    double w = 0.0;
    for (const auto& t : fs) w = std::max(w, PredictedError(t[0], t[1], t[2]));
    return w;
  };
  for (int pass = 0; pass < 6; ++pass) {
    int changes = 0;
    std::vector<std::array<int, 2>> edges = triangulation_.Edges();
    std::vector<double> lengths(edges.size());
    for (size_t i = 0; i < edges.size(); ++i) {
      lengths[i] = (positions_[edges[i][0]] - positions_[edges[i][1]]).norm();
    }
    std::vector<size_t> order(edges.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) {
      return lengths[x] < lengths[y];
    });
    // Collapses, shortest edges first.
    for (size_t o : order) {
      const int a = edges[o][0], b = edges[o][1];
      if (!triangulation_.HasEdge(a, b)) continue;
      double best = target;
      int from = -1, to = -1;
      for (const auto& [v, w] : {std::make_pair(a, b), std::make_pair(b, a)}) {
        if (!triangulation_.PreviewCollapse(v, w, &faces)) continue;
        const double e = worst(faces);
        if (e <= best) {
          best = e;
          from = v;
          to = w;
        }
      }
      if (from >= 0) {
        triangulation_.Collapse(from, to, length);
        ++changes;
      }
    }
    // Flips that lower the larger predicted error of the two faces.
    for (const auto& [a, b] : triangulation_.Edges()) {
      if (!triangulation_.HasEdge(a, b)) continue;
      if (!triangulation_.PreviewFlip(a, b, &faces)) continue;
      const double after = worst(faces);
      // New faces (a, d, c), (d, b, c) replace (a, b, c), (b, a, d).
      const int c = faces[0][2], d = faces[0][1];
      old_faces = {{a, b, c}, {b, a, d}};
      if (after < 0.98 * worst(old_faces) && after <= target) {
        triangulation_.Flip(a, b, length);
        ++changes;
      }
    }
    changes += Smooth(target);
    if (changes == 0) break;
  }
}

// Moves each vertex halfway toward the centroid of its neighbours on the
// domain where that lowers the largest predicted error of its faces
// (equalizing errors leaves room for more collapses). One batch of surface
// evaluations for all candidate positions; acceptance is sequential.
int Tessellator::Smooth(double target) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  std::vector<int> vertices = triangulation_.AliveVertices();
  Eigen::MatrixX3d candidates(vertices.size(), 3);
  for (size_t i = 0; i < vertices.size(); ++i) {
    const int v = vertices[i];
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int x : triangulation_.Ring(v)) centroid += triangulation_.vertex(x);
    candidates.row(i) =
        (triangulation_.vertex(v) + centroid.normalized()).normalized();
  }
  Eigen::MatrixX3d positions, normals;
  surface_.Sample(candidates, &positions, &normals);
  evaluations_ += candidates.rows();
  int moved = 0;
  for (size_t i = 0; i < vertices.size(); ++i) {
    const int v = vertices[i];
    const std::vector<int> ring = triangulation_.Ring(v);
    const int n = static_cast<int>(ring.size());
    double before = 0.0;
    for (int k = 0; k < n; ++k) {
      before = std::max(before, PredictedError(v, ring[k], ring[(k + 1) % n]));
    }
    const Eigen::Vector3d old_direction = triangulation_.vertex(v);
    const Eigen::Vector3d old_position = positions_[v],
                          old_normal = normals_[v];
    positions_[v] = positions.row(i).transpose();
    normals_[v] = normals.row(i).transpose();
    triangulation_.MoveVertex(v, candidates.row(i).transpose(), length);
    double after = 0.0;
    bool valid = true;
    for (int k = 0; k < n && valid; ++k) {
      valid = triangulation_.IsPositive(v, ring[k], ring[(k + 1) % n]);
      after = std::max(after, PredictedError(v, ring[k], ring[(k + 1) % n]));
    }
    if (valid && after < 0.98 * before && after <= std::max(target, before)) {
      ++moved;
      continue;
    }
    positions_[v] = old_position;
    normals_[v] = old_normal;
    triangulation_.MoveVertex(v, old_direction, length);
  }
  return moved;
}

Status Tessellator::Run(Tessellation* out) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  // The icosahedron's vertices are evaluated before its edges are ordered.
  triangulation_ =
      SphereTriangulation::Icosahedron([](int, int) { return 0.0; });
  for (int v = 0; v < triangulation_.num_vertices(); ++v) AddVertex(v);
  triangulation_ = SphereTriangulation::Icosahedron(length);
  auto alive_faces = [this] {
    std::vector<int> all;
    for (int f = 0; f < triangulation_.num_face_slots(); ++f) {
      if (triangulation_.alive(f)) all.push_back(f);
    }
    return all;
  };
  SDCB_RETURN_IF_ERROR(Refine(alive_faces()));
  if (options_.optimize) {
    Optimize();
    // The predictions are not a certificate: certify every face again and
    // split those that fail.
    SDCB_RETURN_IF_ERROR(Refine(alive_faces()));
  }
  // Final certificate of every face (the numbers reported).
  const std::vector<FaceCheck> checks = Check(alive_faces());
  const double scale =
      1.0 / (1.0 - 4.0 / (3.0 * options_.lattice * options_.lattice));
  for (const FaceCheck& c : checks) {
    max_distance_ = std::max(max_distance_, c.distance * scale);
    max_angle_ = std::max(max_angle_, c.angle);
    if (!c.pass) ++uncertified_;
  }

  const std::vector<int> vertices = triangulation_.AliveVertices();
  out->faces = triangulation_.Faces();
  const int nv = static_cast<int>(vertices.size());
  out->directions.resize(nv, 3);
  out->positions.resize(nv, 3);
  out->normals.resize(nv, 3);
  for (int i = 0; i < nv; ++i) {
    const int v = vertices[i];
    out->directions.row(i) = triangulation_.vertex(v).transpose();
    out->positions.row(i) = positions_[v].transpose();
    out->normals.row(i) = normals_[v].transpose();
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
