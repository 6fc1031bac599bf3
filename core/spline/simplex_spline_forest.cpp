#include "sdcb/core/spline/simplex_spline_forest.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>

namespace sdcb {
namespace {

std::uint64_t NextForestId() {
  static std::atomic<std::uint64_t> next{0};
  return ++next;
}

std::array<int, 8> SubsetKey(std::uint32_t mask,
                             const std::vector<int>& global) {
  std::array<int, 8> key;
  key.fill(-1);
  int n = 0;
  for (size_t j = 0; j < global.size(); ++j) {
    if (mask & (1u << j)) key[n++] = global[j];
  }
  return key;
}

}  // namespace

// One point's memo: a node, pair or generation entry is valid iff its stamp
// equals `generation`, which changes with the point, the order or the forest.
struct SimplexSplineForest::Scratch {
  std::uint64_t forest = 0;
  int order = -1;
  Eigen::Vector3d p =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  double bound = 0.0;  // The sign filter's bound for p (PairSigns).
  std::uint64_t generation = 0;
  // A node's stamp and value side by side: one cache line per lookup.
  struct NodeMemo {
    std::uint64_t stamp = 0;
    double value = 0.0;
  };
  struct PairMemo {
    std::uint64_t stamp = 0;
    int sign = 0;
  };
  std::vector<NodeMemo> node;
  std::vector<char> live;
  std::vector<std::array<double, 3>> gradient;
  std::vector<std::array<double, 9>> hessian;
  std::vector<PairMemo> pair;
};

std::size_t SimplexSplineForest::KeyHash::operator()(
    const std::array<int, 8>& key) const {
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (int v : key) {
    h ^= static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)) +
         0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  }
  return static_cast<std::size_t>(h);
}

SimplexSplineForest::SimplexSplineForest() : id_(NextForestId()) {}

int SimplexSplineForest::Add(const SimplexSpline& spline,
                             const std::vector<int>& global) {
  id_ = NextForestId();  // the memo of an earlier copy no longer applies
  const int m = static_cast<int>(spline.knots_.rows());
  int pair_map[SimplexSpline::kMaxKnots * (SimplexSpline::kMaxKnots - 1) / 2];
  for (int i = 0, k = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j, ++k) {
      std::array<int, 8> key;
      key.fill(-1);
      key[0] = global[i];
      key[1] = global[j];
      auto [it, added] =
          pair_of_.try_emplace(key, static_cast<int>(pairs_.size()));
      if (added) {
        pairs_.push_back({global[i], global[j]});
        pair_knots_.push_back(spline.knots_.row(i).transpose());
        pair_knots_.push_back(spline.knots_.row(j).transpose());
        pair_normals_.push_back(spline.pair_normals_[k]);
      }
      pair_map[k] = it->second;
    }
  // Children come before parents in spline.nodes_.
  int node_map[1 << SimplexSpline::kMaxKnots];
  for (size_t i = 0; i < spline.nodes_.size(); ++i) {
    const SimplexSpline::Node& local = spline.nodes_[i];
    auto [it, added] = node_of_.try_emplace(SubsetKey(local.mask, global),
                                            static_cast<int>(nodes_.size()));
    node_map[i] = it->second;
    if (!added) continue;
    Node node;
    if (local.matrix < 0) {
      node.orientation = local.orientation;
      node.inv_abs_det = local.inv_abs_det;
      if (local.pair[0] >= 0) {
        for (int j = 0; j < 3; ++j) node.pair[j] = pair_map[local.pair[j]];
      }
    } else {
      std::array<int, 8> key;
      key.fill(-1);
      for (int j = 0; j < 3; ++j) key[j] = global[local.local[j]];
      auto [mit, madded] =
          matrix_of_.try_emplace(key, static_cast<int>(matrices_.size()));
      if (madded) matrices_.push_back(spline.matrices_[local.matrix]);
      node.matrix = mit->second;
      for (int j = 0; j < 3; ++j) node.child[j] = node_map[local.child[j]];
    }
    nodes_.push_back(node);
  }
  tops_.push_back(node_map[spline.nodes_.size() - 1]);
  return static_cast<int>(tops_.size()) - 1;
}

void SimplexSplineForest::FinishAdding() {
  node_of_ = {};
  matrix_of_ = {};
  pair_of_ = {};
}

SimplexSplineForest::Scratch& SimplexSplineForest::Begin(
    const Eigen::Vector3d& p, int order) const {
  static thread_local Scratch value_scratch, jet_scratch;
  Scratch& s = order == 0 ? value_scratch : jet_scratch;
  if (s.forest != id_ || s.order != order || !(s.p.x() == p.x()) ||
      !(s.p.y() == p.y()) || !(s.p.z() == p.z())) {
    ++s.generation;
    s.forest = id_;
    s.order = order;
    s.p = p;
    s.bound = kSignFilter * 3.01 * p.cwiseAbs().sum();
  }
  if (s.node.size() < nodes_.size()) {
    s.node.resize(nodes_.size());
    s.live.resize(nodes_.size());
  }
  if (order > 0 && s.gradient.size() < nodes_.size()) {
    s.gradient.resize(nodes_.size());
  }
  if (order > 1 && s.hessian.size() < nodes_.size()) {
    s.hessian.resize(nodes_.size());
  }
  if (s.pair.size() < pairs_.size()) {
    s.pair.resize(pairs_.size());
  }
  return s;
}

int SimplexSplineForest::PairSign(int pair, Scratch& s) const {
  Scratch::PairMemo& memo = s.pair[pair];
  if (memo.stamp != s.generation) {
    memo.stamp = s.generation;
    memo.sign =
        (FilteredSign(s.p.dot(pair_normals_[pair]), s.bound, s.p,
                      pair_knots_[2 * pair], pair_knots_[2 * pair + 1]));
  }
  return memo.sign;
}

