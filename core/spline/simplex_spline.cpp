#include "sdcb/core/spline/simplex_spline.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <string>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/sphere/spherical_barycentric.h"

namespace sdcb {
namespace {

constexpr int kMax = SimplexSpline::kMaxKnots;

// Index of the pair i < j among m knots: 0 .. m (m - 1) / 2 - 1, increasing
// in the order (0,1), (0,2), ..., (0,m-1), (1,2), ...
int PairIndex(int i, int j, int m) {
  return i * (2 * m - i - 1) / 2 + j - i - 1;
}
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

  // Depth-first construction, children first; `index_of` memoizes subsets.
  std::map<std::uint32_t, int> index_of;
  std::map<std::array<int, 3>, int> matrix_of;
  std::function<int(std::uint32_t)> build = [&](std::uint32_t mask) -> int {
    auto it = index_of.find(mask);
    if (it != index_of.end()) return it->second;
    std::vector<int> members;
    for (int i = 0; i < m; ++i)
      if (mask & (1u << i)) members.push_back(i);
    Node node;
    node.mask = mask;
    if (members.size() == 3) {
      const int a = members[0], b = members[1], c = members[2];
      node.local[0] = a;
      node.local[1] = b;
      node.local[2] = c;
      node.pair[0] = PairIndex(b, c, m);
      node.pair[1] = PairIndex(a, c, m);
      node.pair[2] = PairIndex(a, b, m);
      // det = 0 (three knots on a great circle, or within kFlatDeterminant of
      // one): a zero leaf, for the reason given below for larger flat
      // subsets.
      node.orientation =
          SpansR3(t(a), t(b), t(c)) ? Det3Sign(t(a), t(b), t(c)) : 0;
      if (node.orientation != 0) {
        node.inv_abs_det = 1.0 / std::abs(Det3(t(a), t(b), t(c)));
      }
    } else {
      // Spanning triples of S in ascending order; pick one by the rule.
      std::vector<std::array<int, 3>> spanning;
      const int ms = static_cast<int>(members.size());
      for (int x = 0; x < ms; ++x)
        for (int y = x + 1; y < ms; ++y)
          for (int z = y + 1; z < ms; ++z) {
            const std::array<int, 3> w = {members[x], members[y], members[z]};
            if (SpansR3(t(w[0]), t(w[1]), t(w[2]))) spanning.push_back(w);
          }
      if (spanning.empty()) {
        // S lies on a plane P through the origin (up to kFlatDeterminant): M(p
        // | S) is a measure on P, and its coefficient in the parent vanishes on
        // P (the parent's W spans R^3, and its two members in S span P, so b_j
        // = det(.., p,
        // ..) / det(W) is 0 there). The product is 0: a zero leaf, like a
        // three-knot subset with det = 0 (degree 0, eq. 3).
        const int index = static_cast<int>(s.nodes_.size());
        s.nodes_.push_back(node);  // orientation 0: value 0
        index_of[mask] = index;
        return index;
      }
      // Default: the triple of largest |det|, whose barycentric coordinates
      // stay small over the hull of S (the recursion then cancels little).
      size_t pick = 0;
      double largest = -1.0;
      for (size_t x = 0; x < spanning.size(); ++x) {
        const auto& w = spanning[x];
        const double v = std::abs(Det3(t(w[0]), t(w[1]), t(w[2])));
        if (v > largest) {
          largest = v;
          pick = x;
        }
      }
      if (options.split_seed != 0) {
        // Any W gives the same M; skip triples so thin that rounding would
        // dominate (|det| below a quarter of the largest).
        std::vector<size_t> fair;
        for (size_t x = 0; x < spanning.size(); ++x) {
          const auto& w = spanning[x];
          if (std::abs(Det3(t(w[0]), t(w[1]), t(w[2]))) >= 0.25 * largest) {
            fair.push_back(x);
          }
        }
        pick = fair[Mix(options.split_seed * 0x9e3779b9U ^ mask) % fair.size()];
      }
      const std::array<int, 3> w = spanning[pick];
      auto mit = matrix_of.find(w);
      if (mit == matrix_of.end()) {
        mit = matrix_of.emplace(w, static_cast<int>(s.matrices_.size())).first;
        s.matrices_.push_back(
            SphericalBarycentricMatrix(t(w[0]), t(w[1]), t(w[2])));
      }
      node.matrix = mit->second;
      for (int j = 0; j < 3; ++j) {
        node.local[j] = w[j];
        node.child[j] = build(mask & ~(1u << w[j]));
      }
    }
    const int index = static_cast<int>(s.nodes_.size());
    s.nodes_.push_back(node);
    index_of[mask] = index;
    return index;
  };
  build((1u << m) - 1);
  // Leaves first (stable; still children before parents), so an evaluation
  // can stop once all degree-0 values are known to vanish.
  std::vector<int> new_index(s.nodes_.size());
  std::vector<Node> ordered;
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t i = 0; i < s.nodes_.size(); ++i) {
      if ((s.nodes_[i].matrix < 0) == (pass == 0)) {
        new_index[i] = static_cast<int>(ordered.size());
        ordered.push_back(s.nodes_[i]);
      }
    }
    if (pass == 0) s.num_leaves_ = static_cast<int>(ordered.size());
  }
  for (Node& node : ordered) {
    for (int& c : node.child) {
      if (c >= 0) c = new_index[c];
    }
  }
  s.nodes_ = std::move(ordered);
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

bool SimplexSpline::PiecePolynomial(const Eigen::Vector3d& q,
                                    const Eigen::Vector3d& o,
                                    const Eigen::Vector3d& e1,
                                    const Eigen::Vector3d& e2,
                                    double* out) const {
  double leaves[256];
  if (!LeafValues(q, leaves)) return false;
  constexpr int kSize = PolynomialSize(kMax - 3);
  const int count = static_cast<int>(nodes_.size());
  // Reused per thread: this runs once per region and basis function.
  thread_local std::vector<std::array<double, kSize>> poly;
  if (static_cast<int>(poly.size()) < count) poly.resize(count);
  for (int i = 0; i < num_leaves_; ++i) {
    poly[i].fill(0.0);
    poly[i][0] = leaves[i];
  }
  for (int i = num_leaves_; i < count; ++i) {
    const Node& node = nodes_[i];
    poly[i].fill(0.0);
    // Eq. 3 with b_j(p(s, t)) = g_j . o + s g_j . e1 + t g_j . e2.
    const int child_degree = __builtin_popcount(node.mask) - 4;
    const Eigen::Matrix3d& g = matrices_[node.matrix];
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d gj = g.row(j).transpose();
      AccumulateAffineProduct(gj.dot(o), gj.dot(e1), gj.dot(e2),
                              poly[node.child[j]].data(), child_degree,
                              poly[i].data());
    }
  }
  const std::array<double, kSize>& top = poly[count - 1];
  std::copy(top.begin(), top.begin() + PolynomialSize(degree()), out);
  return true;
}

}  // namespace sdcb
