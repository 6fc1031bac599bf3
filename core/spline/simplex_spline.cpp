#include "sdcb/core/spline/simplex_spline.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/sphere/spherical_barycentric.h"

namespace sdcb {
namespace {

constexpr int kMax = SimplexSpline::kMaxKnots;

constexpr int kMaxPairs = kMax * (kMax - 1) / 2;

// Fixed generic axes of the half-open perturbation.
const Eigen::Vector3d kAxis1(0.5773502691896258, 0.3141592653589793,
                             0.7548776662466927);
const Eigen::Vector3d kAxis2(-0.2718281828459045, 0.8660254037844386,
                             0.1414213562373095);

std::uint32_t Mix(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

}  // namespace

bool SpansR3(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
             const Eigen::Vector3d& c) {
  return std::abs(Det3(a, b, c)) > kFlatDeterminant;
}

bool KnotsSpanR3(const Eigen::MatrixX3d& knots) {
  const int m = static_cast<int>(knots.rows());
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b)
      for (int c = b + 1; c < m; ++c) {
        if (SpansR3(knots.row(a).transpose(), knots.row(b).transpose(),
                    knots.row(c).transpose())) {
          return true;
        }
      }
  return false;
}

int ExactPerturbedDetSign(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                          const Eigen::Vector3d& b) {
  int s = Det3Sign(p, a, b);
  if (s != 0) return s;
  s = Det3Sign(kAxis1.cross(p), a, b);
  if (s != 0) return s;
  return Det3Sign(kAxis2.cross(p), a, b);
}

int PerturbedDetSign(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                     const Eigen::Vector3d& b) {
  const double bound = kSignFilter * p.cwiseAbs().sum() * a.cwiseAbs().sum() *
                       b.cwiseAbs().sum();
  return FilteredSign(p.dot(a.cross(b)), bound, p, a, b);
}

bool InHalfOpenTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                        const Eigen::Vector3d& t1, const Eigen::Vector3d& t2) {
  const int o = Det3Sign(t0, t1, t2);
  if (o == 0) return false;
  // det(p,t1,t2), det(t0,p,t2) = det(p,t2,t0), det(t0,t1,p) = det(p,t0,t1).
  return PerturbedDetSign(p, t1, t2) == o && PerturbedDetSign(p, t2, t0) == o &&
         PerturbedDetSign(p, t0, t1) == o;
}

// The recursion tree of M(p | V) (eq. 3) for SimplexSpline::Create, built
// depth-first, children first, each subset of the knots once.
class SimplexSpline::TreeBuilder {
 public:
  // Appends the nodes to `*built` and W's matrices to `*matrices`.
  TreeBuilder(const Eigen::MatrixX3d& knots,
              const SimplexSplineOptions& options, std::vector<Node>* built,
              std::vector<Eigen::Matrix3d>* matrices)
      : knots_(knots),
        options_(options),
        m_(static_cast<int>(knots.rows())),
        built_(*built),
        matrices_(*matrices) {
    // Every triple's determinant, once: det_[(a * kMax + b) * kMax + c] for
    // a < b < c (the same product SpansR3 and Det3 would compute).
    for (int a = 0; a < m_; ++a)
      for (int b = a + 1; b < m_; ++b)
        for (int c = b + 1; c < m_; ++c) {
          det_[(a * kMax + b) * kMax + c] = Det3(t(a), t(b), t(c));
        }
    index_of_.fill(-1);
    matrix_of_.fill(-1);
  }

