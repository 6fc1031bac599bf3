// Spherical simplex splines M(p | V) (paper Sec. 3, eq. 3) on a knot set V of
// k + 3 unit vectors, with their R^3 gradient and Hessian.
//
// M is a piecewise homogeneous polynomial of degree k in p in R^3 (its
// restriction to S^2 is the spline), so derivatives are those of the
// homogeneous extension. The recursion
//   M(p | S) = sum_j b_j(p | W) M(p | S \ {w_j}),  W = {w0, w1, w2} in S,
// is memoized over subsets S of V (bitmasks over the local knots): every
// subset is evaluated once per point, in an order fixed when the spline is
// built. Degree 0 (eq. 3, second line):
//   M(p | t0, t1, t2) = chi[t0, t1, t2)(p) / |det(t0, t1, t2)|.
//
// Half-open convention: p belongs to the half-open triangle [t0, t1, t2) iff
// the perturbed point p + e d1(p) + e^2 d2(p), for infinitesimal e > 0, lies
// strictly inside the cone of t0, t1, t2; d1(p) = E1 x p and d2(p) = E2 x p
// for two fixed generic axes E1, E2. The perturbation depends only on p, so
// any set of triangles that tiles a region counts every point of it exactly
// once, including points on edges and knots. All signs are exact (a filtered
// floating-point test backed by CGAL's exact Det3Sign).
#ifndef SDCB_CORE_SPLINE_SIMPLEX_SPLINE_H_
#define SDCB_CORE_SPLINE_SIMPLEX_SPLINE_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "sdcb/core/common/status.h"

namespace sdcb {

// Value and derivatives of a scalar function of p in R^3.
struct ScalarJet {
  double value = 0.0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
};

// How many derivatives to compute: 0 value, 1 + gradient, 2 + Hessian.
enum class JetOrder { kValue = 0, kGradient = 1, kHessian = 2 };

// Bivariate polynomials in the affine chart p(s, t) = o + s e1 + t e2 of
// R^3 (the per-piece form used by core/spline/piecewise_surface.h): the
// coefficient of s^i t^j, i + j <= d, is at index (i + j)(i + j + 1) / 2 + j.
inline constexpr int PolynomialSize(int degree) {
  return (degree + 1) * (degree + 2) / 2;
}
inline constexpr int MonomialIndex(int i, int j) {
  return (i + j) * (i + j + 1) / 2 + j;
}
// out += (alpha + beta s + gamma t) * in, `in` of degree `degree`.
inline void AccumulateAffineProduct(double alpha, double beta, double gamma,
                                    const double* in, int degree, double* out) {
  for (int n = 0; n <= degree; ++n)
    for (int j = 0; j <= n; ++j) {
      const int i = n - j;
      const double c = in[MonomialIndex(i, j)];
      if (c == 0.0) continue;
      out[MonomialIndex(i, j)] += alpha * c;
      out[MonomialIndex(i + 1, j)] += beta * c;
      out[MonomialIndex(i, j + 1)] += gamma * c;
    }
}

// f(std::integral_constant<int, degree>()), for the degrees 0 .. 5 of
// SimplexSpline (kMaxKnots - 3; larger ones are taken as 5): code
// specialized by degree, chosen at run time.
template <typename F>
decltype(auto) WithDegree(int degree, F&& f) {
  switch (degree) {
    case 0:
      return f(std::integral_constant<int, 0>());
    case 1:
      return f(std::integral_constant<int, 1>());
    case 2:
      return f(std::integral_constant<int, 2>());
    case 3:
      return f(std::integral_constant<int, 3>());
    case 4:
      return f(std::integral_constant<int, 4>());
    default:
      return f(std::integral_constant<int, 5>());
  }
}

// Index of the pair i < j among m knots: 0 .. m (m - 1) / 2 - 1, increasing
// in the order (0,1), (0,2), ..., (0,m-1), (1,2), ...
inline constexpr int PairIndex(int i, int j, int m) {
  return i * (2 * m - i - 1) / 2 + j - i - 1;
}

// AccumulateAffineProduct for a fixed degree: out (degree D) += (alpha +
// beta s + gamma t) * in (degree D - 1). The coefficient of degree n and
// index j of `in` (at n (n + 1) / 2 + j) multiplies into the same index
// (alpha), + n + 1 (s) and + n + 2 (t).
template <int D>
inline void AddAffineProduct(double alpha, double beta, double gamma,
                             const double* in, double* out) {
  for (int n = 0; n < D; ++n) {
    const int first = n * (n + 1) / 2;
    for (int j = 0; j <= n; ++j) {
      const double c = in[first + j];
      out[first + j] += alpha * c;
      out[first + n + 1 + j] += beta * c;
      out[first + n + 2 + j] += gamma * c;
    }
  }
}

// Three unit knots with |det| at or below this count as lying on one great
// circle (a zero node of the recursion). The rounding of det is ~1e-16, so
// 1 / |det| and the barycentric matrix of such a triple are not
// representable (1 / 0 = inf, inf * 0 = NaN), and the triangle is a sliver
// narrower than ~1e-14 rad whose contribution is below the rounding of M.
// Knots meant to be exactly on a great circle but computed with cos / sin
// (a meridian) typically have |det| ~ 1e-17.
inline constexpr double kFlatDeterminant = 1e-14;

// Whether |det(a, b, c)| > kFlatDeterminant (a, b, c unit vectors).
bool SpansR3(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
             const Eigen::Vector3d& c);

// Whether some three rows of `knots` (#knots by 3 unit vectors) satisfy
// SpansR3, i.e. the knots do not all lie on one great circle.
bool KnotsSpanR3(const Eigen::MatrixX3d& knots);

// The sign of p . (a x b) computed in doubles (a, b unit vectors) is exact
// when its magnitude exceeds kSignFilter |p|_1 |a|_1 |b|_1 (the rounding
// error is below ~10 ulps of that).
inline constexpr double kSignFilter = 1e-13;

// PerturbedDetSign computed exactly (CGAL), without a floating-point filter.
int ExactPerturbedDetSign(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                          const Eigen::Vector3d& b);

// Sign of det(p, a, b) given v = p . (a x b) in doubles and a bound on its
// rounding error (see kSignFilter): the sign of v beyond the bound, the exact
// perturbed sign within it.
inline int FilteredSign(double v, double bound, const Eigen::Vector3d& p,
                        const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (v > bound) return 1;
  if (v < -bound) return -1;
  return ExactPerturbedDetSign(p, a, b);
}

// Sign of det(p, a, b) under the half-open perturbation described above:
// +1 or -1, or 0 only in degenerate cases (a, b dependent).
int PerturbedDetSign(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                     const Eigen::Vector3d& b);

// Whether p lies in the half-open spherical triangle [t0, t1, t2) (see
// above). False for a degenerate triangle (det = 0).
bool InHalfOpenTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                        const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);

