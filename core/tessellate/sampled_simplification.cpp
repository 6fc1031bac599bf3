#include "sdcb/core/tessellate/sampled_simplification.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace sdcb {
namespace {

// The thresholds of the collapse passes, as fractions of the final one: the
// cheapest collapses everywhere first. Flips run from kFirstFlipPass on.
constexpr double kPassFractions[] = {0.03, 0.06, 0.1, 0.15, 0.22, 0.3,
                                     0.4,  0.5,  0.6, 0.7,  0.8,  0.9,
                                     1.0,  1.0,  1.0, 1.0};
constexpr int kFirstFlipPass = 7;
// From this fraction on, changes are measured on a lattice too.
constexpr double kLatticeFrom = 0.4;
// Targets certified per vertex (those of lowest estimate).
constexpr int kTargetsTried = 2;
constexpr int kAllTargetsFrom = 9;  // pass index

// One candidate change and what its certificate found.
struct Decision {
  bool made = false;
  FaceChange change;
  ChangeResult result;
  int a = -1, b = -1;  // collapse a into b, or flip the half-edge a
  // The vertices whose stars the evaluation read (the corners of the old
  // faces).
  std::vector<int> reads;
};

class Simplifier {
 public:
  Simplifier(const SimplificationOptions& options, SampledFaces* faces)
      : options_(options),
        faces_(*faces),
        pattern_(faces->samples().pattern),
        positions_(faces->samples().positions) {}

  void Run() {
    struct NoLattice {
      SampledFaces& faces;
      ~NoLattice() { faces.SetLattice(nullptr, 0); }
    } no_lattice{faces_};
    const int passes = static_cast<int>(std::size(kPassFractions));
    for (int pass = 0; pass < passes; ++pass) {
      const double t = kPassFractions[pass] * options_.threshold;
      pass_ = pass;
      if (options_.lattice_surface && kPassFractions[pass] >= kLatticeFrom) {
        faces_.SetLattice(options_.lattice_surface, options_.lattice);
      }
      CollapsePass(t);
      if (pass >= kFirstFlipPass) FlipPass(t);
      if (options_.progress) {
        options_.progress(pass + 1, passes, pattern_.num_faces());
      }
    }
  }

 private:
  // Evaluates the items of `queue` and makes the changes that pass, as if
  // one after another in queue order: batches of kBatch items are evaluated
  // in parallel against the pattern before the batch; then, in order, a
  // passing change is made unless a change made earlier in the batch
  // touched a corner of its old faces (what its evaluation read), in which
  // case it is evaluated again first. The result depends on kBatch, not on
  // the number of threads.
  template <typename Evaluate, typename Make>
  void RunInOrder(const std::vector<int>& queue, const Evaluate& evaluate,
                  const Make& make) {
    constexpr size_t kBatch = 512;
    std::vector<Decision> decisions(kBatch);
    if (stamp_.size() < size_t(pattern_.num_vertices())) {
      stamp_.resize(pattern_.num_vertices(), -1);
    }
    for (size_t first = 0; first < queue.size(); first += kBatch) {
      const size_t n = std::min(kBatch, queue.size() - first);
      ++batch_;
      tbb::parallel_for(size_t{0}, n, [&](size_t i) {
        decisions[i].made = false;
        evaluate(queue[first + i], &decisions[i]);
      });
      for (size_t i = 0; i < n; ++i) {
        Decision& d = decisions[i];
        if (!d.made) continue;
        bool stale = false;
        for (int v : d.reads) stale = stale || stamp_[v] == batch_;
        if (stale) {
          d.made = false;
          evaluate(queue[first + i], &d);
          if (!d.made) continue;
        }
        make(&d);
        for (const auto& t : d.change.faces) {
          for (int v : t) stamp_[v] = batch_;
        }
        for (int v : d.change.freed) stamp_[v] = batch_;
      }
    }
  }

  // Estimated cost of collapsing v into each neighbour: the largest
  // distance of the neighbour's point from the planes of v's faces that do
  // not contain it.
  void Estimates(int v, std::vector<int>* ring,
                 std::vector<double>* estimate) const {
    thread_local std::vector<int> star;
    thread_local std::vector<Eigen::Vector3d> normals;
    pattern_.Star(v, &star, ring);
    const size_t n = ring->size();
    normals.resize(n);
    const Eigen::Vector3d& pv = positions_[v];
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d cross =
          (positions_[(*ring)[i]] - pv)
              .cross(positions_[(*ring)[(i + 1) % n]] - pv);
      const double norm = cross.norm();
      normals[i] =
          norm > 0.0 ? Eigen::Vector3d(cross / norm) : Eigen::Vector3d::Zero();
    }
    estimate->assign(n, 0.0);
    for (size_t j = 0; j < n; ++j) {
      const Eigen::Vector3d d = positions_[(*ring)[j]] - pv;
      for (size_t i = 0; i < n; ++i) {
        if (i == j || (i + 1) % n == j) continue;  // faces containing w
        (*estimate)[j] = std::max((*estimate)[j], std::abs(normals[i].dot(d)));
      }
    }
  }

  // Forgets what is known of the collapses of the corners of `faces` (their
  // stars changed).
  void Touch(const std::vector<SphereTriangulation::Face>& faces) {
    for (const auto& t : faces) {
      for (int v : t) known_[v] = 0;
    }
  }

