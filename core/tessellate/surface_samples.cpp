#include "sdcb/core/tessellate/surface_samples.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/tessellate/trim_pattern.h"

namespace sdcb {
namespace {

// Interleaves the bits of three 21-bit integers (a Morton code).
uint64_t Interleave(uint32_t x, uint32_t y, uint32_t z) {
  uint64_t code = 0;
  for (int b = 0; b < 21; ++b) {
    code |= (uint64_t((x >> b) & 1u) << (3 * b)) |
            (uint64_t((y >> b) & 1u) << (3 * b + 1)) |
            (uint64_t((z >> b) & 1u) << (3 * b + 2));
  }
  return code;
}

// The samples renumbered along a Morton curve of their directions, and the
// faces in the order of their first corner: a vertex's star and its
// neighbours' samples then sit close in memory (the simplification walks
// them millions of times). The same triangulation and samples otherwise.
SurfaceSamples SpatiallyOrdered(const SurfaceSamples& s) {
  const SphereTriangulation& p = s.pattern;
  const std::vector<int> alive = p.AliveVertices();
  const int n = static_cast<int>(alive.size());
  std::vector<uint64_t> key(n);
  const auto quantize = [](double x) {
    return static_cast<uint32_t>(
        std::clamp((x + 1.0) * 0.5 * 2097151.0, 0.0, 2097151.0));
  };
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& d = p.vertex(alive[i]);
    key[i] = Interleave(quantize(d[0]), quantize(d[1]), quantize(d[2]));
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  // Strict total orders (ties broken by index; the faces are distinct):
  // the same result whatever the sort's threads.
  tbb::parallel_sort(order.begin(), order.end(), [&](int a, int b) {
    return key[a] < key[b] || (key[a] == key[b] && a < b);
  });
  // p.Faces() numbers corners by rank among the alive vertices.
  std::vector<int> rank(n);
  for (int i = 0; i < n; ++i) rank[order[i]] = i;
  Eigen::MatrixX3i faces = p.Faces();
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    Eigen::Vector3i t(rank[faces(f, 0)], rank[faces(f, 1)], rank[faces(f, 2)]);
    // Rotated so the first corner is the smallest (same orientation).
    while (t[0] > t[1] || t[0] > t[2]) t = Eigen::Vector3i(t[1], t[2], t[0]);
    faces.row(f) = t.transpose();
  }
  std::vector<Eigen::Index> by_corner(faces.rows());
  std::iota(by_corner.begin(), by_corner.end(), 0);
  tbb::parallel_sort(by_corner.begin(), by_corner.end(),
                     [&](Eigen::Index a, Eigen::Index b) {
                       for (int k = 0; k < 3; ++k) {
                         if (faces(a, k) != faces(b, k))
                           return faces(a, k) < faces(b, k);
                       }
                       return false;
                     });
  Eigen::MatrixX3i sorted(faces.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    sorted.row(f) = faces.row(by_corner[f]);
  }
  SurfaceSamples out;
  Eigen::MatrixX3d directions(n, 3);
  out.positions.resize(n);
  out.normals.resize(n);
  for (int i = 0; i < n; ++i) {
    const int v = alive[order[i]];
    directions.row(i) = p.vertex(v).transpose();
    out.positions[i] = s.positions[v];
    out.normals[i] = s.normals[v];
  }
  StatusOr<SphereTriangulation> pattern =
      SphereTriangulation::FromFaces(directions, sorted);
  // The faces are a renumbered closed triangulation: FromFaces accepts them.
  out.pattern = std::move(pattern).value();
  if (p.has_features()) {
    std::vector<std::array<int, 2>> ends = p.arc_ends();
    std::vector<int> rank_of(p.num_vertices(), -1);
    for (int i = 0; i < n; ++i) rank_of[alive[i]] = rank[i];
    for (auto& e : ends) e = {rank_of[e[0]], rank_of[e[1]]};
    std::vector<int> arc(n);
    for (int i = 0; i < n; ++i) arc[rank[i]] = p.vertex_arc(alive[i]);
    out.pattern.SetFeatures(std::move(ends), std::move(arc));
  }
  out.size = s.size;
  out.evaluations = s.evaluations;
  if (!s.coarse_faces.empty()) {
    const int nc = static_cast<int>(s.coarse_faces.size());
    std::vector<SphereTriangulation::Face> coarse(nc);
    for (int c = 0; c < nc; ++c) {
      SphereTriangulation::Face t;
      for (int k = 0; k < 3; ++k) t[k] = rank[s.coarse_faces[c][k]];
      while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
      coarse[c] = t;
    }
    std::vector<int> by_first(nc);
    std::iota(by_first.begin(), by_first.end(), 0);
    std::sort(by_first.begin(), by_first.end(),
              [&](int a, int b) { return coarse[a] < coarse[b]; });
    std::vector<int> new_index(nc);
    out.coarse_faces.resize(nc);
    for (int c = 0; c < nc; ++c) {
      new_index[by_first[c]] = c;
      out.coarse_faces[c] = coarse[by_first[c]];
    }
    out.coarse_face_of.assign(n, -1);
    for (int v = 0; v < n; ++v) {
      const int c = s.coarse_face_of[v];
      out.coarse_face_of[rank[v]] = c < 0 ? -1 : new_index[c];
    }
  }
  return out;
}

double DomainAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

double PredictedFlatError(const Eigen::Vector3d& pa, const Eigen::Vector3d& pb,
                          const Eigen::Vector3d& pc, const Eigen::Vector3d& na,
                          const Eigen::Vector3d& nb,
                          const Eigen::Vector3d& nc) {
  const double qab = std::abs((nb - na).dot(pb - pa));
  const double qbc = std::abs((nc - nb).dot(pc - pb));
  const double qca = std::abs((na - nc).dot(pa - pc));
  return std::max({qab, qbc, qca}) / 6.0;
}

void EvaluateNewVertices(const SurfaceSampler& surface, int first,
                         SurfaceSamples* samples) {
  const int n = samples->pattern.num_vertices();
  if (n <= first) return;
  Eigen::MatrixX3d directions(n - first, 3), positions, normals;
  for (int v = first; v < n; ++v) {
    directions.row(v - first) = samples->pattern.vertex(v).transpose();
  }
  surface.Sample(directions, &positions, &normals);
  samples->positions.resize(n);
  samples->normals.resize(n);
  for (int v = first; v < n; ++v) {
    samples->positions[v] = positions.row(v - first).transpose();
    samples->normals[v] = normals.row(v - first).transpose();
  }
  samples->evaluations += n - first;
}

namespace {

// The refinement of SampleSurface: the samples, the criteria and the
// bisections.
class Refiner {
 public:
  Refiner(const SurfaceSampler& surface, const SurfaceSampleOptions& options,
          SurfaceSamples* s)
      : surface_(surface),
        options_(options),
        s_(*s),
        test_angle_(options.angle_degrees < 180.0),
        angle_length_(options.angle_length_factor * options.tolerance) {}

