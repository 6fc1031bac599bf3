#include "sdcb/core/spline/dcb_basis.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/sphere/perturbed_predicates.h"
#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {

// Slack so that rounding never drops a point of the support from its cap.
constexpr double kCapSlack = 1e-10;

Eigen::Vector3d Knot(const Eigen::MatrixX3d& knots, int i) {
  return knots.row(i).transpose();
}

// The smaller cap bounded by the circle through a, b, c (paper Definition
// 3), loosened to contain every knot of `set` with a little slack.
SphericalCap BoundaryCap(const Eigen::MatrixX3d& knots,
                         const std::array<int, 3>& b,
                         const std::vector<int>& set) {
  const Eigen::Vector3d ta = Knot(knots, b[0]), tb = Knot(knots, b[1]),
                        tc = Knot(knots, b[2]);
  Eigen::Vector3d axis = (tb - ta).cross(tc - ta).normalized();
  if (axis.dot(ta) < 0) axis = -axis;
  SphericalCap cap;
  cap.axis = axis;
  cap.cos_radius = axis.dot(ta);
  for (int q : set) {
    cap.cos_radius = std::min(cap.cos_radius, axis.dot(Knot(knots, q)));
  }
  cap.cos_radius -= kCapSlack;
  return cap;
}

int Clamp(int v, int lo, int hi) { return std::max(lo, std::min(hi, v)); }

Eigen::MatrixX3d Rows(const Eigen::MatrixX3d& knots,
                      const std::vector<int>& indices) {
  Eigen::MatrixX3d local(indices.size(), 3);
  for (size_t j = 0; j < indices.size(); ++j) {
    local.row(j) = knots.row(indices[j]);
  }
  return local;
}

// kInvalidArgument unless every set of `configurations` has degree + 3
// knots in [0, n) and boundary triples of its own knots.
Status CheckConfigurationSets(const DelaunayConfigurations& configurations,
                              int n) {
  const int k = configurations.degree;
  for (size_t i = 0; i < configurations.sets.size(); ++i) {
    const ConfigurationSet& set = configurations.sets[i];
    const std::string where = "configuration set " + std::to_string(i);
    if (static_cast<int>(set.knots.size()) != k + 3) {
      return InvalidArgumentError(where + " does not have degree + 3 knots");
    }
    if (set.boundaries.empty()) {
      return InvalidArgumentError(where + " has no boundary triple");
    }
    for (int q : set.knots) {
      if (q < 0 || q >= n) {
        return InvalidArgumentError(where + " has a knot index out of range");
      }
    }
    for (const auto& b : set.boundaries) {
      for (int q : b) {
        if (!std::binary_search(set.knots.begin(), set.knots.end(), q)) {
          return InvalidArgumentError(where +
                                      " has a boundary knot outside the set");
        }
      }
    }
  }
  return Status();
}

}  // namespace

