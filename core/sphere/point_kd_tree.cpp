#include "sdcb/core/sphere/point_kd_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {
constexpr int kLeafSize = 8;
// Queries shorter than this use the tree: the direction of a short query
// says little about which unit point is nearest in R^3.
constexpr double kMinDirectionQuery = 0.5;
// Angle added to each cell's candidate radius: covers the points' lengths
// (1 within kUnitVectorTolerance: the nearest point in R^3 to a query of
// length >= 0.5 is then within ~1e-4 rad of the nearest by angle) and the
// rounding of the distances.
constexpr double kCandidateMargin = 1e-3;

// The angle between unit vectors a and b.
double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return AngleFromChord((a - b).norm());
}

// The point of cube face f (axis f / 2, positive for even f) at face
// coordinates (a, b) in [-1, 1]^2.
Eigen::Vector3d FacePoint(int f, double a, double b) {
  const int axis = f / 2;
  Eigen::Vector3d p;
  p[axis] = f % 2 == 0 ? 1.0 : -1.0;
  p[(axis + 1) % 3] = a;
  p[(axis + 2) % 3] = b;
  return p;
}
}  // namespace

PointKdTree::PointKdTree(const Eigen::MatrixX3d& points, bool direction_index)
    : points_(points) {
  order_.resize(points_.rows());
  std::iota(order_.begin(), order_.end(), 0);
  if (!order_.empty()) Build(0, static_cast<int>(order_.size()));
  if (direction_index && points_.rows() > 0 && AllUnitRows(points_)) {
    BuildDirectionIndex();
  }
}

void PointKdTree::Within(int node, const Eigen::Vector3d& center, double radius,
                         std::vector<int>* rows) const {
  const Node& n = nodes_[node];
  if (n.left < 0) {
    for (int i = n.begin; i < n.end; ++i) {
      const int row = order_[i];
      if ((points_.row(row).transpose() - center).norm() <= radius) {
        rows->push_back(row);
      }
    }
    return;
  }
  const double delta = center[n.axis] - n.split;
  if (delta - radius <= 0) Within(n.left, center, radius, rows);
  if (delta + radius >= 0) Within(n.right, center, radius, rows);
}

int PointKdTree::CellOf(const Eigen::Vector3d& d) const {
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(d[k]) > std::abs(d[axis])) axis = k;
  }
  const int face = 2 * axis + (d[axis] < 0 ? 1 : 0);
  const double scale = 1.0 / std::abs(d[axis]);
  const int n = cells_per_side_;
  auto cell = [n](double t) {
    return std::clamp(static_cast<int>(std::floor((t + 1) / 2 * n)), 0, n - 1);
  };
  return (face * n + cell(d[(axis + 1) % 3] * scale)) * n +
         cell(d[(axis + 2) % 3] * scale);
}

void PointKdTree::BuildDirectionIndex() {
  // About two cells per point.
  const double per_face = 2.0 * static_cast<double>(points_.rows()) / 6.0;
  cells_per_side_ =
      std::clamp(static_cast<int>(std::ceil(std::sqrt(per_face))), 1, 256);
  const int n = cells_per_side_;
  cell_start_.assign(6 * n * n + 1, 0);
  cell_rows_.clear();
  std::vector<int> rows;
  for (int f = 0; f < 6; ++f) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        auto at = [&](double u, double v) {
          return FacePoint(f, -1 + 2 * u / n, -1 + 2 * v / n).normalized();
        };
        // The cell is the central projection of a square: a convex
        // spherical quadrilateral, farthest from its centre at a corner.
        const Eigen::Vector3d centre = at(i + 0.5, j + 0.5);
        double reach = 0;
        for (const auto& [u, v] : {std::pair{0, 0}, {0, 1}, {1, 0}, {1, 1}}) {
          reach = std::max(reach, Angle(centre, at(i + u, j + v)));
        }
        // A query in the cell is within `reach` of the centre, so its
        // nearest point is within reach + (the centre's nearest) of it, and
        // within twice the reach plus that of the centre.
        const Neighbor nearest = Nearest(centre);
        const double angle =
            2 * reach +
            Angle(centre, points_.row(nearest.index).transpose().normalized()) +
            kCandidateMargin;
        rows.clear();
        Within(0, centre, ChordFromAngle(angle) + kCandidateMargin, &rows);
        std::sort(rows.begin(), rows.end());
        cell_rows_.insert(cell_rows_.end(), rows.begin(), rows.end());
        cell_start_[(f * n + i) * n + j + 1] =
            static_cast<int>(cell_rows_.size());
      }
    }
  }
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
  if (cells_per_side_ > 0 && query.allFinite() &&
      query.squaredNorm() >= kMinDirectionQuery * kMinDirectionQuery) {
    // The cell's candidates, with the tree's distances and tie rule.
    const int cell = CellOf(query);
    Neighbor best;
    for (int k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
      const int row = cell_rows_[k];
      const double d = (points_.row(row).transpose() - query).squaredNorm();
      if (d < best.squared_distance ||
          (d == best.squared_distance && row < best.index)) {
        best.index = row;
        best.squared_distance = d;
      }
    }
    return best.squared_distance < bound_squared ? best : Neighbor();
  }
  if (hint >= 0) {
    // The margin covers a different rounding of the same distance below.
    const double d2 = (points_.row(hint).transpose() - query).squaredNorm();
    bound_squared = std::min(bound_squared, d2 * (1 + 1e-12) + 1e-300);
  }
  return Nearest(query, bound_squared);
}

}  // namespace sdcb
