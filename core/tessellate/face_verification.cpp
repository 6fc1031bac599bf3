#include "sdcb/core/tessellate/face_verification.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sdcb/core/measure/sample_lattice.h"
#include "sdcb/core/tessellate/mesh_side_distance.h"
#include "sdcb/core/tessellate/trim_pattern.h"

namespace sdcb {
namespace {

// Faces measured near the threshold, or whose lattice image is stretched,
// are measured again at a finer order, up to this one.
constexpr int kMaxOrder = 24;
constexpr double kRecheckFraction = 0.7;
constexpr double kMaxStretch = 1.2;
constexpr double kRecheckRefinement = 2.5;

// A face's barycentric lattice of order m (TriangleLattice): the weights
// (i, j, m - i - j) / m, corners not included (they are the face's
// vertices, not evaluated), and the pairs of adjacent points.
struct Lattice {
  explicit Lattice(int m) {
    const TriangleLattice lattice(m, LatticeOrientation::kIJ);
    // Corners (i = m), (j = m), (k = m) as -1, -2, -3; others renumbered.
    std::vector<int> renumber(lattice.points.size());
    for (size_t x = 0; x < lattice.points.size(); ++x) {
      const int i = lattice.points[x][0], j = lattice.points[x][1];
      if (i == m) {
        renumber[x] = -1;
      } else if (j == m) {
        renumber[x] = -2;
      } else if (i + j == 0) {
        renumber[x] = -3;
      } else {
        renumber[x] = static_cast<int>(weights.size());
        weights.emplace_back(double(i) / m, double(j) / m,
                             double(m - i - j) / m);
      }
    }
    for (size_t t = 0; t < lattice.triangles.size(); ++t) {
      if (!lattice.upward[t]) continue;
      const Eigen::Vector3i& c = lattice.triangles[t];
      const int x = renumber[c[0]], y = renumber[c[1]], z = renumber[c[2]];
      edges.push_back({x, y});
      edges.push_back({x, z});
      edges.push_back({y, z});
    }
  }
  std::vector<Eigen::Vector3d> weights;   // points other than corners
  std::vector<std::array<int, 2>> edges;  // corner c as -1 - c
};

// Lattice points whose distance is above this fraction of the threshold
// and a local maximum start an ascent (Ascend), at most kMaxStarts a face.
constexpr double kAscentFrom = 0.5;
constexpr int kMaxStarts = 4;

// The local maxima of the distance over face f's lattice `l` (points at
// rows first.. of `points`), above kAscentFrom of the threshold, farthest
// first, at most kMaxStarts.
std::vector<Eigen::Vector3d> LatticePeaks(const SampledFaces& faces, int f,
                                          const Lattice& l,
                                          const Eigen::MatrixX3d& points,
                                          Eigen::Index first,
                                          double threshold) {
  const size_t n = l.weights.size();
  std::vector<double> d(n);
  for (size_t k = 0; k < n; ++k) {
    bool angle_ok = true;
    double angle = 0.0;
    Eigen::Index worst = 0;
    d[k] = faces.MeasurePoints(f, points, nullptr, first + k, 1, threshold,
                               &angle_ok, &angle, &worst);
  }
  std::vector<char> peak(n, 1);
  for (const auto& [x, y] : l.edges) {
    if (x < 0 || y < 0) continue;
    if (d[x] < d[y]) peak[x] = 0;
    if (d[y] < d[x]) peak[y] = 0;
  }
  std::vector<int> order;
  for (size_t k = 0; k < n; ++k) {
    if (peak[k] && d[k] > kAscentFrom * threshold) order.push_back(int(k));
  }
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return d[a] > d[b] || (d[a] == d[b] && a < b);
  });
  if (order.size() > size_t(kMaxStarts)) order.resize(kMaxStarts);
  std::vector<Eigen::Vector3d> out;
  for (int k : order) out.push_back(l.weights[k]);
  return out;
}