// One basis function (eq. 4) of the set: its simplex spline and weight, the
// limit terms of its flat boundary triples, and its support cap.
Status DcbBasis::BuildBasisFunction(const Eigen::MatrixX3d& knots,
                                    const ConfigurationSet& set,
                                    const SimplexSplineOptions& options,
                                    std::optional<SimplexSpline>* spline,
                                    double* weight,
                                    std::vector<LimitTerm>* limit_terms,
                                    SphericalCap* support) {
  const Eigen::MatrixX3d local = Rows(knots, set.knots);
  const bool pointed = InOpenHemisphere(local);
  *weight = 0.0;
  SphericalCap best;
  best.cos_radius = -2.0;
  for (const auto& b : set.boundaries) {
    const Eigen::Vector3d ta = Knot(knots, b[0]), tb = Knot(knots, b[1]),
                          tc = Knot(knots, b[2]);
    const SphericalCap cap = BoundaryCap(knots, b, set.knots);
    if (cap.cos_radius > best.cos_radius) best = cap;
    if (SpansR3(ta, tb, tc)) {
      // Eq. 4: B = sum_X |det(X_B)| M(p | X~), summed in the sets' order.
      *weight += std::abs(Det3(ta, tb, tc));
      continue;
    }
    // X_B on a great circle: its cap is a hemisphere, decided by the
    // configurations' perturbation. For the perturbed knots, eq. 3 with
    // W = X_B gives |det X_B| M(p | X~) = s sum_j det(X_B, x_j -> p)
    // M(p | X~ \ x_j), s the perturbed sign of det(X_B); its limit keeps
    // the cofactors and the children's simplex splines. If X~ lies in an
    // open hemisphere, M(p | X~) stays bounded and the limit is 0.
    if (pointed) continue;
    if (set.knots.size() == 3) {
      return InvalidInputError("a degree-0 configuration on a great circle");
    }
    const double s =
        PerturbedOrient3dSign(knots, kOriginIndex, b[0], b[1], b[2]);
    const Eigen::Vector3d cofactor[3] = {s * tb.cross(tc), s * tc.cross(ta),
                                         s * ta.cross(tb)};
    for (int j = 0; j < 3; ++j) {
      // Two antipodal corners left: the cofactor is 0 and so is the term.
      if (cofactor[j].isZero(0.0)) continue;
      std::vector<int> child;
      for (int q : set.knots) {
        if (q != b[j]) child.push_back(q);
      }
      const Eigen::MatrixX3d c = Rows(knots, child);
      // A child on one great circle is a measure on a plane where its
      // cofactor vanishes (the plane holds the other two corners): term 0.
      if (!KnotsSpanR3(c)) continue;
      StatusOr<SimplexSpline> m = SimplexSpline::Create(c, options);
      if (!m.ok()) {
        return InvalidInputError(
            "degenerate knots not supported: boundary triple (" +
            std::to_string(b[0]) + " " + std::to_string(b[1]) + " " +
            std::to_string(b[2]) +
            ") lies on a great circle, the set's knots are not in an open "
            "hemisphere, and without knot " +
            std::to_string(b[j]) + " they are still not (" +
            m.status().message() + "; docs/BASIS.md)");
      }
      limit_terms->push_back({cofactor[j], std::move(m).value()});
    }
  }
  if (pointed) {
    StatusOr<SimplexSpline> m = SimplexSpline::Create(local, options);
    if (!m.ok()) return m.status();
    *spline = std::move(m).value();
  } else if (*weight != 0.0) {
    // Unreachable: a boundary off every great circle bounds a cap smaller
    // than a hemisphere, which holds the set.
    return InternalError("a set outside an open hemisphere has a proper cap");
  }
  // A cap larger than a hemisphere is not convex: fall back to the sphere.
  if (best.cos_radius < 0.0) best.cos_radius = -2.0;
  *support = best;
  return Status();
}

StatusOr<DcbBasis> DcbBasis::Create(
    const Eigen::MatrixX3d& knots, const DelaunayConfigurations& configurations,
    const DcbBasisOptions& options) {
  const int n = static_cast<int>(knots.rows());
  const int k = configurations.degree;
  if (k < 0 || k > SimplexSpline::kMaxKnots - 3) {
    return InvalidArgumentError("DCB basis degree must be in 0..5, got " +
                                std::to_string(k));
  }
  SDCB_RETURN_IF_ERROR(CheckConfigurationSets(configurations, n));

  DcbBasis basis;
  basis.degree_ = k;
  basis.knots_ = knots;
  basis.sets_ = configurations.sets;
  const int m = static_cast<int>(basis.sets_.size());
  basis.weights_.assign(m, 0.0);
  basis.caps_.resize(m);
  std::vector<std::optional<SimplexSpline>> splines(m);
  std::vector<std::vector<LimitTerm>> limit_terms(m);
  std::vector<Status> statuses(m);
  tbb::parallel_for(0, m, [&](int i) {
    statuses[i] = BuildBasisFunction(knots, basis.sets_[i], options.spline,
                                     &splines[i], &basis.weights_[i],
                                     &limit_terms[i], &basis.caps_[i]);
  });
  for (int i = 0; i < m; ++i) {
    if (statuses[i].ok()) continue;
    std::string where = "configuration set " + std::to_string(i) + " (knots";
    for (int q : basis.sets_[i].knots) where += " " + std::to_string(q);
    return statuses[i].WithPrefix(where + ")");
  }
  basis.splines_ = std::move(splines);
  basis.forest_handle_.assign(m, -1);
  if (options.spline.split_seed == 0) {
    for (int i = 0; i < m; ++i) {
      if (basis.splines_[i].has_value()) {
        basis.forest_handle_[i] =
            basis.forest_.Add(*basis.splines_[i], basis.sets_[i].knots);
      }
    }
    basis.forest_.FinishAdding();
  }
  basis.BuildHulls();
  basis.limit_start_.assign(m + 1, 0);
  for (int i = 0; i < m; ++i) {
    basis.limit_start_[i + 1] =
        basis.limit_start_[i] + static_cast<int>(limit_terms[i].size());
    for (LimitTerm& t : limit_terms[i]) {
      basis.limit_terms_.push_back(std::move(t));
    }
  }

  basis.BuildSupportGrid(options.grid_rows);
  SDCB_RETURN_IF_ERROR(basis.CheckCoverage(options.coverage_samples));
  return basis;
}

