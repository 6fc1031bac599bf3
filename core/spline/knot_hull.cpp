#include "sdcb/core/spline/knot_hull.h"

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <utility>

#include "sdcb/core/sphere/perturbed_predicates.h"

namespace sdcb {
namespace {

Status NotConvexError(int knot) {
  return InvalidArgumentError(
      "knot " + std::to_string(knot) +
      " is not a vertex of the knots' convex hull (knots off the sphere, or "
      "three or more knots within about 1e-8 of each other)");
}

struct Facet {
  std::array<int, 3> v;    // counter-clockwise seen from outside
  std::array<int, 3> adj;  // adj[i]: facet across edge (v[i], v[i+1])
  bool alive = true;
  std::vector<int> conflicts;  // uninserted knots that see this facet
};

class HullBuilder {
 public:
  // Builds the hull of the knots ids[0..]; internally knots are numbered by
  // their position in `ids`.
  HullBuilder(const Eigen::MatrixX3d& knots, std::vector<int> ids)
      : knots_(knots),
        ids_(std::move(ids)),
        n_(static_cast<int>(ids_.size())),
        knot_facets_(n_),
        inserted_(n_, false),
        knot_stamp_(n_, -1),
        horizon_start_(n_, -1) {}

  Status Build() {
    const std::vector<int> order = InsertionOrder();
    BuildTetrahedron(order);
    for (int t = 4; t < n_; ++t) SDCB_RETURN_IF_ERROR(Insert(order[t]));
    return Status::Ok();
  }

  // Alive facets in knot indices, smallest index first (keeps the
  // orientation), sorted.
  std::vector<std::array<int, 3>> Facets() const {
    std::vector<std::array<int, 3>> result;
    for (const Facet& f : facets_) {
      if (!f.alive) continue;
      std::array<int, 3> v = {ids_[f.v[0]], ids_[f.v[1]], ids_[f.v[2]]};
      std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
      result.push_back(v);
    }
    std::sort(result.begin(), result.end());
    return result;
  }

 private:
  // A fixed pseudo-random order (Fisher-Yates with std::mt19937, whose
  // output the standard fixes) gives the expected O(n log n) bound.
  std::vector<int> InsertionOrder() const {
    std::vector<int> order(n_);
    for (int i = 0; i < n_; ++i) order[i] = i;
    std::mt19937 rng(20240611u);
    for (int i = n_ - 1; i > 0; --i) {
      const int j = static_cast<int>(rng() % static_cast<uint32_t>(i + 1));
      std::swap(order[i], order[j]);
    }
    return order;
  }

  int Orient(int a, int b, int c, int d) const {
    return PerturbedOrient3dSign(knots_, ids_[a], ids_[b], ids_[c], ids_[d]);
  }

  bool Sees(const Facet& f, int q) const {
    return Orient(f.v[0], f.v[1], f.v[2], q) > 0;
  }

  void AddConflict(int facet, int q) {
    facets_[facet].conflicts.push_back(q);
    knot_facets_[q].push_back(facet);
  }

  void BuildTetrahedron(const std::vector<int>& order) {
    const std::array<int, 4> p = {order[0], order[1], order[2], order[3]};
    // Facet i omits p[i]; orient it so that p[i] is on its inner side.
    for (int i = 0; i < 4; ++i) {
      std::array<int, 3> v;
      int m = 0;
      for (int j = 0; j < 4; ++j) {
        if (j != i) v[m++] = p[j];
      }
      if (Orient(v[0], v[1], v[2], p[i]) > 0) {
        std::swap(v[1], v[2]);
      }
      Facet f;
      f.v = v;
      facets_.push_back(f);
    }
    for (int a = 0; a < 4; ++a) {
      for (int i = 0; i < 3; ++i) {
        const int u = facets_[a].v[i], w = facets_[a].v[(i + 1) % 3];
        for (int b = 0; b < 4; ++b) {
          for (int j = 0; j < 3; ++j) {
            if (facets_[b].v[j] == w && facets_[b].v[(j + 1) % 3] == u) {
              facets_[a].adj[i] = b;
            }
          }
        }
      }
    }
    for (int t = 0; t < 4; ++t) inserted_[p[t]] = true;
    for (int t = 4; t < n_; ++t) {
      for (int f = 0; f < 4; ++f) {
        if (Sees(facets_[f], order[t])) AddConflict(f, order[t]);
      }
    }
  }