// What the lattice of a face measured.
struct LatticeMeasure {
  double distance = 0.0;
  double angle = 0.0;  // radians
  bool angle_ok = true;
  // The largest ratio of a lattice edge's image to the same edge of the
  // flat triangle's lattice (1 where the surface is affine over the face).
  double stretch = 1.0;
  // Barycentric weights of the lattice's local maxima of the distance
  // above kAscentFrom of the threshold (at most kMaxStarts, farthest first),
  // and the lattice's order.
  std::vector<Eigen::Vector3d> peaks;
  int order = 0;
  // The mesh's side: the largest distance from the flat triangle's lattice
  // points to the surface, each the distance to a surface point found (never
  // below the true one); and that raised by what can hide between the
  // points (see MeasureMeshSide).
  double mesh_sampled = 0.0;
  double mesh_distance = 0.0;
};

// Flat points whose distance S(u) reads above this share of the threshold
// are searched for a nearer surface point
// (core/tessellate/mesh_side_distance.h).
constexpr double kMeshSideSearchStop = 0.9;

// The mesh's side of faces `which` on their lattices (rows offset[i].. of
// `directions` / `points`, S at the lattice's domain points): fills
// (*out)[i].mesh_sampled and mesh_distance.
void MeasureMeshSide(const SurfaceSampler& surface,
                     const SurfaceSamples& samples,
                     const std::vector<int>& which,
                     const std::vector<std::unique_ptr<Lattice>>& lattices,
                     const std::vector<int>& orders,
                     const std::vector<Eigen::Index>& offset,
                     const Eigen::MatrixX3d& directions,
                     const Eigen::MatrixX3d& points, double threshold,
                     std::vector<LatticeMeasure>* out, int64_t* evaluations) {
  std::vector<int> faces(offset.back());
  std::vector<Eigen::Vector3d> weights(offset.back());
  for (size_t i = 0; i < which.size(); ++i) {
    const Lattice& l = *lattices[orders[i]];
    for (size_t k = 0; k < l.weights.size(); ++k) {
      faces[offset[i] + k] = which[i];
      weights[offset[i] + k] = l.weights[k];
    }
  }
  const Eigen::VectorXd distance = FlatToSurfaceDistances(
      surface, samples, faces, weights, directions, points,
      kMeshSideSearchStop * threshold, evaluations);
  // Between lattice points (spacing 1/m of the face) the distance of a flat
  // triangle to a smooth surface is near quadratic, delta (1 - 4 (t - t*)^2)
  // on a unit edge: its maximum exceeds the largest at the points by a
  // factor of at most 1 / (1 - 1 / m^2); twice that margin is taken for
  // what is not quite quadratic.
  for (size_t i = 0; i < which.size(); ++i) {
    const double m = orders[i];
    LatticeMeasure& measure = (*out)[i];
    measure.mesh_sampled =
        offset[i + 1] > offset[i]
            ? distance.segment(offset[i], offset[i + 1] - offset[i]).maxCoeff()
            : 0.0;
    measure.mesh_distance = measure.mesh_sampled / (1.0 - 2.0 / (m * m));
  }
}