  // The index in *built of the node of the subset `mask` (bit i: knot i),
  // built with its descendants on first use.
  int Build(std::uint32_t mask) {
    if (index_of_[mask] >= 0) return index_of_[mask];
    int members[kMax];
    int ms = 0;
    for (int i = 0; i < m_; ++i)
      if (mask & (1u << i)) members[ms++] = i;
    Node node;
    node.mask = mask;
    std::array<int, 3> w;
    if (ms == 3) {
      MakeLeaf(members[0], members[1], members[2], &node);
    } else if (PickSplit(mask, members, ms, &w)) {
      node.matrix = MatrixOf(w);
      for (int j = 0; j < 3; ++j) {
        node.local[j] = w[j];
        node.child[j] = Build(mask & ~(1u << w[j]));
      }
    }
    // else: S lies on a plane P through the origin (up to kFlatDeterminant):
    // M(p | S) is a measure on P, and its coefficient in the parent vanishes
    // on P (the parent's W spans R^3, and its two members in S span P, so
    // b_j = det(.., p, ..) / det(W) is 0 there). The product is 0: a zero
    // leaf (orientation 0: value 0), like a three-knot subset with det = 0
    // (degree 0, eq. 3).
    const int index = static_cast<int>(built_.size());
    built_.push_back(node);
    index_of_[mask] = index;
    return index;
  }

 private:
  Eigen::Vector3d t(int i) const { return knots_.row(i).transpose(); }
  double TripleDet(int a, int b, int c) const {
    return det_[(a * kMax + b) * kMax + c];
  }
  bool Spans(int a, int b, int c) const {
    return std::abs(TripleDet(a, b, c)) > kFlatDeterminant;
  }

  // Fills the leaf `node` of the triple a < b < c.
  void MakeLeaf(int a, int b, int c, Node* node) const {
    node->local[0] = a;
    node->local[1] = b;
    node->local[2] = c;
    node->pair[0] = PairIndex(b, c, m_);
    node->pair[1] = PairIndex(a, c, m_);
    node->pair[2] = PairIndex(a, b, m_);
    // det = 0 (three knots on a great circle, or within kFlatDeterminant of
    // one): a zero leaf, for the reason given in Build for larger flat
    // subsets.
    node->orientation = Spans(a, b, c) ? Det3Sign(t(a), t(b), t(c)) : 0;
    if (node->orientation != 0) {
      node->inv_abs_det = 1.0 / std::abs(TripleDet(a, b, c));
    }
  }

  // The triple W of the subset `mask` (members[0 .. ms), ascending) that
  // eq. 3 splits it by: by default the spanning triple of largest |det|,
  // whose barycentric coordinates stay small over the hull of S (the
  // recursion then cancels little); with a split seed, a seeded pick among
  // the fair ones. False if no triple spans R^3.
  bool PickSplit(std::uint32_t mask, const int* members, int ms,
                 std::array<int, 3>* w) const {
    // Spanning triples of S in ascending order.
    std::array<int, 3> spanning[kMax * (kMax - 1) * (kMax - 2) / 6];
    int num_spanning = 0;
    for (int x = 0; x < ms; ++x)
      for (int y = x + 1; y < ms; ++y)
        for (int z = y + 1; z < ms; ++z) {
          if (Spans(members[x], members[y], members[z])) {
            spanning[num_spanning++] = {members[x], members[y], members[z]};
          }
        }
    if (num_spanning == 0) return false;
    int pick = 0;
    double largest = -1.0;
    for (int x = 0; x < num_spanning; ++x) {
      const auto& s = spanning[x];
      const double v = std::abs(TripleDet(s[0], s[1], s[2]));
      if (v > largest) {
        largest = v;
        pick = x;
      }
    }
    if (options_.split_seed != 0) {
      // Any W gives the same M; skip triples so thin that rounding would
      // dominate (|det| below a quarter of the largest).
      std::vector<int> fair;
      for (int x = 0; x < num_spanning; ++x) {
        const auto& s = spanning[x];
        if (std::abs(TripleDet(s[0], s[1], s[2])) >= 0.25 * largest) {
          fair.push_back(x);
        }
      }
      pick = fair[Mix(options_.split_seed * 0x9e3779b9U ^ mask) % fair.size()];
    }
    *w = spanning[pick];
    return true;
  }

