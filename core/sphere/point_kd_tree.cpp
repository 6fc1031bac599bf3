#include "sdcb/core/sphere/point_kd_tree.h"

#include <algorithm>
#include <numeric>

namespace sdcb {
namespace {
constexpr int kLeafSize = 8;
}  // namespace

PointKdTree::PointKdTree(const Eigen::MatrixX3d& points) : points_(points) {
  order_.resize(points_.rows());
  std::iota(order_.begin(), order_.end(), 0);
  if (!order_.empty()) Build(0, static_cast<int>(order_.size()));
}

int PointKdTree::Build(int begin, int end) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{begin, end});
  if (end - begin <= kLeafSize) return id;
  Eigen::RowVector3d lo = points_.row(order_[begin]), hi = lo;
  for (int i = begin + 1; i < end; ++i) {
    lo = lo.cwiseMin(points_.row(order_[i]));
    hi = hi.cwiseMax(points_.row(order_[i]));
  }
  int axis;
  (hi - lo).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  // Ties on the coordinate are broken by row so the tree is deterministic.
  std::nth_element(order_.begin() + begin, order_.begin() + mid,
                   order_.begin() + end, [&](int a, int b) {
                     const double pa = points_(a, axis), pb = points_(b, axis);
                     return pa < pb || (pa == pb && a < b);
                   });
  const double split = points_(order_[mid], axis);
  const int left = Build(begin, mid);
  const int right = Build(mid, end);
  nodes_[id].left = left;
  nodes_[id].right = right;
  nodes_[id].axis = axis;
  nodes_[id].split = split;
  return id;
}

PointKdTree::Neighbor PointKdTree::Nearest(const Eigen::Vector3d& query,
                                           double bound_squared,
                                           int exclude) const {
  Neighbor best;
  if (nodes_.empty()) return best;
  // Explicit stack of (node, squared distance from query to its half-space).
  struct Item {
    int node;
    double gap_squared;
  };
  Item stack[128];
  int top = 0;
  stack[top++] = {0, 0.0};
  while (top > 0) {
    const Item item = stack[--top];
    const double limit = std::min(bound_squared, best.squared_distance);
    // A subtree at the same distance as the best can still hold a tie with
    // a smaller index, hence ">" and not ">=".
    if (item.gap_squared > limit) continue;
    const Node& node = nodes_[item.node];
    if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i) {
        const int row = order_[i];
        if (row == exclude) continue;
        const double d = (points_.row(row).transpose() - query).squaredNorm();
        if (d >= bound_squared) continue;
        if (d < best.squared_distance ||
            (d == best.squared_distance && row < best.index)) {
          best.index = row;
          best.squared_distance = d;
        }
      }
      continue;
    }
    const double delta = query[node.axis] - node.split;
    const int near_child = delta < 0 ? node.left : node.right;
    const int far_child = delta < 0 ? node.right : node.left;
    // Far child first on the stack so that the near child is visited first.
    stack[top++] = {far_child, std::max(item.gap_squared, delta * delta)};
    stack[top++] = {near_child, item.gap_squared};
  }
  return best;
}

PointKdTree::Neighbor PointKdTree::NearestNear(const Eigen::Vector3d& query,
                                               int hint,
                                               double bound_squared) const {
  if (hint >= 0) {
    // The margin covers a different rounding of the same distance below.
    const double d2 = (points_.row(hint).transpose() - query).squaredNorm();
    bound_squared = std::min(bound_squared, d2 * (1 + 1e-12) + 1e-300);
  }
  return Nearest(query, bound_squared);
}

}  // namespace sdcb
