// Many simplex splines (core/spline/simplex_spline.h) over one global knot
// set, their recursions (eq. 3) merged so that evaluations at one point share
// knot subsets.
#ifndef SDCB_CORE_SPLINE_SIMPLEX_SPLINE_FOREST_H_
#define SDCB_CORE_SPLINE_SIMPLEX_SPLINE_FOREST_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "sdcb/core/spline/simplex_spline.h"

namespace sdcb {

// Many simplex splines over one global knot set with their recursions
// merged: every subset of knots (a node of eq. 3), pair sign and barycentric
// matrix is stored once, keyed by global knot indices, and the evaluations
// of any of the splines at one point share them (memoized per thread and
// point). A basis function's support overlaps ~50 others' at a point, all
// built from the same few knots, so most of their nodes coincide.
//
// Values are bit-for-bit those of SimplexSpline::Value / Evaluate when the
// splines were built with the default SimplexSplineOptions and their local
// knot order is the ascending global order: a subset's W is then chosen from
// the subset alone (the first spanning triple of largest |det|, ascending).
class SimplexSplineForest {
 public:
  SimplexSplineForest();

  // Adds `spline`, whose local knot j is global knot global[j] (strictly
  // ascending, one per knot); returns its handle (0, 1, ... in call order).
  int Add(const SimplexSpline& spline, const std::vector<int>& global);

  // Frees the lookup tables that Add uses to share nodes (splines added
  // later are still correct, but share nothing with earlier ones).
  void FinishAdding();

  int size() const { return static_cast<int>(tops_.size()); }
  // Distinct nodes over all splines added (for benchmarks).
  int num_nodes() const { return static_cast<int>(nodes_.size()); }

  // SimplexSpline::Value / Evaluate of the spline `handle`. Thread-safe;
  // consecutive calls at the same p on one thread reuse each other's nodes.
  double Value(int handle, const Eigen::Vector3d& p) const;

  // Values of many splines at one point p: value(handle) is Value(handle, p),
  // without checking the point again for every spline. Valid on the thread
  // that called At, until that thread evaluates this forest at another point.
  class PointValues {
   public:
    double value(int handle) const;

   private:
    friend class SimplexSplineForest;
    PointValues(const SimplexSplineForest* forest, void* scratch)
        : forest_(forest), scratch_(scratch) {}
    const SimplexSplineForest* forest_;
    void* scratch_;
  };
  PointValues At(const Eigen::Vector3d& p) const;
  ScalarJet Evaluate(int handle, const Eigen::Vector3d& p,
                     JetOrder order) const;

 private:
  struct Node {
    int child[3] = {-1, -1, -1};  // Internal: S \ {w_j} (node indices).
    int pair[3] = {-1, -1, -1};   // Leaf: pairs (b,c), (a,c), (a,b).
    int orientation = 0;          // Leaf: sign of det(t_a, t_b, t_c).
    double inv_abs_det = 0.0;     // Leaf: 1 / |det|.
    int matrix = -1;              // Internal: index into matrices_.
  };
  struct Scratch;
  struct KeyHash {
    std::size_t operator()(const std::array<int, 8>& key) const;
  };
  Scratch& Begin(const Eigen::Vector3d& p, int order) const;
  int PairSign(int pair, Scratch& s) const;
  double LeafValue(const Node& node, Scratch& s) const;
  double NodeValue(int node, Scratch& s) const;
  void NodeJet(int node, Scratch& s) const;

  // Distinguishes forests in the per-thread memo (copies share it: they
  // hold the same nodes).
  std::uint64_t id_ = 0;
  std::vector<Node> nodes_;
  std::vector<int> tops_;  // Node of each spline's full knot set.
  std::vector<Eigen::Matrix3d> matrices_;
  std::vector<std::array<int, 2>> pairs_;      // Global knots (a, b), a < b.
  std::vector<Eigen::Vector3d> pair_knots_;    // t_a, t_b of each pair.
  std::vector<Eigen::Vector3d> pair_normals_;  // t_a x t_b.
  std::unordered_map<std::array<int, 8>, int, KeyHash> node_of_;
  std::unordered_map<std::array<int, 8>, int, KeyHash> matrix_of_;
  std::unordered_map<std::array<int, 8>, int, KeyHash> pair_of_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_SIMPLEX_SPLINE_FOREST_H_