  // The index in *matrices of W's spherical barycentric matrix, made on
  // first use.
  int MatrixOf(const std::array<int, 3>& w) {
    int& matrix = matrix_of_[(w[0] * kMax + w[1]) * kMax + w[2]];
    if (matrix < 0) {
      matrix = static_cast<int>(matrices_.size());
      matrices_.push_back(
          SphericalBarycentricMatrix(t(w[0]), t(w[1]), t(w[2])));
    }
    return matrix;
  }

  const Eigen::MatrixX3d& knots_;
  const SimplexSplineOptions& options_;
  const int m_;
  std::array<double, kMax * kMax * kMax> det_;
  std::array<int, 1 << kMax> index_of_;            // -1: not built yet
  std::array<int, kMax * kMax * kMax> matrix_of_;  // W's matrix, -1: none yet
  std::vector<Node>& built_;
  std::vector<Eigen::Matrix3d>& matrices_;
};

StatusOr<SimplexSpline> SimplexSpline::Create(
    const Eigen::MatrixX3d& knots, const SimplexSplineOptions& options) {
  const int m = static_cast<int>(knots.rows());
  if (m < 3 || m > kMax) {
    return InvalidArgumentError("a simplex spline needs 3 to 8 knots, got " +
                                std::to_string(m));
  }
  if (!AllUnitRows(knots)) {
    return InvalidArgumentError("simplex spline knots must be unit vectors");
  }
  // M(p | V) is a bounded function only if V spans R^3 (otherwise it is a
  // measure on a great circle) and lies in an open hemisphere (otherwise
  // its cone is not pointed and the integral defining it diverges).
  if (!KnotsSpanR3(knots)) {
    return InvalidInputError(
        "simplex spline knots: all lie on one great circle");
  }
  if (!InOpenHemisphere(knots)) {
    return InvalidInputError(
        "simplex spline knots: not in an open hemisphere (antipodal knots, "
        "or the origin in their convex hull)");
  }
  SimplexSpline s;
  s.knots_ = knots;
  auto t = [&](int i) -> Eigen::Vector3d { return knots.row(i).transpose(); };
  s.pair_normals_.assign(m * (m - 1) / 2, Eigen::Vector3d::Zero());
  for (int i = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j) {
      s.pair_normals_[PairIndex(i, j, m)] = t(i).cross(t(j));
    }

  // Built in this thread's buffers, kept at their exact sizes.
  thread_local std::vector<Node> built;
  thread_local std::vector<Eigen::Matrix3d> matrices;
  built.clear();
  matrices.clear();
  TreeBuilder(knots, options, &built, &matrices).Build((1u << m) - 1);
  // Leaves first, so an evaluation can stop once all degree-0 values are
  // known to vanish; then the internal nodes by size (children before
  // parents), each size's first at level_start_[size - 3].
  std::array<int, 1 << kMax> new_index;
  std::vector<Node>& ordered = s.nodes_;
  ordered.reserve(built.size());
  for (size_t i = 0; i < built.size(); ++i) {
    if (built[i].matrix < 0) {
      new_index[i] = static_cast<int>(ordered.size());
      ordered.push_back(built[i]);
    }
  }
  s.num_leaves_ = static_cast<int>(ordered.size());
  for (int size = 4; size <= m; ++size) {
    s.level_start_[size - 3] = static_cast<int>(ordered.size());
    for (size_t i = 0; i < built.size(); ++i) {
      if (built[i].matrix >= 0 && __builtin_popcount(built[i].mask) == size) {
        new_index[i] = static_cast<int>(ordered.size());
        ordered.push_back(built[i]);
      }
    }
  }
  s.level_start_[m - 2] = static_cast<int>(ordered.size());
  for (Node& node : ordered) {
    for (int& c : node.child) {
      if (c >= 0) c = new_index[c];
    }
  }
  s.matrices_.assign(matrices.begin(), matrices.end());
  return s;
}