  Status Insert(int p) {
    const int step = step_++;
    std::vector<int> visible;
    for (int f : knot_facets_[p]) {
      if (facets_[f].alive) visible.push_back(f);
    }
    knot_facets_[p].clear();
    knot_facets_[p].shrink_to_fit();
    if (visible.empty()) {
      return NotConvexError(ids_[p]);
    }
    facet_mark_.resize(facets_.size(), -1);
    for (int f : visible) facet_mark_[f] = step;
    // Horizon: edges of visible facets whose other facet stays.
    std::vector<int> created;
    for (int f : visible) {
      for (int i = 0; i < 3; ++i) {
        const int g = facets_[f].adj[i];
        if (facet_mark_[g] == step) continue;
        const int u = facets_[f].v[i], w = facets_[f].v[(i + 1) % 3];
        Facet h;
        h.v = {u, w, p};
        h.adj = {g, -1, -1};
        const int id = static_cast<int>(facets_.size());
        for (int j = 0; j < 3; ++j) {
          if (facets_[g].adj[j] == f) facets_[g].adj[j] = id;
        }
        facets_.push_back(std::move(h));
        facet_mark_.push_back(-1);
        horizon_start_[u] = id;
        created.push_back(id);
        // Conflicts of the new facet are among those of f and g.
        for (int source : {f, g}) {
          for (int q : facets_[source].conflicts) {
            if (q == p || inserted_[q] || knot_stamp_[q] == id) continue;
            knot_stamp_[q] = id;
            if (Sees(facets_[id], q)) AddConflict(id, q);
          }
        }
      }
    }
    for (int h : created) {
      const int next = horizon_start_[facets_[h].v[1]];
      facets_[h].adj[1] = next;  // edge (w, p) is the twin of next's (p, w)
      facets_[next].adj[2] = h;
    }
    for (int f : visible) {
      facets_[f].alive = false;
      facets_[f].conflicts.clear();
      facets_[f].conflicts.shrink_to_fit();
    }
    inserted_[p] = true;
    return Status::Ok();
  }

  const Eigen::MatrixX3d& knots_;
  const std::vector<int> ids_;  // knot index of each local number
  const int n_;
  std::vector<Facet> facets_;
  std::vector<std::vector<int>> knot_facets_;  // conflict graph, knot side
  std::vector<bool> inserted_;
  std::vector<int> knot_stamp_;     // dedupes candidate knots per new facet
  std::vector<int> horizon_start_;  // new facet whose horizon edge starts here
  std::vector<int> facet_mark_;     // == step for facets visible at that step
  int step_ = 0;                    // insertions done after the tetrahedron
};

}  // namespace

StatusOr<KnotHull> ComputeKnotHull(const Eigen::MatrixX3d& knots) {
  if (knots.rows() < 4) {
    return InvalidArgumentError("a hull needs at least 4 knots, got " +
                                std::to_string(knots.rows()));
  }
  std::vector<int> all(knots.rows());
  for (int i = 0; i < knots.rows(); ++i) all[i] = i;
  HullBuilder builder(knots, std::move(all));
  SDCB_RETURN_IF_ERROR(builder.Build());
  KnotHull hull;
  hull.facets = builder.Facets();
  hull.neighbors.resize(knots.rows());
  for (const auto& f : hull.facets) {
    for (int i = 0; i < 3; ++i) hull.neighbors[f[i]].push_back(f[(i + 1) % 3]);
  }
  for (std::vector<int>& nb : hull.neighbors) std::sort(nb.begin(), nb.end());
  // A knot inserted early can end up inside the final hull only if the
  // knots are not in convex position.
  for (int i = 0; i < knots.rows(); ++i) {
    if (hull.neighbors[i].empty()) return NotConvexError(i);
  }
  return hull;
}

StatusOr<std::vector<std::array<int, 3>>> ComputeKnotSubsetHull(
    const Eigen::MatrixX3d& knots, const std::vector<int>& subset) {
  if (subset.size() < 4) {
    return InvalidArgumentError("a hull needs at least 4 knots, got " +
                                std::to_string(subset.size()));
  }
  HullBuilder builder(knots, subset);
  SDCB_RETURN_IF_ERROR(builder.Build());
  std::vector<std::array<int, 3>> facets = builder.Facets();
  if (facets.size() != 2 * subset.size() - 4) {
    return NotConvexError(subset[0]);
  }
  return facets;
}

}  // namespace sdcb