  void CollapsePass(double threshold) {
    const int nv = pattern_.num_vertices();
    if (known_.size() < size_t(nv)) {
      known_.resize(nv, 0);
      bound_.resize(nv, 0.0);
      estimate_.resize(nv, 0.0);
    }
    // Vertices in the order of their cheapest estimate, without those whose
    // tried collapses failed above this threshold, their stars unchanged.
    std::vector<int> vertices;
    const auto consider = [&](int v) {
      if (pattern_.vertex_alive(v) && !(known_[v] && bound_[v] > threshold)) {
        vertices.push_back(v);
      }
    };
    for (int v = 0; v < nv; ++v) consider(v);
    std::vector<double> best(vertices.size());
    tbb::parallel_for(size_t{0}, vertices.size(), [&](size_t i) {
      const int v = vertices[i];
      if (!known_[v]) {
        thread_local std::vector<int> ring;
        thread_local std::vector<double> estimate;
        Estimates(v, &ring, &estimate);
        estimate_[v] = *std::min_element(estimate.begin(), estimate.end());
      }
      best[i] = estimate_[v];
    });
    std::vector<int> order(vertices.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int x, int y) { return best[x] < best[y]; });
    std::vector<int> queue(vertices.size());
    for (size_t i = 0; i < order.size(); ++i) queue[i] = vertices[order[i]];

    const auto evaluate = [&](int v, Decision* d) {
      if (!pattern_.vertex_alive(v)) return;
      thread_local std::vector<int> ring, star, targets;
      thread_local std::vector<double> estimate;
      thread_local FaceChange change;
      thread_local ChangeResult result;
      Estimates(v, &ring, &estimate);
      targets.resize(ring.size());
      std::iota(targets.begin(), targets.end(), 0);
      const size_t tried = std::min<size_t>(
          pass_ >= kAllTargetsFrom ? ring.size() : kTargetsTried, ring.size());
      std::partial_sort(targets.begin(), targets.begin() + tried, targets.end(),
                        [&](int x, int y) {
                          return estimate[x] < estimate[y] ||
                                 (estimate[x] == estimate[y] && x < y);
                        });
      pattern_.Star(v, &star, nullptr);
      double bound = std::numeric_limits<double>::infinity();
      for (size_t k = 0; k < tried; ++k) {
        const int w = ring[targets[k]];
        if (!pattern_.PreviewCollapse(v, w, &change.faces, &change.slots)) {
          continue;
        }
        change.old_faces = star;
        change.freed = {v};
        if (!faces_.Evaluate(change, threshold, &result)) {
          bound = std::min(bound, result.failed_at);
          continue;
        }
        if (d->made && result.worst >= d->result.worst) continue;
        d->made = true;
        d->a = v;
        d->b = w;
        d->change = change;
        d->result = result;
        d->reads.assign(ring.begin(), ring.end());
        d->reads.push_back(v);
      }
      if (!d->made) {
        known_[v] = 1;
        bound_[v] = bound;
        estimate_[v] = estimate[targets[0]];
      }
    };
    const auto make = [&](Decision* d) {
      pattern_.Collapse(d->a, d->b);
      faces_.Apply(d->change, &d->result);
      Touch(d->change.faces);
    };
    RunInOrder(queue, evaluate, make);
  }

  void FlipPass(double threshold) {
    // Each edge once, by its half-edge of the smaller face slot.
    std::vector<int> queue;
    for (int f = 0; f < pattern_.num_face_slots(); ++f) {
      if (!pattern_.alive(f)) continue;
      for (int e = 0; e < 3; ++e) {
        const int h = 3 * f + e;
        if (h < pattern_.Twin(h)) queue.push_back(h);
      }
    }
    // Half-edges are re-read at evaluation: a flip nearby changes what a
    // half-edge index names, so each item carries its two vertices.
    std::vector<std::array<int, 2>> ends(queue.size());
    for (size_t i = 0; i < queue.size(); ++i) {
      ends[i] = {pattern_.Origin(queue[i]), pattern_.Target(queue[i])};
    }
    std::vector<int> items(queue.size());
    std::iota(items.begin(), items.end(), 0);
    const auto evaluate = [&](int i, Decision* d) {
      thread_local std::array<SphereTriangulation::Face, 2> flipped;
      thread_local FaceChange change;
      thread_local ChangeResult result;
      const int h = pattern_.HalfEdge(ends[i][0], ends[i][1]);
      if (h < 0 || !pattern_.PreviewFlip(h, &flipped)) return;
      const int f = h / 3, g = pattern_.Twin(h) / 3;
      const double before = std::max(faces_.error(f), faces_.error(g));
      change.faces.assign(flipped.begin(), flipped.end());
      change.slots = {f, g};
      change.old_faces = {f, g};
      change.freed.clear();
      if (!faces_.Evaluate(change, std::min(threshold, before), &result)) {
        return;
      }
      if (!(result.worst < 0.98 * before)) return;
      d->made = true;
      d->a = i;
      d->change = change;
      d->result = result;
      d->reads = {pattern_.Origin(h), pattern_.Target(h), pattern_.Apex(h),
                  pattern_.Apex(pattern_.Twin(h))};
    };
    const auto make = [&](Decision* d) {
      pattern_.Flip(pattern_.HalfEdge(ends[d->a][0], ends[d->a][1]));
      faces_.Apply(d->change, &d->result);
      Touch(d->change.faces);
    };
    RunInOrder(items, evaluate, make);
  }

  // Per vertex: whether its star is unchanged since its collapses were
  // last certified and failed, the least distance that failed them, and
  // its cheapest estimate then.
  int pass_ = 0;
  // Per vertex: the last batch of RunInOrder that changed its star.
  std::vector<int64_t> stamp_;
  int64_t batch_ = 0;
  std::vector<char> known_;
  std::vector<double> bound_, estimate_;
  const SimplificationOptions options_;
  SampledFaces& faces_;
  SphereTriangulation& pattern_;
  const std::vector<Eigen::Vector3d>& positions_;
};

}  // namespace

void SimplifySampledFaces(const SimplificationOptions& options,
                          SampledFaces* faces) {
  Simplifier(options, faces).Run();
}

}  // namespace sdcb