void SimplexSpline::PairSigns(const Eigen::Vector3d& p, int* signs) const {
  const int m = static_cast<int>(knots_.rows());
  // Unit knots: |t_i|_1 |t_j|_1 <= 3 (+ kUnitVectorTolerance).
  const double bound = kSignFilter * 3.01 * p.cwiseAbs().sum();
  for (int i = 0, k = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j, ++k) {
      signs[k] =
          FilteredSign(p.dot(pair_normals_[k]), bound, p,
                       knots_.row(i).transpose(), knots_.row(j).transpose());
    }
}

double SimplexSpline::LeafValue(const Node& node, const int* signs) const {
  // Inside [ta, tb, tc) (a < b < c) iff det(p,tb,tc), det(p,tc,ta) and
  // det(p,ta,tb) all have the triangle's orientation; det(p,tc,ta) is minus
  // the pair sign of (a, c).
  const int o = node.orientation;
  if (o == 0) return 0.0;
  const bool inside = signs[node.pair[0]] == o && signs[node.pair[1]] == -o &&
                      signs[node.pair[2]] == o;
  return inside ? node.inv_abs_det : 0.0;
}

bool SimplexSpline::LeafValues(const Eigen::Vector3d& p, double* values) const {
  int signs[kMaxPairs];
  PairSigns(p, signs);
  // All zero iff p is outside the hull of V; then M and its derivatives
  // vanish.
  bool any = false;
  for (int i = 0; i < num_leaves_; ++i) {
    values[i] = LeafValue(nodes_[i], signs);
    any = any || values[i] != 0.0;
  }
  return any;
}

double SimplexSpline::Value(const Eigen::Vector3d& p) const {
  double values[256];
  if (!LeafValues(p, values)) return 0.0;
  const int count = static_cast<int>(nodes_.size());
  for (int i = num_leaves_; i < count; ++i) {
    const Node& node = nodes_[i];
    const double v0 = values[node.child[0]], v1 = values[node.child[1]],
                 v2 = values[node.child[2]];
    // Most subsets' hulls miss p: skip the barycentric product there.
    if (v0 == 0.0 && v1 == 0.0 && v2 == 0.0) {
      values[i] = 0.0;
      continue;
    }
    // Eq. 3: M(p|S) = sum_j b_j(p|W) M(p|S \ {w_j}).
    const Eigen::Vector3d b = matrices_[node.matrix] * p;
    values[i] = b[0] * v0 + b[1] * v1 + b[2] * v2;
  }
  return values[count - 1];
}

ScalarJet SimplexSpline::Evaluate(const Eigen::Vector3d& p,
                                  JetOrder order) const {
  ScalarJet jet;
  if (order == JetOrder::kValue) {
    jet.value = Value(p);
    return jet;
  }
  // Per node: the value, the gradient, the Hessian (row-major) when asked,
  // and whether the node is identically zero around p (all its leaves are),
  // so that its derivatives vanish too and it can be skipped.
  double value[256];
  if (!LeafValues(p, value)) return jet;
  double gradient[256][3];
  double hessian_storage[256][9];
  const bool hessian = order == JetOrder::kHessian;
  double(*hess)[9] = hessian ? hessian_storage : nullptr;
  bool live[256];
  // Degree 0: piecewise constant, zero derivatives.
  for (int i = 0; i < num_leaves_; ++i) {
    live[i] = value[i] != 0.0;
    gradient[i][0] = gradient[i][1] = gradient[i][2] = 0.0;
    if (hessian) std::fill(hess[i], hess[i] + 9, 0.0);
  }
  const int count = static_cast<int>(nodes_.size());
  for (int i = num_leaves_; i < count; ++i) {
    const Node& node = nodes_[i];
    double* g_out = gradient[i];
    value[i] = g_out[0] = g_out[1] = g_out[2] = 0.0;
    if (hessian) std::fill(hess[i], hess[i] + 9, 0.0);
    live[i] = live[node.child[0]] || live[node.child[1]] || live[node.child[2]];
    if (!live[i]) continue;
    // Differentiating eq. 3 (grad b_j = g_j, the rows of G, constant):
    //   grad M = sum_j g_j M_j + b_j grad M_j,
    //   hess M = sum_j g_j grad M_j^T + grad M_j g_j^T + b_j hess M_j.
    const Eigen::Matrix3d& g = matrices_[node.matrix];
    const Eigen::Vector3d b = g * p;
    for (int j = 0; j < 3; ++j) {
      const int c = node.child[j];
      if (!live[c]) continue;
      const double gj[3] = {g(j, 0), g(j, 1), g(j, 2)};
      const double* gc = gradient[c];
      value[i] += b[j] * value[c];
      for (int r = 0; r < 3; ++r) g_out[r] += gj[r] * value[c] + b[j] * gc[r];
      if (hessian) {
        double* h = hess[i];
        const double* hc = hess[c];
        for (int r = 0; r < 3; ++r)
          for (int q = 0; q < 3; ++q) {
            h[3 * r + q] +=
                gj[r] * gc[q] + gc[r] * gj[q] + b[j] * hc[3 * r + q];
          }
      }
    }
  }
  const int top = count - 1;
  jet.value = value[top];
  jet.gradient =
      Eigen::Vector3d(gradient[top][0], gradient[top][1], gradient[top][2]);
  if (hessian) {
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) jet.hessian(r, q) = hess[top][3 * r + q];
  }
  return jet;
}

