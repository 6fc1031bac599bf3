#include "core/dcb_basis.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "core/sphere_geometry.h"

namespace sdcb {
namespace {

constexpr double kPi = 3.14159265358979323846;
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

}  // namespace

StatusOr<DcbBasis> DcbBasis::Create(
    const Eigen::MatrixX3d& knots, const DelaunayConfigurations& configurations,
    const DcbBasisOptions& options) {
  const int n = static_cast<int>(knots.rows());
  const int k = configurations.degree;
  if (k < 0 || k > SimplexSpline::kMaxKnots - 3) {
    return InvalidArgumentError("DCB basis degree must be in 0..5, got " +
                                std::to_string(k));
  }
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

  DcbBasis basis;
  basis.degree_ = k;
  basis.knots_ = knots;
  basis.sets_ = configurations.sets;
  const int m = static_cast<int>(basis.sets_.size());
  basis.weights_.assign(m, 0.0);
  basis.caps_.resize(m);
  std::vector<std::optional<SimplexSpline>> splines(m);
  std::vector<Status> statuses(m);
  tbb::parallel_for(0, m, [&](int i) {
    const ConfigurationSet& set = basis.sets_[i];
    Eigen::MatrixX3d local(k + 3, 3);
    for (int j = 0; j < k + 3; ++j) local.row(j) = knots.row(set.knots[j]);
    StatusOr<SimplexSpline> spline =
        SimplexSpline::Create(local, options.spline);
    if (!spline.ok()) {
      statuses[i] = spline.status();
      return;
    }
    splines[i] = std::move(spline).value();
    // Eq. 4: B = sum_X |det(X_B)| M(p | X~), summed in the sets' order.
    double weight = 0.0;
    SphericalCap best;
    best.cos_radius = -2.0;
    for (const auto& b : set.boundaries) {
      weight += std::abs(
          Det3(Knot(knots, b[0]), Knot(knots, b[1]), Knot(knots, b[2])));
      const SphericalCap cap = BoundaryCap(knots, b, set.knots);
      if (cap.cos_radius > best.cos_radius) best = cap;
    }
    basis.weights_[i] = weight;
    basis.caps_[i] = best;
  });
  for (int i = 0; i < m; ++i) {
    if (statuses[i].ok()) continue;
    std::string where = "configuration set " + std::to_string(i) + " (knots";
    for (int q : basis.sets_[i].knots) where += " " + std::to_string(q);
    where += ")";
    if (statuses[i].code() == StatusCode::kInvalidInput) {
      // Only a boundary triple on a great circle (a hemisphere for a cap)
      // lets a set reach a closed hemisphere. The perturbed knots' basis
      // function |det X_B| M tends to 0 * infinity there; that limit is not
      // evaluated, so such inputs are refused rather than given a hole.
      return InvalidInputError(
          where + ": degenerate knots not supported: " +
          statuses[i].message() +
          "; a boundary triple lies on a great circle (docs/BASIS.md)");
    }
    return statuses[i].WithPrefix(where);
  }
  basis.splines_.reserve(m);
  for (auto& s : splines) basis.splines_.push_back(std::move(*s));

  // Support grid over latitude / longitude.
  basis.rows_ = options.grid_rows > 0
                    ? options.grid_rows
                    : Clamp(static_cast<int>(std::ceil(std::sqrt(n))), 4, 512);
  const int rows = basis.rows_, cols = 2 * rows;
  std::vector<std::vector<int>> cells(rows * cols);
  for (int i = 0; i < m; ++i) {
    const SphericalCap& cap = basis.caps_[i];
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
  basis.cell_start_.assign(rows * cols + 1, 0);
  for (int c = 0; c < rows * cols; ++c) {
    basis.cell_start_[c + 1] =
        basis.cell_start_[c] + static_cast<int>(cells[c].size());
  }
  basis.cell_items_.reserve(basis.cell_start_.back());
  for (const auto& cell : cells) {
    basis.cell_items_.insert(basis.cell_items_.end(), cell.begin(), cell.end());
  }
  return basis;
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

double DcbBasis::Value(int i, const Eigen::Vector3d& p) const {
  return weights_[i] * splines_[i].Value(p);
}

ScalarJet DcbBasis::Evaluate(int i, const Eigen::Vector3d& p,
                             JetOrder order) const {
  ScalarJet jet = splines_[i].Evaluate(p, order);
  jet.value *= weights_[i];
  jet.gradient *= weights_[i];
  jet.hessian *= weights_[i];
  return jet;
}

void DcbBasis::Candidates(const Eigen::Vector3d& p,
                          std::vector<int>* out) const {
  out->clear();
  ForEachCandidate(p, [&](int i) { out->push_back(i); });
}

void DcbBasis::NonzeroValues(const Eigen::Vector3d& p,
                             std::vector<BasisValue>* out) const {
  out->clear();
  ForEachCandidate(p, [&](int i) {
    const double v = Value(i, p);
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
  std::vector<BasisValue> values;
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