// Measures faces[i] on its lattice of order orders[i] (one batch).
std::vector<LatticeMeasure> MeasureLattices(const SurfaceSampler& surface,
                                            const SampledFaces& faces,
                                            const std::vector<int>& which,
                                            const std::vector<int>& orders,
                                            double threshold,
                                            int64_t* evaluations) {
  const SurfaceSamples& samples = faces.samples();
  const SphereTriangulation& pattern = samples.pattern;
  const bool with_normals = faces.tests_angle();
  std::vector<std::unique_ptr<Lattice>> lattices(kMaxOrder + 1);
  std::vector<Eigen::Index> offset(which.size() + 1, 0);
  for (size_t i = 0; i < which.size(); ++i) {
    auto& l = lattices[orders[i]];
    if (!l) l = std::make_unique<Lattice>(orders[i]);
    offset[i + 1] = offset[i] + static_cast<Eigen::Index>(l->weights.size());
  }
  Eigen::MatrixX3d directions(offset.back(), 3), points, normals;
  tbb::parallel_for(size_t{0}, which.size(), [&](size_t i) {
    const auto& t = pattern.face(which[i]);
    const Lattice& l = *lattices[orders[i]];
    for (size_t k = 0; k < l.weights.size(); ++k) {
      const Eigen::Vector3d& w = l.weights[k];
      directions.row(offset[i] + k) =
          (w[0] * pattern.vertex(t[0]) + w[1] * pattern.vertex(t[1]) +
           w[2] * pattern.vertex(t[2]))
              .normalized()
              .transpose();
    }
  });
  surface.Sample(directions, &points, with_normals ? &normals : nullptr);
  *evaluations += directions.rows();
  std::vector<LatticeMeasure> out(which.size());
  tbb::parallel_for(size_t{0}, which.size(), [&](size_t i) {
    const auto& t = pattern.face(which[i]);
    const Lattice& l = *lattices[orders[i]];
    LatticeMeasure& m = out[i];
    Eigen::Index worst = -1;
    m.distance = faces.MeasurePoints(
        which[i], points, with_normals ? &normals : nullptr, offset[i],
        offset[i + 1] - offset[i], threshold, &m.angle_ok, &m.angle, &worst);
    m.order = orders[i];
    if (m.angle_ok && m.distance > kAscentFrom * threshold &&
        m.distance <= threshold) {
      m.peaks = LatticePeaks(faces, which[i], l, points, offset[i], threshold);
    }
    const auto image = [&](int x) -> Eigen::Vector3d {
      return x < 0 ? samples.positions[t[-1 - x]]
                   : Eigen::Vector3d(points.row(offset[i] + x).transpose());
    };
    const auto flat = [&](int x) -> Eigen::Vector3d {
      if (x < 0) return samples.positions[t[-1 - x]];
      const Eigen::Vector3d& w = l.weights[x];
      return w[0] * samples.positions[t[0]] + w[1] * samples.positions[t[1]] +
             w[2] * samples.positions[t[2]];
    };
    double stretch2 = 1.0;
    for (const auto& [x, y] : l.edges) {
      const double along = (flat(x) - flat(y)).squaredNorm();
      const double imaged = (image(x) - image(y)).squaredNorm();
      if (imaged > stretch2 * along) {
        stretch2 = along > 0.0 ? imaged / along : 1e300;
      }
    }
    m.stretch = std::sqrt(stretch2);
  });
  MeasureMeshSide(surface, samples, which, lattices, orders, offset, directions,
                  points, threshold, &out, evaluations);
  return out;
}

// From the farthest lattice point of each face (faces[i], measured[i]),
// a pattern search over the face's barycentric coordinates for a larger
// distance: six neighbours at a step of half the lattice spacing, the best
// taken while it gains, the step halved when none does, kAscentSteps
// halvings. It finds maxima narrower than the lattice spacing that rise on
// a lattice point's flank (a small bump on a large flat face). Raises
// measured[i].distance; one batch of evaluations per iteration.
constexpr int kAscentSteps = 5;

void Ascend(const SurfaceSampler& surface, const SampledFaces& faces,
            const std::vector<int>& which, double threshold,
            std::vector<LatticeMeasure>* measured, int64_t* evaluations) {
  const SphereTriangulation& pattern = faces.samples().pattern;
  struct Climb {
    size_t i;
    Eigen::Vector3d at;
    double step;
    double distance;  // at `at`
    int halvings = 0;
  };
  std::vector<Climb> climbs;
  for (size_t i = 0; i < which.size(); ++i) {
    const LatticeMeasure& m = (*measured)[i];
    if (!m.angle_ok || !(m.distance <= threshold)) continue;
    for (const Eigen::Vector3d& w : m.peaks) {
      climbs.push_back({i, w, 0.5 / m.order, m.distance});
    }
  }
  static const double kMoves[6][3] = {{1, -1, 0}, {-1, 1, 0}, {1, 0, -1},
                                      {-1, 0, 1}, {0, 1, -1}, {0, -1, 1}};
  while (!climbs.empty()) {
    const Eigen::Index n = static_cast<Eigen::Index>(climbs.size());
    Eigen::MatrixX3d directions(6 * n, 3), points;
    std::vector<Eigen::Vector3d> weights(6 * n);
    tbb::parallel_for(Eigen::Index{0}, n, [&](Eigen::Index c) {
      const Climb& climb = climbs[c];
      const auto& t = pattern.face(which[climb.i]);
      for (int k = 0; k < 6; ++k) {
        Eigen::Vector3d w =
            climb.at + climb.step * Eigen::Vector3d(kMoves[k][0], kMoves[k][1],
                                                    kMoves[k][2]);
        w = w.cwiseMax(0.0);
        w /= w.sum();
        weights[6 * c + k] = w;
        directions.row(6 * c + k) =
            (w[0] * pattern.vertex(t[0]) + w[1] * pattern.vertex(t[1]) +
             w[2] * pattern.vertex(t[2]))
                .normalized()
                .transpose();
      }
    });
    surface.Sample(directions, &points, nullptr);
    *evaluations += directions.rows();
    std::vector<char> done(n, 0);
    // Climbs of one face run in one task (they raise its distance).
    std::vector<Eigen::Index> start{0};
    for (Eigen::Index c = 1; c < n; ++c) {
      if (climbs[c].i != climbs[c - 1].i) start.push_back(c);
    }
    start.push_back(n);
    tbb::parallel_for(size_t{0}, start.size() - 1, [&](size_t g) {
      for (Eigen::Index c = start[g]; c < start[g + 1]; ++c) {
        Climb& climb = climbs[c];
        LatticeMeasure& m = (*measured)[climb.i];
        double best = climb.distance;
        int moved = -1;
        for (int k = 0; k < 6; ++k) {
          bool angle_ok = true;
          double angle = 0.0;
          Eigen::Index worst = 0;
          const double d =
              faces.MeasurePoints(which[climb.i], points, nullptr, 6 * c + k, 1,
                                  threshold, &angle_ok, &angle, &worst);
          if (d > best) {
            best = d;
            moved = k;
          }
        }
        if (moved >= 0) {
          climb.distance = best;
          climb.at = weights[6 * c + moved];
          m.distance = std::max(m.distance, best);
        } else {
          climb.step *= 0.5;
          ++climb.halvings;
        }
        done[c] = climb.halvings >= kAscentSteps || m.distance > threshold;
      }
    });
    std::vector<Climb> next;
    for (Eigen::Index c = 0; c < n; ++c) {
      if (!done[c]) next.push_back(climbs[c]);
    }
    climbs = std::move(next);
  }
}