struct SimplexSplineOptions {
  // Choice of W at every node of the recursion (eq. 3); the value does not
  // depend on it, its rounding does. 0: the triple of S with the largest
  // |det| (best conditioned). Otherwise a pseudo-random spanning triple
  // derived from this seed among those with |det| >= 1/4 of the largest
  // (used by tests to check W-independence).
  std::uint32_t split_seed = 0;
};

class SimplexSpline {
 public:
  // Maximum number of knots, k + 3 for degree k <= 5.
  static constexpr int kMaxKnots = 8;

  // `knots`: (k + 3) by 3 unit vectors, 3 <= k + 3 <= kMaxKnots. Fails with
  // kInvalidArgument for a bad size or knots that are not unit vectors
  // (within kUnitVectorTolerance), and with kInvalidInput if the knots do not
  // span R^3 (all on one great circle) or do not lie in an open hemisphere
  // (antipodal knots, or the origin in their hull): M is then not a bounded
  // function. Degenerate subsets are allowed: three knots on a great circle
  // (det = 0) or larger subsets on one great circle are zero nodes of the
  // recursion (their coefficient vanishes on their support), so M is the limit
  // of the simplex splines of nearby generic knots (with lower smoothness).
  static StatusOr<SimplexSpline> Create(
      const Eigen::MatrixX3d& knots, const SimplexSplineOptions& options = {});

  int degree() const { return static_cast<int>(knots_.rows()) - 3; }
  const Eigen::MatrixX3d& knots() const { return knots_; }
  // Number of memoized subsets visited per evaluation.
  int num_nodes() const { return static_cast<int>(nodes_.size()); }