  // The criteria, `scale` times looser than the options' (errors times it,
  // lengths and angles times its square root, angles at most the final one).
  void SetCriteria(double scale) {
    max_length_ = options_.length_factor *
                  std::sqrt(scale * options_.tolerance * s_.size);
    max_error_ = scale * options_.error_fraction * options_.tolerance;
    min_cos_ = std::cos(std::min(options_.angle_degrees,
                                 options_.angle_degrees * std::sqrt(scale) /
                                     options_.angle_divisions) *
                        kPi / 180.0);
  }

  // Bisects the failing faces of `pending` and then the faces that made,
  // round after round, until none fails.
  Status Refine(std::vector<int> pending) {
    std::vector<char> failing;
    while (!pending.empty()) {
      if (options_.kept_region_only) {
        SDCB_ASSIGN_OR_RETURN(const std::vector<char> kept,
                              KeptFaceSlots(s_.pattern));
        pending.erase(std::remove_if(pending.begin(), pending.end(),
                                     [&](int f) { return !kept[f]; }),
                      pending.end());
      }
      failing.assign(pending.size(), 0);
      tbb::parallel_for(size_t{0}, pending.size(), [&](size_t i) {
        failing[i] = s_.pattern.alive(pending[i]) && Fails(pending[i]);
      });
      const int first_vertex = s_.pattern.num_vertices();
      const int first_face = s_.pattern.num_face_slots();
      std::vector<int> touched;
      for (size_t i = 0; i < pending.size(); ++i) {
        // A split earlier in this round may have split this face already.
        const SphereTriangulation::Face& t = s_.pattern.face(pending[i]);
        if (failing[i] && s_.pattern.alive(pending[i]) &&
            std::max({t[0], t[1], t[2]}) < first_vertex) {
          Bisect(pending[i], &touched);
        }
      }
      if (s_.pattern.num_vertices() > options_.max_vertices) {
        return InvalidInputError(
            "the surface needs more than " +
            std::to_string(options_.max_vertices) +
            " samples for this tolerance (it bends or tears faster than "
            "its domain can be refined): use a larger tolerance");
      }
      EvaluateNewVertices(surface_, first_vertex, &s_);
      for (int f = first_face; f < s_.pattern.num_face_slots(); ++f) {
        touched.push_back(f);
      }
      std::sort(touched.begin(), touched.end());
      touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
      pending = std::move(touched);
      if (options_.progress) options_.progress(s_.pattern.num_vertices());
    }
    return Status::Ok();
  }