constexpr double kRightAngle = 1.57079632679489661923;  // radians
enum : char { kPassed, kDistanceFailed, kAngleFailed };
// A face still outside the angle after this many splits for it is left with
// its measured angle (the report's max_normal_angle_degrees), unless that is
// above 90 degrees (a face across a fold or a cusp, split until it is below
// the tolerance): over a fillet much narrower than the face, each split
// halves the face but not the turn of the normals, and the splits would not
// end before the faces are smaller than the tolerance, about
// (face / tolerance)^2 of them.
constexpr char kMaxAngleSplits = 8;
// ... and one above 90 degrees after this many: the normals of a surface
// that turns back on itself along a curve (a cusp the fit left in the kept
// region) stay more than 90 degrees apart across every face on it however
// small, so splitting it would not end before VerificationOptions::
// max_faces (an open part of CGAL-style CAD, 2CylinderEngine's part 43:
// 77,000 faces after 18,700 rounds and growing). It is left uncertified
// (VerificationResult::uncertified_faces).
constexpr char kMaxFoldSplits = 20;

// The half-edge of face f to split: the longest image edge for a distance
// failure (the chord that misses the surface); the longest domain edge for
// an angular one (the normals turn with the domain: bisecting it shrinks
// the face's image below the angular test's length wherever they never
// settle, as at a cusp).
int SplitEdgeOf(const SurfaceSamples& samples, int f, bool in_domain) {
  const SphereTriangulation& pattern = samples.pattern;
  const auto& t = pattern.face(f);
  int edge = 3 * f;
  double longest2 = -1.0;
  for (int e = 0; e < 3; ++e) {
    const int a = t[e], b = t[(e + 1) % 3];
    const double l2 =
        in_domain ? (pattern.vertex(b) - pattern.vertex(a)).squaredNorm()
                  : (samples.positions[b] - samples.positions[a]).squaredNorm();
    if (l2 > longest2) {
      longest2 = l2;
      edge = 3 * f + e;
    }
  }
  return edge;
}

double ShortestDomainEdge(const SphereTriangulation& pattern, int f) {
  const auto& t = pattern.face(f);
  double s = 4.0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d& a = pattern.vertex(t[i]);
    const Eigen::Vector3d& b = pattern.vertex(t[(i + 1) % 3]);
    s = std::min(s, std::atan2(a.cross(b).norm(), a.dot(b)));
  }
  return s;
}

// Per face slot, what the verification keeps between rounds.
struct FaceState {
  std::vector<double> lattice_error;
  std::vector<double> angle;
  std::vector<char> settled;  // too small
  std::vector<char> was_flipped;
  // How many splits for the angle its domain triangle went through
  // (kMaxAngleSplits ends them).
  std::vector<char> angle_splits;