  // M(p | V) at p (any nonzero p in R^3; homogeneous of degree k).
  double Value(const Eigen::Vector3d& p) const;
  // M and, up to `order`, its R^3 gradient and Hessian at p. Entries beyond
  // `order` are left zero.
  ScalarJet Evaluate(const Eigen::Vector3d& p, JetOrder order) const;

  // The polynomial piece of M that contains q (decided by the same exact,
  // perturbed signs as Value(q)), in the chart p(s, t) = o + s e1 + t e2:
  // writes PolynomialSize(degree()) coefficients to `out` (see
  // MonomialIndex) so that M(p(s, t)) = sum c_ij s^i t^j wherever p(s, t)
  // lies in that piece. Returns false, leaving `out` untouched, if M
  // vanishes around q (q outside the support).
  bool PiecePolynomial(const Eigen::Vector3d& q, const Eigen::Vector3d& o,
                       const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                       double* out) const;

  // The recursion unrolled: M(p | V) = sum over its leaves T (the subsets
  // the recursion ends at) of P_T(p) chi_T(p) / |det T|, where chi_T is the
  // half-open triangle's indicator and P_T(p), homogeneous of degree k, sums
  // over the recursion's paths from V to T the products of the barycentric
  // coordinates b_j(p | W) met on the way.
  struct Leaf {
    std::array<int, 3> knots = {-1, -1, -1};  // local, ascending
    int orientation = 0;       // exact sign of det(t_a, t_b, t_c); 0: zero leaf
    double inv_abs_det = 0.0;  // 1 / |det(t_a, t_b, t_c)|
  };
  int num_leaves() const { return num_leaves_; }
  // The perturbed signs of det(p, t_i, t_j) for the pairs i < j, at
  // PairIndex(i, j, k + 3) (as Value(p) decides them).
  void PairSigns(const Eigen::Vector3d& p, int* signs) const;
  Leaf leaf(int i) const;
  // P_T in the chart p(s, t) = o + s e1 + t e2 of each leaf i with
  // wanted[i] (num_leaves() flags): PolynomialSize(degree()) coefficients
  // at out + i * PolynomialSize(degree()); the other leaves' are left as
  // they are.
  void LeafPathPolynomials(const Eigen::Vector3d& o, const Eigen::Vector3d& e1,
                           const Eigen::Vector3d& e2, const bool* wanted,
                           double* out) const;

 private:
  friend class SimplexSplineForest;
  struct Node {
    std::uint32_t mask = 0;
    // Leaf (3 knots, or a zero node: a subset on one great circle, with
    // orientation 0): local knot indices, ascending, and the triangle data.
    // Internal: the children S \ {w_j} (node indices) and W's matrix.
    int child[3] = {-1, -1, -1};
    int local[3] = {-1, -1, -1};
    int pair[3] = {-1, -1, -1};  // Leaf: pairs (b,c), (a,c), (a,b).
    int orientation = 0;         // Leaf: exact sign of det(t_a, t_b, t_c).
    double inv_abs_det = 0.0;    // Leaf: 1 / |det|.
    int matrix = -1;             // Internal: index into matrices_.
  };

  class TreeBuilder;  // Create's recursion tree

  SimplexSpline() = default;
  template <int K>
  void PathsOfDegree(const Eigen::Vector3d& o, const Eigen::Vector3d& e1,
                     const Eigen::Vector3d& e2, const bool* wanted,
                     double* out) const;
  template <int K>
  bool PieceOfDegree(const Eigen::Vector3d& q, const Eigen::Vector3d& o,
                     const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                     double* out) const;
  double LeafValue(const Node& node, const int* signs) const;
  // Degree-0 values of the num_leaves_ leaves into `values`; false if all
  // are zero.
  bool LeafValues(const Eigen::Vector3d& p, double* values) const;

  Eigen::MatrixX3d knots_;
  // t_i x t_j for the pairs i < j in the order (0,1), (0,2), ..., (1,2), ...
  std::vector<Eigen::Vector3d> pair_normals_;
  std::vector<Eigen::Matrix3d> matrices_;  // Spherical barycentric G of W.
  // Children before parents; the num_leaves_ leaves (3 knots) first.
  std::vector<Node> nodes_;
  int num_leaves_ = 0;
  // The internal nodes of size d + 3 are level_start_[d] ..
  // level_start_[d + 1] - 1 (d = 1 .. k).
  std::array<int, kMaxKnots - 1> level_start_{};
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_SIMPLEX_SPLINE_H_