  // The coarse pattern is done: its faces are recorded as the coarse faces,
  // and every face of a later split belongs to its ancestor.
  void RecordCoarseFaces() {
    ancestor_.assign(s_.pattern.num_face_slots(), -1);
    for (int f = 0; f < s_.pattern.num_face_slots(); ++f) {
      if (!s_.pattern.alive(f)) continue;
      ancestor_[f] = static_cast<int>(s_.coarse_faces.size());
      s_.coarse_faces.push_back(s_.pattern.face(f));
    }
    s_.coarse_face_of.assign(s_.pattern.num_vertices(), -1);
  }

 private:
  // Whether face f fails (see the header). Faces whose image is within the
  // error share of a point are left: at a singular point of the surface
  // (its normals turning over within any neighbourhood) no split would make
  // them pass.
  bool Fails(int f) const {
    const SphereTriangulation::Face& t = s_.pattern.face(f);
    double longest2 = 0.0, q = 0.0, least_cos = 1.0;
    for (int e = 0; e < 3; ++e) {
      const int a = t[e], b = t[(e + 1) % 3];
      const Eigen::Vector3d d = s_.positions[b] - s_.positions[a];
      longest2 = std::max(longest2, d.squaredNorm());
      if (s_.normals[a].isZero(0.0) || s_.normals[b].isZero(0.0)) continue;
      const double c = s_.normals[a].dot(s_.normals[b]);
      least_cos = std::min(least_cos, c);
      // Across a fold or a cusp (normals turned over) the quadratic
      // prediction means nothing; the size criterion still holds there.
      if (c > 0.0)
        q = std::max(q, std::abs((s_.normals[b] - s_.normals[a]).dot(d)));
    }
    if (longest2 > max_length_ * max_length_) return true;
    if (longest2 <= max_error_ * max_error_) return false;
    // The angular test applies to faces larger than the tolerance only.
    return q > 6.0 * max_error_ || (test_angle_ && least_cos < min_cos_ &&
                                    longest2 > angle_length_ * angle_length_);
  }

  // Domain edges order the bisections (longest first, ties by vertex
  // index): Rivara's longest-edge bisection, which keeps the domain faces
  // well shaped and ends. (Image lengths would not: near a singular point
  // of the surface they drive the domain faces into needles.)
  bool Longer(int a, int b, int c, int d) const {
    const double lab =
        (s_.pattern.vertex(a) - s_.pattern.vertex(b)).squaredNorm();
    const double lcd =
        (s_.pattern.vertex(c) - s_.pattern.vertex(d)).squaredNorm();
    if (lab != lcd) return lab > lcd;
    return std::make_pair(std::min(a, b), std::max(a, b)) >
           std::make_pair(std::min(c, d), std::max(c, d));
  }