  explicit FaceState(int slots)
      : lattice_error(slots, 0.0),
        angle(slots, 0.0),
        settled(slots, 0),
        was_flipped(slots, 0),
        angle_splits(slots, 0) {}
};

// Measures faces `pending` on their lattices of order options.lattice and,
// where the lattice may miss the maximum (near the threshold, or a
// stretched image), again finer; then the ascents from the lattice peaks.
std::vector<LatticeMeasure> MeasurePending(const SurfaceSampler& surface,
                                           const SampledFaces& faces,
                                           const std::vector<int>& pending,
                                           const VerificationOptions& options,
                                           int64_t* evaluations) {
  const Eigen::Index n = static_cast<Eigen::Index>(pending.size());
  std::vector<LatticeMeasure> measured =
      MeasureLattices(surface, faces, pending,
                      std::vector<int>(pending.size(), options.lattice),
                      options.threshold, evaluations);
  std::vector<int> again, orders;
  std::vector<size_t> again_index;
  for (Eigen::Index i = 0; i < n; ++i) {
    const LatticeMeasure& m = measured[i];
    const double distance = std::max(m.distance, m.mesh_sampled);
    if (!m.angle_ok || !(distance <= options.threshold)) continue;
    if (distance > kRecheckFraction * options.threshold ||
        m.stretch > kMaxStretch) {
      again.push_back(pending[i]);
      again_index.push_back(i);
      orders.push_back(std::min<int>(
          kMaxOrder,
          static_cast<int>(std::ceil(
              options.lattice *
              std::min(10.0, std::max(kRecheckRefinement, m.stretch))))));
    }
  }
  if (!again.empty()) {
    const std::vector<LatticeMeasure> finer = MeasureLattices(
        surface, faces, again, orders, options.threshold, evaluations);
    for (size_t j = 0; j < again.size(); ++j) {
      LatticeMeasure& m = measured[again_index[j]];
      if (finer[j].distance > m.distance || !finer[j].peaks.empty()) {
        m.peaks = finer[j].peaks;
        m.order = finer[j].order;
      }
      m.distance = std::max(m.distance, finer[j].distance);
      m.mesh_distance = std::max(m.mesh_sampled, finer[j].mesh_distance);
      m.mesh_sampled = std::max(m.mesh_sampled, finer[j].mesh_sampled);
      m.angle = std::max(m.angle, finer[j].angle);
      m.angle_ok = m.angle_ok && finer[j].angle_ok;
    }
  }
  Ascend(surface, faces, pending, options.threshold, &measured, evaluations);
  return measured;
}

// Records each measured face's error and angle in `state` and returns per
// face whether it passed, failed the distance or failed the angle.
std::vector<char> Judge(const SampledFaces& faces,
                        const std::vector<int>& pending,
                        const std::vector<LatticeMeasure>& measured,
                        double threshold, FaceState* state) {
  std::vector<char> failed(pending.size(), kPassed);
  for (size_t i = 0; i < pending.size(); ++i) {
    const int f = pending[i];
    state->lattice_error[f] =
        std::max(measured[i].distance, measured[i].mesh_distance);
    state->angle[f] = measured[i].angle;
    if (!(state->lattice_error[f] <= threshold) ||
        !(faces.error(f) <= threshold)) {
      failed[i] = kDistanceFailed;
    } else if (!measured[i].angle_ok) {
      const char depth = state->angle_splits[f];
      if (depth < kMaxAngleSplits ||
          (measured[i].angle > kRightAngle && depth < kMaxFoldSplits)) {
        failed[i] = kAngleFailed;
      } else if (measured[i].angle > kRightAngle) {
        state->settled[f] = 1;
      }
    }
  }
  return failed;
}