// Degree 0: 1 / |det| inside [ta, tb, tc) (SimplexSpline::LeafValue), else
// 0. A pair's memo is read here; PairSign computes it when it is stale.
inline double SimplexSplineForest::LeafValue(const Node& n, Scratch& s) const {
  const auto sign = [&](int pair) {
    const Scratch::PairMemo& memo = s.pair[pair];
    return memo.stamp == s.generation ? memo.sign : PairSign(pair, s);
  };
  const int o = n.orientation;
  return o != 0 && sign(n.pair[0]) == o && sign(n.pair[1]) == -o &&
                 sign(n.pair[2]) == o
             ? n.inv_abs_det
             : 0.0;
}

double SimplexSplineForest::NodeValue(int g, Scratch& s) const {
  if (s.node[g].stamp == s.generation) return s.node[g].value;
  const Node& n = nodes_[g];
  double v = 0.0;
  if (n.matrix < 0) {
    v = LeafValue(n, s);
  } else {
    // Most children were computed for an earlier node of the point: their
    // memo is read here rather than in a call; a stale leaf is computed
    // here too (no call).
    const auto child = [&](int c) {
      Scratch::NodeMemo& memo = s.node[c];
      if (memo.stamp == s.generation) return memo.value;
      const Node& cn = nodes_[c];
      if (cn.matrix >= 0) return NodeValue(c, s);
      memo = {s.generation, LeafValue(cn, s)};
      return memo.value;
    };
    const double v0 = child(n.child[0]);
    const double v1 = child(n.child[1]);
    const double v2 = child(n.child[2]);
    if (!(v0 == 0.0 && v1 == 0.0 && v2 == 0.0)) {
      const Eigen::Vector3d b = matrices_[n.matrix] * s.p;
      v = b[0] * v0 + b[1] * v1 + b[2] * v2;
    }
  }
  s.node[g] = {s.generation, v};
  return v;
}

void SimplexSplineForest::NodeJet(int g, Scratch& s) const {
  if (s.node[g].stamp == s.generation) return;
  const Node& n = nodes_[g];
  const bool hessian = s.order > 1;
  double value = 0.0;
  double gradient[3] = {0.0, 0.0, 0.0};
  double hess[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  bool live = false;
  if (n.matrix < 0) {
    const auto sign = [&](int pair) {  // as in NodeValue
      const Scratch::PairMemo& memo = s.pair[pair];
      return memo.stamp == s.generation ? memo.sign : PairSign(pair, s);
    };
    const int o = n.orientation;
    if (o != 0 && sign(n.pair[0]) == o && sign(n.pair[1]) == -o &&
        sign(n.pair[2]) == o) {
      value = n.inv_abs_det;
    }
    live = value != 0.0;
  } else {
    for (int j = 0; j < 3; ++j) {
      const int c = n.child[j];
      if (s.node[c].stamp != s.generation) NodeJet(c, s);
      live = live || s.live[c];
    }
    if (live) {
      // As SimplexSpline::Evaluate.
      const Eigen::Matrix3d& g = matrices_[n.matrix];
      const Eigen::Vector3d b = g * s.p;
      for (int j = 0; j < 3; ++j) {
        const int c = n.child[j];
        if (!s.live[c]) continue;
        const double gj[3] = {g(j, 0), g(j, 1), g(j, 2)};
        const double vc = s.node[c].value;
        const std::array<double, 3>& gc = s.gradient[c];
        value += b[j] * vc;
        for (int r = 0; r < 3; ++r) gradient[r] += gj[r] * vc + b[j] * gc[r];
        if (hessian) {
          const std::array<double, 9>& hc = s.hessian[c];
          for (int r = 0; r < 3; ++r)
            for (int q = 0; q < 3; ++q) {
              hess[3 * r + q] +=
                  gj[r] * gc[q] + gc[r] * gj[q] + b[j] * hc[3 * r + q];
            }
        }
      }
    }
  }
  s.node[g] = {s.generation, value};
  s.live[g] = live;
  s.gradient[g] = {gradient[0], gradient[1], gradient[2]};
  if (hessian) std::copy(hess, hess + 9, s.hessian[g].begin());
}

double SimplexSplineForest::Value(int handle, const Eigen::Vector3d& p) const {
  Scratch& s = Begin(p, 0);
  return NodeValue(tops_[handle], s);
}

SimplexSplineForest::PointValues SimplexSplineForest::At(
    const Eigen::Vector3d& p) const {
  return PointValues(this, &Begin(p, 0));
}

double SimplexSplineForest::PointValues::value(int handle) const {
  return forest_->NodeValue(forest_->tops_[handle],
                            *static_cast<Scratch*>(scratch_));
}

ScalarJet SimplexSplineForest::Evaluate(int handle, const Eigen::Vector3d& p,
                                        JetOrder order) const {
  ScalarJet jet;
  if (order == JetOrder::kValue) {
    jet.value = Value(handle, p);
    return jet;
  }
  Scratch& s = Begin(p, static_cast<int>(order));
  const int top = tops_[handle];
  NodeJet(top, s);
  jet.value = s.node[top].value;
  jet.gradient = Eigen::Vector3d(s.gradient[top][0], s.gradient[top][1],
                                 s.gradient[top][2]);
  if (order == JetOrder::kHessian) {
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) jet.hessian(r, q) = s.hessian[top][3 * r + q];
  }
  return jet;
}

}  // namespace sdcb