template <int K>
bool SimplexSpline::PieceOfDegree(const Eigen::Vector3d& q,
                                  const Eigen::Vector3d& o,
                                  const Eigen::Vector3d& e1,
                                  const Eigen::Vector3d& e2,
                                  double* out) const {
  double leaves[256];
  if (!LeafValues(q, leaves)) return false;
  // Each node's polynomial (degree = its size - 3) at slot[node] in poly, or
  // -1 where all its leaves vanish.
  int slot[256];
  double poly[256 * PolynomialSize(K > 0 ? K - 1 : 0) + 64];
  int used = 0;
  for (int i = 0; i < num_leaves_; ++i) {
    slot[i] = leaves[i] != 0.0 ? used : -1;
    if (leaves[i] != 0.0) poly[used++] = leaves[i];
  }
  const auto level = [&](auto degree) {
    constexpr int D = decltype(degree)::value;
    for (int i = level_start_[D]; i < level_start_[D + 1]; ++i) {
      const Node& node = nodes_[i];
      const int* c = node.child;
      slot[i] = -1;
      if (slot[c[0]] < 0 && slot[c[1]] < 0 && slot[c[2]] < 0) continue;
      double* result = D == K ? out : poly + used;
      std::fill(result, result + PolynomialSize(D), 0.0);
      // Eq. 3 with b_j(p(s, t)) = g_j . o + s g_j . e1 + t g_j . e2.
      const Eigen::Matrix3d& g = matrices_[node.matrix];
      for (int j = 0; j < 3; ++j) {
        if (slot[c[j]] < 0) continue;
        const Eigen::Vector3d gj = g.row(j).transpose();
        AddAffineProduct<D>(gj.dot(o), gj.dot(e1), gj.dot(e2),
                            poly + slot[c[j]], result);
      }
      slot[i] = used;
      if (D < K) used += PolynomialSize(D);
    }
  };
  if constexpr (K >= 1) level(std::integral_constant<int, 1>());
  if constexpr (K >= 2) level(std::integral_constant<int, 2>());
  if constexpr (K >= 3) level(std::integral_constant<int, 3>());
  if constexpr (K >= 4) level(std::integral_constant<int, 4>());
  if constexpr (K >= 5) level(std::integral_constant<int, 5>());
  const int count = static_cast<int>(nodes_.size());
  if (slot[count - 1] < 0) {
    // Every path to a nonzero leaf passes a zero node: M vanishes here.
    std::fill(out, out + PolynomialSize(K), 0.0);
  } else if (K == 0) {
    out[0] = poly[slot[count - 1]];
  }
  return true;
}