// The great circles bounding each set's spherical convex hull, interior on
// the positive side: a point strictly outside one of them is outside the
// support (B = 0 there, with all derivatives), so evaluation can skip it.
void DcbBasis::BuildHulls() {
  const int m = static_cast<int>(sets_.size());
  std::vector<std::vector<Eigen::Vector3d>> hulls(m);
  tbb::parallel_for(0, m, [&](int i) {
    if (!splines_[i].has_value()) return;  // no pointed cone: no test
    const std::vector<int>& set = sets_[i].knots;
    for (int a : set) {
      for (int b : set) {
        if (a == b) continue;
        const Eigen::Vector3d ka = knots_.row(a).transpose();
        const Eigen::Vector3d kb = knots_.row(b).transpose();
        bool edge = true;
        for (int c : set) {
          if (c == a || c == b) continue;
          edge = edge && Det3Sign(ka, kb, knots_.row(c).transpose()) > 0;
        }
        if (edge) hulls[i].push_back(ka.cross(kb));
      }
    }
  });
  hull_start_.assign(m + 1, 0);
  for (int i = 0; i < m; ++i) {
    hull_start_[i + 1] = hull_start_[i] + static_cast<int>(hulls[i].size());
    for (const Eigen::Vector3d& n : hulls[i]) hull_normals_.push_back(n);
  }
}

// The support grid over latitude / longitude: each cell lists the basis
// functions whose support cap may meet it.
void DcbBasis::BuildSupportGrid(int grid_rows) {
  const int n = static_cast<int>(knots_.rows());
  const int m = static_cast<int>(sets_.size());
  rows_ = grid_rows > 0
              ? grid_rows
              : Clamp(static_cast<int>(std::ceil(std::sqrt(n))), 4, 512);
  const int rows = rows_, cols = 2 * rows;
  std::vector<std::vector<int>> cells(rows * cols);
  for (int i = 0; i < m; ++i) {
    const SphericalCap& cap = caps_[i];
    const double radius =
        std::acos(std::max(-1.0, std::min(1.0, cap.cos_radius))) + 1e-9;
    const double lat = std::asin(std::max(-1.0, std::min(1.0, cap.axis.z())));
    const double lon = std::atan2(cap.axis.y(), cap.axis.x());
    const double lat_lo = lat - radius, lat_hi = lat + radius;
    const int r0 =
        Clamp(static_cast<int>(std::floor((lat_lo + kPi / 2) / kPi * rows)), 0,
              rows - 1);
    const int r1 =
        Clamp(static_cast<int>(std::floor((lat_hi + kPi / 2) / kPi * rows)), 0,
              rows - 1);
    // Longitude half-width of a cap that avoids both poles.
    bool all_columns = lat_hi >= kPi / 2 || lat_lo <= -kPi / 2;
    double half_width = kPi;
    if (!all_columns) {
      const double s = std::sin(radius) / std::cos(lat);
      if (s >= 1.0) {
        all_columns = true;
      } else {
        half_width = std::asin(s) + 1e-9;
      }
    }
    int c0 = 0, c1 = cols - 1;
    if (!all_columns) {
      c0 = static_cast<int>(
          std::floor((lon - half_width + kPi) / (2 * kPi) * cols));
      c1 = static_cast<int>(
          std::floor((lon + half_width + kPi) / (2 * kPi) * cols));
      if (c1 - c0 + 1 >= cols) {
        c0 = 0;
        c1 = cols - 1;
      }
    }
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) {
        const int wrapped = ((c % cols) + cols) % cols;
        cells[r * cols + wrapped].push_back(i);
      }
  }
  cell_start_.assign(rows * cols + 1, 0);
  for (int c = 0; c < rows * cols; ++c) {
    cell_start_[c + 1] = cell_start_[c] + static_cast<int>(cells[c].size());
  }
  cell_items_.reserve(cell_start_.back());
  for (const auto& cell : cells) {
    cell_items_.insert(cell_items_.end(), cell.begin(), cell.end());
  }
}

