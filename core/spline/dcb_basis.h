// The spherical DCB-spline basis (paper Sec. 3, eqs. 4 and 5): one basis
// function per unordered Delaunay configuration set X~ (k + 3 knots),
//   B(p) = sum_{X in <X>} |det(X_B)| M(p | X~)           (eq. 4)
// The PDF shows "1 / det(X_B)"; multiplying is the consistent reading:
// degree 0 then gives the indicator of each Delaunay triangle, and in the
// plane Neamtu's partition of unity. M(p | X~) does not depend on X, so
// B = w M with the constant weight w = sum |det(X_B)|. Normalized (eq. 5):
//   I(p) = sum_i B_i(p),   Bbar_i(p) = B_i(p) / I(p).
// The support of B is the spherical convex hull of X~, which lies in the
// smaller cap of any of its boundary triples X_B; a latitude-longitude grid
// of those caps finds, for a point, the few basis functions that may be
// nonzero there.
#ifndef SDCB_CORE_SPLINE_DCB_BASIS_H_
#define SDCB_CORE_SPLINE_DCB_BASIS_H_

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/simplex_spline.h"
#include "sdcb/core/spline/simplex_spline_forest.h"

namespace sdcb {

// The closed cap {q in S^2 : axis . q >= cos_radius}, axis a unit vector.
struct SphericalCap {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double cos_radius = 1.0;
};

// One basis function's value (or normalized value) at a point.
struct BasisValue {
  int index = 0;  // Basis index (position in DelaunayConfigurations::sets).
  double value = 0.0;
};

struct DcbBasisOptions {
  SimplexSplineOptions spline;
  // Latitude rows of the support grid (longitude columns: twice as many);
  // 0 chooses from the number of knots.
  int grid_rows = 0;
  // Create checks I(p) > 0 (eq. 5) at this many quasi-uniform points (a
  // Fibonacci spiral) and fails if some I is 0: small knot sets can leave
  // parts of the sphere outside every basis support even in general
  // position (docs/BASIS.md). A sampled check: a hole smaller than the
  // sample spacing (~3.5 / sqrt(samples) rad) can be missed. 0 disables.
  int coverage_samples = 2048;
};

class DcbBasis {
 public:
  // `knots`: #knots by 3 unit vectors; `configurations`: their degree-k
  // configuration sets (ComputeDelaunayConfigurations). Fails with
  // kInvalidArgument if a set has the wrong size, an index is out of range,
  // or a boundary triple is not in its set, and with kInvalidInput if the
  // coverage check (DcbBasisOptions::coverage_samples) finds I = 0.
  // Degenerate knots (co-circular,
  // on great circles) are supported as the limit of the configurations'
  // symbolic perturbation (docs/BASIS.md), except when a set's knots are not
  // in an open hemisphere (possible only if a boundary triple lies on a
  // great circle, e.g. with antipodal knots): kInvalidInput naming the set.
  // A set whose boundary triples all lie on great circles gets weight 0
  // (B = 0: |det X_B| -> 0 while M stays bounded).
  static StatusOr<DcbBasis> Create(const Eigen::MatrixX3d& knots,
                                   const DelaunayConfigurations& configurations,
                                   const DcbBasisOptions& options = {});

  int degree() const { return degree_; }
  int size() const { return static_cast<int>(splines_.size()); }
  const Eigen::MatrixX3d& knots() const { return knots_; }
  const ConfigurationSet& configuration_set(int i) const { return sets_[i]; }
  // sum over the configurations of set i of |det(X_B)| (eq. 4).
  double weight(int i) const { return weights_[i]; }
  // M(p | X~) of set i; only for sets whose knots lie in an open hemisphere
  // (always, unless a boundary triple lies on a great circle).
  bool has_simplex_spline(int i) const { return splines_[i].has_value(); }
  const SimplexSpline& simplex_spline(int i) const { return *splines_[i]; }
  // Number of limit terms (a . p) M(p | X~ \ x_j) of set i (see Create).
  int num_limit_terms(int i) const {
    return limit_start_[i + 1] - limit_start_[i];
  }
  // A cap containing the support of basis function i.
  const SphericalCap& support_cap(int i) const { return caps_[i]; }

  // B_i(p), eq. 4, p a unit vector (or any nonzero p: homogeneous of degree k).
  double Value(int i, const Eigen::Vector3d& p) const;
  // B_i and its R^3 derivatives up to `order`.
  ScalarJet Evaluate(int i, const Eigen::Vector3d& p, JetOrder order) const;

  // The polynomial piece of B_i containing q in the chart p(s, t) = o +
  // s e1 + t e2 (SimplexSpline::PiecePolynomial): adds its
  // PolynomialSize(degree()) coefficients to `out`. Returns false if B_i
  // vanishes around q.
  bool AddPiecePolynomial(int i, const Eigen::Vector3d& q,
                          const Eigen::Vector3d& o, const Eigen::Vector3d& e1,
                          const Eigen::Vector3d& e2, double* out) const;