SimplexSpline::Leaf SimplexSpline::leaf(int i) const {
  const Node& node = nodes_[i];
  Leaf out;
  out.knots = {node.local[0], node.local[1], node.local[2]};
  out.orientation = node.orientation;
  out.inv_abs_det = node.inv_abs_det;
  return out;
}

template <int K>
void SimplexSpline::PathsOfDegree(const Eigen::Vector3d& o,
                                  const Eigen::Vector3d& e1,
                                  const Eigen::Vector3d& e2, const bool* wanted,
                                  double* out) const {
  constexpr int kSize = PolynomialSize(K);
  const int count = static_cast<int>(nodes_.size());
  // Only the nodes above a wanted leaf carry a polynomial: a node of size
  // |S| one of degree k + 3 - |S|, at slot[node] in poly.
  bool useful[256];
  for (int i = 0; i < num_leaves_; ++i) {
    useful[i] = wanted[i];
    if (wanted[i]) std::fill(out + i * kSize, out + (i + 1) * kSize, 0.0);
  }
  double poly[256 * PolynomialSize(K > 0 ? K - 1 : 0) + 64];
  int slot[256];
  int used = 0;
  for (int i = num_leaves_; i < count; ++i) {
    const int* c = nodes_[i].child;
    useful[i] = useful[c[0]] || useful[c[1]] || useful[c[2]];
    if (!useful[i]) continue;
    slot[i] = used;
    used += PolynomialSize(K - (__builtin_popcount(nodes_[i].mask) - 3));
  }
  if (!useful[count - 1]) return;
  if constexpr (K == 0) {
    out[0] = 1.0;  // V is its only leaf
    return;
  } else {
    std::fill(poly, poly + used, 0.0);
    poly[slot[count - 1]] = 1.0;
    // Parents before children (sizes descending): each passes its polynomial
    // times b_j(p(s, t)) = g_j . o + s g_j . e1 + t g_j . e2 to child j.
    const auto level = [&](auto degree) {
      constexpr int D = decltype(degree)::value;  // the parents' degree
      for (int i = level_start_[K - D]; i < level_start_[K - D + 1]; ++i) {
        if (!useful[i]) continue;
        const Node& node = nodes_[i];
        const Eigen::Matrix3d& g = matrices_[node.matrix];
        for (int j = 0; j < 3; ++j) {
          const int c = node.child[j];
          if (!useful[c]) continue;
          const Eigen::Vector3d gj = g.row(j).transpose();
          double* target = c < num_leaves_ ? out + c * kSize : poly + slot[c];
          AddAffineProduct<D + 1>(gj.dot(o), gj.dot(e1), gj.dot(e2),
                                  poly + slot[i], target);
        }
      }
    };
    level(std::integral_constant<int, 0>());
    if constexpr (K >= 2) level(std::integral_constant<int, 1>());
    if constexpr (K >= 3) level(std::integral_constant<int, 2>());
    if constexpr (K >= 4) level(std::integral_constant<int, 3>());
    if constexpr (K >= 5) level(std::integral_constant<int, 4>());
  }
}

void SimplexSpline::LeafPathPolynomials(const Eigen::Vector3d& o,
                                        const Eigen::Vector3d& e1,
                                        const Eigen::Vector3d& e2,
                                        const bool* wanted, double* out) const {
  WithDegree(degree(), [&](auto k) {
    PathsOfDegree<decltype(k)::value>(o, e1, e2, wanted, out);
  });
}

bool SimplexSpline::PiecePolynomial(const Eigen::Vector3d& q,
                                    const Eigen::Vector3d& o,
                                    const Eigen::Vector3d& e1,
                                    const Eigen::Vector3d& e2,
                                    double* out) const {
  return WithDegree(degree(), [&](auto k) {
    return PieceOfDegree<decltype(k)::value>(q, o, e1, e2, out);
  });
}

}  // namespace sdcb