Status DcbBasis::CheckCoverage(int samples) const {
  if (samples <= 0) return Status();
  // Fibonacci spiral: quasi-uniform, deterministic.
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  Eigen::MatrixX3d points(samples, 3);
  for (int i = 0; i < samples; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / samples;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    points.row(i) << r * std::cos(golden * i), r * std::sin(golden * i), z;
  }
  std::vector<char> covered(samples, 0);
  ParallelForEachPoint(points, [&](Eigen::Index r) {
    covered[r] = Normalization(points.row(r).transpose()) > 0.0;
  });
  for (int i = 0; i < samples; ++i) {
    if (covered[i]) continue;
    const Eigen::RowVector3d p = points.row(i);
    return InvalidInputError(
        "the degree-" + std::to_string(degree_) + " basis of these " +
        std::to_string(knots_.rows()) +
        " knots leaves a hole: I = sum B_i = 0 near (" + std::to_string(p.x()) +
        ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) +
        "), outside every basis support (too few or too unevenly spread "
        "knots for this degree)");
  }
  return Status();
}

int DcbBasis::CellOf(const Eigen::Vector3d& p) const {
  const int rows = rows_, cols = 2 * rows_;
  const Eigen::Vector3d u = p.normalized();
  const double lat = std::asin(std::max(-1.0, std::min(1.0, u.z())));
  const double lon = std::atan2(u.y(), u.x());
  const int r = Clamp(
      static_cast<int>(std::floor((lat + kPi / 2) / kPi * rows)), 0, rows - 1);
  const int c =
      Clamp(static_cast<int>(std::floor((lon + kPi) / (2 * kPi) * cols)), 0,
            cols - 1);
  return r * cols + c;
}