  // A permutation of the rows of `points` (#P by 3 unit vectors) that visits
  // them support-grid cell by cell (stable within a cell): evaluating in this
  // order reuses the same few basis functions from cache.
  std::vector<Eigen::Index> LocalityOrder(const Eigen::MatrixX3d& points) const;

  // Calls visit(r) once for every row r of `points` (#P by 3 unit vectors),
  // in parallel (TBB), in LocalityOrder. `visit` may only write state that
  // belongs to row r; results then do not depend on the thread count.
  void ParallelForEachPoint(
      const Eigen::MatrixX3d& points,
      const std::function<void(Eigen::Index)>& visit) const;

  // Replaces `out` with the ascending indices of the basis functions whose
  // support cap contains p: every i with B_i(p) != 0 is among them.
  void Candidates(const Eigen::Vector3d& p, std::vector<int>* out) const;
  // Replaces `out` with (i, B_i(p)) for every nonzero B_i(p), ascending i.
  void NonzeroValues(const Eigen::Vector3d& p,
                     std::vector<BasisValue>* out) const;
  // I(p) = sum_i B_i(p), eq. 5 (> 0 on S^2 for a valid configuration set).
  double Normalization(const Eigen::Vector3d& p) const;
  // Replaces `out` with (i, Bbar_i(p)) = B_i / I for the nonzero B_i(p).
  void NormalizedValues(const Eigen::Vector3d& p,
                        std::vector<BasisValue>* out) const;

 private:
  // A term (cofactor . p) M(p | X~ \ x_j) of the limit of |det X_B| M for
  // a boundary triple X_B on a great circle (see BuildBasisFunction).
  struct LimitTerm {
    Eigen::Vector3d cofactor;
    SimplexSpline spline;
  };

  DcbBasis() = default;
  static Status BuildBasisFunction(const Eigen::MatrixX3d& knots,
                                   const ConfigurationSet& set,
                                   const SimplexSplineOptions& options,
                                   std::optional<SimplexSpline>* spline,
                                   double* weight,
                                   std::vector<LimitTerm>* limit_terms,
                                   SphericalCap* support);
  // Fills hull_start_ and hull_normals_ from knots_, sets_ and splines_.
  void BuildHulls();
  // Fills rows_ (grid_rows, or from the knot count if 0), cell_start_ and
  // cell_items_ from caps_.
  void BuildSupportGrid(int grid_rows);
  int CellOf(const Eigen::Vector3d& p) const;
  // Value(i, p) with the forest's value of a handle from
  // forest_value(handle).
  template <typename ForestValue>
  double ValueWith(int i, const Eigen::Vector3d& p,
                   const ForestValue& forest_value) const;
  // kInvalidInput if I = 0 at one of `samples` quasi-uniform points.
  Status CheckCoverage(int samples) const;
  // Calls visit(i), ascending, for each basis i whose support cap holds p.
  template <typename Visit>
  void ForEachCandidate(const Eigen::Vector3d& p, Visit visit) const {
    const int cell = CellOf(p);
    const Eigen::Vector3d u = p.normalized();
    for (int j = cell_start_[cell]; j < cell_start_[cell + 1]; ++j) {
      const int i = cell_items_[j];
      if (caps_[i].axis.dot(u) >= caps_[i].cos_radius && !OutsideHull(i, u)) {
        visit(i);
      }
    }
  }
  // Whether the unit vector u lies strictly outside the spherical convex
  // hull of set i's knots, by a margin far above rounding (points near the
  // hull's boundary are never skipped: the exact predicates decide there).
  bool OutsideHull(int i, const Eigen::Vector3d& u) const {
    for (int e = hull_start_[i]; e < hull_start_[i + 1]; ++e) {
      if (hull_normals_[e].dot(u) < -1e-12) return true;
    }
    return false;
  }

  int degree_ = 0;
  Eigen::MatrixX3d knots_;
  std::vector<ConfigurationSet> sets_;
  // splines_[i] is empty iff set i is not in an open hemisphere; weights_[i]
  // is then 0 and the limit terms carry the function.
  std::vector<std::optional<SimplexSpline>> splines_;
  // The splines with their recursions merged (SimplexSplineForest): a
  // point's basis values share their knot subsets. forest_handle_[i] is -1
  // for sets without a spline, or when the splines were built with a
  // split_seed (their W is then not a function of the subset alone).
  SimplexSplineForest forest_;
  std::vector<int> forest_handle_;
  std::vector<double> weights_;
  // CSR: the limit terms of set i are limit_terms_[limit_start_[i] ..
  // limit_start_[i + 1]).
  std::vector<int> limit_start_;
  std::vector<LimitTerm> limit_terms_;
  std::vector<SphericalCap> caps_;
  // CSR: normals a x b of the hull edges (a, b) of set i, the hull on their
  // positive side; empty for sets without a simplex spline.
  std::vector<int> hull_start_;
  std::vector<Eigen::Vector3d> hull_normals_;
  // Support grid: rows_ x 2 rows_ latitude-longitude cells, CSR lists of
  // basis indices (ascending) whose cap meets each cell.
  int rows_ = 1;
  std::vector<int> cell_start_;
  std::vector<int> cell_items_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_DCB_BASIS_H_