  int LongestHalfEdge(int f) const {
    const SphereTriangulation::Face& t = s_.pattern.face(f);
    int best = 0;
    for (int e = 1; e < 3; ++e) {
      if (Longer(t[e], t[(e + 1) % 3], t[best], t[(best + 1) % 3])) best = e;
    }
    return 3 * f + best;
  }

  void Split(int h, std::vector<int>* touched) {
    const int a = s_.pattern.Origin(h), b = s_.pattern.Target(h);
    touched->push_back(h / 3);
    touched->push_back(s_.pattern.Twin(h) / 3);
    const int f = h / 3, g = s_.pattern.Twin(h) / 3;
    s_.pattern.SplitEdge(
        h, (s_.pattern.vertex(a) + s_.pattern.vertex(b)).normalized());
    if (!ancestor_.empty()) {
      const int slots = s_.pattern.num_face_slots();
      ancestor_.resize(slots);
      ancestor_[slots - 2] = ancestor_[f];
      ancestor_[slots - 1] = ancestor_[g];
      s_.coarse_face_of.push_back(ancestor_[f]);
    }
  }

  // LEPP: walks from f across longest edges until two faces share their
  // longest edge, splits it, and starts again until f itself is split.
  void Bisect(int f0, std::vector<int>* touched) {
    constexpr int kMaxPath = 64;
    const SphereTriangulation::Face original = s_.pattern.face(f0);
    while (s_.pattern.alive(f0) && s_.pattern.face(f0) == original) {
      int h = LongestHalfEdge(f0);
      for (int depth = 0; depth < kMaxPath; ++depth) {
        const int t = s_.pattern.Twin(h);
        const int next = LongestHalfEdge(t / 3);
        if (next == t) break;
        h = next;
      }
      const int a = s_.pattern.Origin(h), b = s_.pattern.Target(h);
      if (DomainAngle(s_.pattern.vertex(a), s_.pattern.vertex(b)) <
          options_.min_edge_radians) {
        return;
      }
      Split(h, touched);
    }
  }

  const SurfaceSampler& surface_;
  const SurfaceSampleOptions& options_;
  SurfaceSamples& s_;
  const bool test_angle_;
  const double angle_length_;
  double max_length_ = 0.0, max_error_ = 0.0, min_cos_ = 1.0;
  // Once the coarse pattern is done: per face slot, the coarse face it
  // belongs to (empty before).
  std::vector<int> ancestor_;
};

}  // namespace

StatusOr<SurfaceSamples> SampleSurface(const SurfaceSampler& surface,
                                       const SurfaceSampleOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    return InvalidArgumentError("the tolerance must be positive");
  }
  SurfaceSamples s;
  s.pattern = options.initial_pattern != nullptr
                  ? *options.initial_pattern
                  : SphereTriangulation::Icosphere(options.initial_level);
  EvaluateNewVertices(surface, 0, &s);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const Eigen::Vector3d& p : s.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  s.size = (hi - lo).maxCoeff();
  if (!std::isfinite(s.size)) {
    return InvalidInputError("the surface has a non-finite point");
  }
  Refiner refiner(surface, options, &s);
  const bool coarse_first = options.coarse_scale > 1.0;
  refiner.SetCriteria(coarse_first ? options.coarse_scale : 1.0);
  std::vector<int> all(s.pattern.num_face_slots());
  std::iota(all.begin(), all.end(), 0);
  SDCB_RETURN_IF_ERROR(refiner.Refine(all));
  if (coarse_first) {
    // The coarse pattern is done: its faces, then the dense criteria.
    refiner.RecordCoarseFaces();
    refiner.SetCriteria(1.0);
    all.resize(s.pattern.num_face_slots());
    std::iota(all.begin(), all.end(), 0);
    SDCB_RETURN_IF_ERROR(refiner.Refine(all));
  }
  return SpatiallyOrdered(s);
}

}  // namespace sdcb