// The flips: one of a failing face's edges whose two new faces pass (their
// samples and lattices) repairs it without new faces. Once per face: a flip
// that passed on the base lattice may fail the finer one, and flipping back
// would never end. They run before any split of the round, whose midpoints
// are not evaluated yet. Marks the faces in `touched` and appends them to
// `changed`.
void FlipFailing(const std::vector<int>& pending,
                 const std::vector<char>& failed, double threshold,
                 SampledFaces* faces, FaceState* state,
                 std::vector<char>* touched, std::vector<int>* changed) {
  SphereTriangulation& pattern = faces->samples().pattern;
  std::vector<char>& was_flipped = state->was_flipped;
  for (size_t i = 0; i < pending.size(); ++i) {
    const int f = pending[i];
    if (!failed[i] || (*touched)[f] || was_flipped[f]) continue;
    for (int e = 0; e < 3; ++e) {
      const int h = 3 * f + e;
      const int g = pattern.Twin(h) / 3;
      std::array<SphereTriangulation::Face, 2> two;
      if ((*touched)[g] || was_flipped[g] || !pattern.PreviewFlip(h, &two)) {
        continue;
      }
      FaceChange change;
      change.faces.assign(two.begin(), two.end());
      change.slots = {f, g};
      change.old_faces = {f, g};
      ChangeResult checked;
      if (!faces->Evaluate(change, threshold, &checked)) continue;
      pattern.Flip(h);
      faces->Apply(change, &checked);
      (*touched)[f] = (*touched)[g] = 1;
      was_flipped[f] = was_flipped[g] = 1;
      changed->push_back(f);
      changed->push_back(g);
      break;
    }
  }
}

// The splits of the faces still failing: each (SplitEdgeOf) at the edge's
// domain midpoint, with the face across it (each face at most once per
// round). Appends the new midpoints to `midpoints`, the changes to
// `changes` (their new faces not yet filled in), the changed slots to
// `changed` and the faces to measure again that could not be split this
// round to `next`. Returns the number of splits.
int64_t SplitFailing(const std::vector<int>& pending,
                     const std::vector<char>& failed, double min_edge_radians,
                     SurfaceSamples* samples, FaceState* state,
                     std::vector<char>* touched, std::vector<int>* next,
                     std::vector<int>* changed, std::vector<int>* midpoints,
                     std::vector<FaceChange>* changes) {
  SphereTriangulation& pattern = samples->pattern;
  int64_t splits = 0;
  for (size_t i = 0; i < pending.size(); ++i) {
    const int f = pending[i];
    if (!failed[i] || !pattern.alive(f)) continue;
    if ((*touched)[f]) {
      next->push_back(f);
      continue;
    }
    if (ShortestDomainEdge(pattern, f) < min_edge_radians) {
      state->settled[f] = 1;
      continue;
    }
    const int edge = SplitEdgeOf(*samples, f, failed[i] == kAngleFailed);
    const int g = pattern.Twin(edge) / 3;
    if ((*touched)[g]) {
      next->push_back(f);
      continue;
    }
    const int a = pattern.Origin(edge), b = pattern.Target(edge);
    const int m = pattern.SplitEdge(
        edge, (pattern.vertex(a) + pattern.vertex(b)).normalized());
    midpoints->push_back(m);
    FaceChange change;
    change.old_faces = {f, g};
    change.slots = {f, g, pattern.num_face_slots() - 2,
                    pattern.num_face_slots() - 1};
    ++splits;
    touched->resize(pattern.num_face_slots(), 0);
    state->was_flipped.resize(pattern.num_face_slots(), 0);
    state->angle_splits.resize(pattern.num_face_slots(), 0);
    const char depth = static_cast<char>(
        std::max(state->angle_splits[f], state->angle_splits[g]) +
        (failed[i] == kAngleFailed ? 1 : 0));
    for (int x : change.slots) {
      (*touched)[x] = 1;
      state->was_flipped[x] = 0;
      state->angle_splits[x] = depth;
      changed->push_back(x);
    }
    changes->push_back(std::move(change));
  }
  return splits;
}

