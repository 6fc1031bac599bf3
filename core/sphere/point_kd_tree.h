// A static k-d tree over points in R^3 for nearest-neighbour queries with a
// distance bound: which knot is nearest to a quadrature sample (spherical
// CVT, paper Sec. 4.4), closest pairs of knots.
#ifndef SDCB_CORE_SPHERE_POINT_KD_TREE_H_
#define SDCB_CORE_SPHERE_POINT_KD_TREE_H_

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace sdcb {

class PointKdTree {
 public:
  struct Neighbor {
    int index = -1;  // row of the point, or -1 if none qualified
    double squared_distance = std::numeric_limits<double>::infinity();
  };

  // `points`: #P by 3, copied. Any #P >= 0. With `direction_index`, and
  // when every point is a unit vector (within kUnitVectorTolerance), also a
  // cube-map grid of directions that lists, per cell, every point that can
  // be nearest to a query whose direction falls in the cell (about eight):
  // NearestNear scans that list instead of descending the tree, for queries
  // of length >= 0.5. The same answers; for many queries against few points
  // (the fit's samples against its knots).
  explicit PointKdTree(const Eigen::MatrixX3d& points,
                       bool direction_index = false);

  // The point nearest to `query` among those with squared distance strictly
  // below `bound_squared`, ignoring row `exclude` (-1: none). Ties between
  // equally distant points go to the smaller row index, so the answer is a
  // function of the input alone.
  Neighbor Nearest(
      const Eigen::Vector3d& query,
      double bound_squared = std::numeric_limits<double>::infinity(),
      int exclude = -1) const;

  // Nearest(query, bound_squared) for a query near the point of row `hint`
  // (-1: no hint), e.g. the answer to the previous query of a run of nearby
  // ones: the hint's distance tightens the bound, so the search visits
  // fewer nodes. The bound still admits the hint, so the answer is
  // Nearest(query, bound_squared)'s, ties included.
  Neighbor NearestNear(
      const Eigen::Vector3d& query, int hint,
      double bound_squared = std::numeric_limits<double>::infinity()) const;

  int size() const { return static_cast<int>(order_.size()); }

 private:
  struct Node {
    int begin, end;             // range in order_
    int left = -1, right = -1;  // children, -1 for a leaf
    int axis = 0;
    double split = 0;
  };
  int Build(int begin, int end);
  // Rows of the points within `radius` of `center` (|p - c| <= radius).
  void Within(int node, const Eigen::Vector3d& center, double radius,
              std::vector<int>* rows) const;
  void BuildDirectionIndex();
  // The direction grid's cell of a nonzero `direction`.
  int CellOf(const Eigen::Vector3d& direction) const;

  Eigen::MatrixX3d points_;
  std::vector<int> order_;  // point rows, grouped by leaf
  std::vector<Node> nodes_;
  // The direction index: cells_per_side_ x cells_per_side_ cells on each of
  // the cube's six faces (0: none); cell c's candidates are
  // cell_rows_[cell_start_[c] .. cell_start_[c + 1]).
  int cells_per_side_ = 0;
  std::vector<int> cell_start_;
  std::vector<int> cell_rows_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_POINT_KD_TREE_H_