std::vector<Eigen::Index> DcbBasis::LocalityOrder(
    const Eigen::MatrixX3d& points) const {
  std::vector<std::pair<int, Eigen::Index>> keyed(points.rows());
  for (Eigen::Index r = 0; r < points.rows(); ++r) {
    keyed[r] = {CellOf(points.row(r).transpose()), r};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<Eigen::Index> order(points.rows());
  for (Eigen::Index r = 0; r < points.rows(); ++r) order[r] = keyed[r].second;
  return order;
}

template <typename ForestValue>
double DcbBasis::ValueWith(int i, const Eigen::Vector3d& p,
                           const ForestValue& forest_value) const {
  double value = 0.0;
  if (weights_[i] != 0.0) {
    value =
        weights_[i] * (forest_handle_[i] >= 0 ? forest_value(forest_handle_[i])
                                              : splines_[i]->Value(p));
  }
  for (int t = limit_start_[i]; t < limit_start_[i + 1]; ++t) {
    const LimitTerm& term = limit_terms_[t];
    value += term.cofactor.dot(p) * term.spline.Value(p);
  }
  return value;
}

double DcbBasis::Value(int i, const Eigen::Vector3d& p) const {
  return ValueWith(i, p, [&](int handle) { return forest_.Value(handle, p); });
}

ScalarJet DcbBasis::Evaluate(int i, const Eigen::Vector3d& p,
                             JetOrder order) const {
  ScalarJet jet;
  if (weights_[i] != 0.0) {
    jet = forest_handle_[i] >= 0 ? forest_.Evaluate(forest_handle_[i], p, order)
                                 : splines_[i]->Evaluate(p, order);
    jet.value *= weights_[i];
    jet.gradient *= weights_[i];
    jet.hessian *= weights_[i];
  }
  for (int t = limit_start_[i]; t < limit_start_[i + 1]; ++t) {
    // (a . p) M: gradient a M + (a . p) grad M, Hessian a grad M^T +
    // grad M a^T + (a . p) hess M.
    const LimitTerm& term = limit_terms_[t];
    const ScalarJet m = term.spline.Evaluate(p, order);
    const Eigen::Vector3d& a = term.cofactor;
    const double ap = a.dot(p);
    jet.value += ap * m.value;
    if (order == JetOrder::kValue) continue;
    jet.gradient += a * m.value + ap * m.gradient;
    if (order == JetOrder::kHessian) {
      jet.hessian += a * m.gradient.transpose() + m.gradient * a.transpose() +
                     ap * m.hessian;
    }
  }
  return jet;
}

bool DcbBasis::AddPiecePolynomial(int i, const Eigen::Vector3d& q,
                                  const Eigen::Vector3d& o,
                                  const Eigen::Vector3d& e1,
                                  const Eigen::Vector3d& e2,
                                  double* out) const {
  constexpr int kSize = PolynomialSize(SimplexSpline::kMaxKnots - 3);
  double piece[kSize];
  bool any = false;
  const int size = PolynomialSize(degree_);
  // Outside the hull by a margin every leaf of the recursion vanishes at q.
  if (OutsideHull(i, q.normalized())) return false;
  if (weights_[i] != 0.0 && splines_[i]->PiecePolynomial(q, o, e1, e2, piece)) {
    for (int c = 0; c < size; ++c) out[c] += weights_[i] * piece[c];
    any = true;
  }
  for (int t = limit_start_[i]; t < limit_start_[i + 1]; ++t) {
    // (a . p) M(p | X~ \ x_j), M of degree k - 1.
    const LimitTerm& term = limit_terms_[t];
    double child[kSize];
    if (!term.spline.PiecePolynomial(q, o, e1, e2, child)) continue;
    const Eigen::Vector3d& a = term.cofactor;
    AccumulateAffineProduct(a.dot(o), a.dot(e1), a.dot(e2), child, degree_ - 1,
                            out);
    any = true;
  }
  return any;
}

void DcbBasis::Candidates(const Eigen::Vector3d& p,
                          std::vector<int>* out) const {
  out->clear();
  ForEachCandidate(p, [&](int i) { out->push_back(i); });
}

void DcbBasis::NonzeroValues(const Eigen::Vector3d& p,
                             std::vector<BasisValue>* out) const {
  out->clear();
  // Value(i, p), the forest's memo prepared once for the point.
  const SimplexSplineForest::PointValues at = forest_.At(p);
  const auto forest_value = [&](int handle) { return at.value(handle); };
  ForEachCandidate(p, [&](int i) {
    const double v = ValueWith(i, p, forest_value);
    if (v != 0.0) out->push_back({i, v});
  });
}

void DcbBasis::ParallelForEachPoint(
    const Eigen::MatrixX3d& points,
    const std::function<void(Eigen::Index)>& visit) const {
  const std::vector<Eigen::Index> order = LocalityOrder(points);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, points.rows(), 128),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      for (Eigen::Index o = range.begin(); o < range.end();
                           ++o) {
                        visit(order[o]);
                      }
                    });
}

double DcbBasis::Normalization(const Eigen::Vector3d& p) const {
  thread_local std::vector<BasisValue> values;  // no allocation per point
  NonzeroValues(p, &values);
  double sum = 0.0;
  for (const BasisValue& v : values) sum += v.value;
  return sum;
}

void DcbBasis::NormalizedValues(const Eigen::Vector3d& p,
                                std::vector<BasisValue>* out) const {
  NonzeroValues(p, out);
  double sum = 0.0;
  for (const BasisValue& v : *out) sum += v.value;
  // Eq. 5: Bbar = B / I.
  for (BasisValue& v : *out) v.value /= sum;
}

}  // namespace sdcb