// After a round's splits: the midpoints evaluated (the newest vertices, one
// batch), the samples of the split faces redistributed, and the faces to
// measure next: the changed ones and their neighbours (whose triangles
// across changed), with `next`, alive and not settled, ascending.
std::vector<int> FinishRound(const SurfaceSampler& surface,
                             const std::vector<int>& midpoints,
                             const std::vector<int>& changed,
                             std::vector<FaceChange>* changes,
                             std::vector<int> next, SampledFaces* faces,
                             FaceState* state) {
  SurfaceSamples& samples = faces->samples();
  SphereTriangulation& pattern = samples.pattern;
  if (!midpoints.empty()) {
    EvaluateNewVertices(surface, midpoints.front(), &samples);
  }
  faces->Resize();
  state->lattice_error.resize(pattern.num_face_slots(), 0.0);
  state->angle.resize(pattern.num_face_slots(), 0.0);
  state->settled.resize(pattern.num_face_slots(), 0);
  state->was_flipped.resize(pattern.num_face_slots(), 0);
  for (FaceChange& change : *changes) {
    for (int x : change.slots) change.faces.push_back(pattern.face(x));
    faces->Reassign(change);
  }
  for (int x : changed) {
    state->settled[x] = 0;
    next.push_back(x);
    for (int e = 0; e < 3; ++e) next.push_back(pattern.Twin(3 * x + e) / 3);
  }
  std::sort(next.begin(), next.end());
  next.erase(std::unique(next.begin(), next.end()), next.end());
  next.erase(std::remove_if(
                 next.begin(), next.end(),
                 [&](int f) { return !pattern.alive(f) || state->settled[f]; }),
             next.end());
  return next;
}

}  // namespace

Status VerifyFaces(const SurfaceSampler& surface,
                   const VerificationOptions& options, SampledFaces* faces,
                   VerificationResult* result) {
  if (options.lattice < 2 || options.lattice > 16) {
    return InvalidArgumentError("the lattice order must be in [2, 16]");
  }
  SurfaceSamples& samples = faces->samples();
  SphereTriangulation& pattern = samples.pattern;
  FaceState state(pattern.num_face_slots());
  std::vector<int> pending;
  for (int f = 0; f < pattern.num_face_slots(); ++f) {
    if (pattern.alive(f)) pending.push_back(f);
  }
  // Flips that repair a face are measured on the lattice too.
  faces->SetLattice(&surface, options.lattice);
  struct NoLattice {
    SampledFaces* faces;
    ~NoLattice() { faces->SetLattice(nullptr, 0); }
  } no_lattice{faces};
  std::vector<char> kept;
  const auto keep_region = [&]() -> Status {
    if (!options.kept_region_only) return Status::Ok();
    SDCB_ASSIGN_OR_RETURN(kept, KeptFaceSlots(pattern));
    pending.erase(std::remove_if(pending.begin(), pending.end(),
                                 [&](int f) { return !kept[f]; }),
                  pending.end());
    return Status::Ok();
  };
  SDCB_RETURN_IF_ERROR(keep_region());
  while (!pending.empty()) {
    const std::vector<LatticeMeasure> measured =
        MeasurePending(surface, *faces, pending, options, &result->evaluations);
    const std::vector<char> failed =
        Judge(*faces, pending, measured, options.threshold, &state);
    // Each failing face is repaired by a flip or split (SplitEdgeOf) at the
    // edge's domain midpoint, with the face across it; the midpoints are
    // evaluated in one batch and the two faces' samples redistributed among
    // the four.
    std::vector<char> touched(pattern.num_face_slots(), 0);
    std::vector<int> next, changed, midpoints;
    std::vector<FaceChange> changes;
    FlipFailing(pending, failed, options.threshold, faces, &state, &touched,
                &changed);
    const int64_t splits =
        SplitFailing(pending, failed, options.min_edge_radians, &samples,
                     &state, &touched, &next, &changed, &midpoints, &changes);
    if (pattern.num_faces() > options.max_faces) {
      return InvalidInputError("the tolerance needs more than " +
                               std::to_string(options.max_faces) +
                               " triangles");
    }
    next = FinishRound(surface, midpoints, changed, &changes, std::move(next),
                       faces, &state);
    result->splits += splits;
    if (options.progress) options.progress(pending.size(), splits);
    pending = std::move(next);
    SDCB_RETURN_IF_ERROR(keep_region());
  }
  SDCB_RETURN_IF_ERROR(keep_region());
  result->max_distance = 0.0;
  result->max_angle = 0.0;
  result->uncertified_faces = 0;
  for (int f = 0; f < pattern.num_face_slots(); ++f) {
    if (!pattern.alive(f) || (options.kept_region_only && !kept[f])) continue;
    result->max_distance = std::max(
        {result->max_distance, state.lattice_error[f], faces->error(f)});
    result->max_angle = std::max(result->max_angle, state.angle[f]);
    if (state.settled[f]) ++result->uncertified_faces;
  }
  return Status::Ok();
}

}  // namespace sdcb
