#include "sdcb/core/spline/piecewise_surface.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <mutex>
#include <set>
#include <shared_mutex>
#include <unordered_map>

#include "sdcb/core/spline/simplex_spline.h"

namespace sdcb {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxLines = 64;    // bits of a region key
constexpr int kSplitLines = 24;  // cells with more lines are split
constexpr int kMaxDepth = 8;

// Cube face f: axis a = sign * e_k (f = 2k + (sign < 0)) and e1, e2 with
// e1 x e2 = a, so the chart (u, v) -> a + u e1 + v e2 is positively oriented.
void FaceFrame(int f, Eigen::Vector3d* a, Eigen::Vector3d* e1,
               Eigen::Vector3d* e2) {
  const int k = f / 2;
  const double sign = f % 2 == 0 ? 1.0 : -1.0;
  *a = sign * Eigen::Vector3d::Unit(k);
  *e1 = Eigen::Vector3d::Unit((k + (sign > 0 ? 1 : 2)) % 3);
  *e2 = Eigen::Vector3d::Unit((k + (sign > 0 ? 2 : 1)) % 3);
}

double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

struct PiecewiseSurface::Cell {
  int index = 0;
  // Quadtree: a cell with more than kMaxLines lines is split into four
  // children (quadrants of (u, v) around (uc, vc)); leaves hold the regions.
  std::unique_ptr<Cell> children[4];
  double uc = 0.0, vc = 0.0, h = 1.0;    // centre and half side in (u, v)
  Eigen::Vector3d origin, e1, e2;        // local chart o + s e1 + t e2
  std::vector<int> lines;                // indices into segments_
  std::vector<Eigen::Vector3d> normals;  // t_a x t_b of each line
  std::vector<double> bounds;            // sign filter: kSignFilter |a|_1 |b|_1
  std::vector<int> sets;                 // basis functions meeting the cell
  bool slow = false;                     // too many lines: use the spline
  mutable std::shared_mutex mutex;
  // Region key -> its coefficients (a deque keeps them in place).
  mutable std::unordered_map<uint64_t, const double*> regions;
  mutable std::deque<std::array<double, 4 * PolynomialSize(5)>> coefficients;
};

PiecewiseSurface::PiecewiseSurface(const SphericalSpline& spline, int grid)
    : spline_(spline) {
  const DcbBasis& basis = spline.basis();
  const Eigen::MatrixX3d& knots = spline.knots();
  size_ = PolynomialSize(spline.degree());
  std::set<std::array<int, 2>> pairs;
  for (int i = 0; i < basis.size(); ++i) {
    const auto& k = basis.configuration_set(i).knots;
    for (size_t a = 0; a < k.size(); ++a)
      for (size_t b = a + 1; b < k.size(); ++b) pairs.insert({k[a], k[b]});
  }
  segments_.assign(pairs.begin(), pairs.end());
  const int ns = static_cast<int>(segments_.size());
  std::vector<Eigen::Vector3d> mid(ns), normal(ns);
  std::vector<double> half(ns);
  double length = 0.0;
  for (int s = 0; s < ns; ++s) {
    const Eigen::Vector3d a = knots.row(segments_[s][0]).transpose();
    const Eigen::Vector3d b = knots.row(segments_[s][1]).transpose();
    mid[s] = (a + b).normalized();
    half[s] = 0.5 * Angle(a, b);
    normal[s] = a.cross(b);
    length += 2.0 * half[s];
  }
  // Expected crossings of a cell of side ~(pi / 2) / G: L (pi / 2) / (G pi^2).
  grid_ =
      grid > 0
          ? grid
          : std::clamp(static_cast<int>(std::ceil(length / (2.0 * kPi * 10.0))),
                       2, 96);
  const int g = grid_;
  std::vector<double> set_radius(basis.size());
  for (int i = 0; i < basis.size(); ++i) {
    const double c = basis.support_cap(i).cos_radius;
    set_radius[i] = c <= -1.0 ? kPi : std::acos(std::min(1.0, c));
  }
  cells_.resize(6 * g * g);
  // Builds the cell of face f centred at (uc, vc) with half side h from the
  // candidate segments and basis functions of its parent.
  std::function<std::unique_ptr<Cell>(int, double, double, double,
                                      const std::vector<int>&,
                                      const std::vector<int>&, int)>
      build = [&](int f, double uc, double vc, double h,
                  const std::vector<int>& segments,
                  const std::vector<int>& sets, int depth) {
        auto cell = std::make_unique<Cell>();
        Eigen::Vector3d a, e1, e2;
        FaceFrame(f, &a, &e1, &e2);
        cell->uc = uc;
        cell->vc = vc;
        cell->h = h;
        cell->origin = a + uc * e1 + vc * e2;
        cell->e1 = h * e1;
        cell->e2 = h * e2;
        const Eigen::Vector3d center = cell->origin.normalized();
        Eigen::Vector3d corner[4];
        double radius = 0.0;
        for (int c = 0; c < 4; ++c) {
          corner[c] = a + (uc + h * ((c & 1) ? 1 : -1)) * e1 +
                      (vc + h * ((c >> 1) ? 1 : -1)) * e2;
          radius = std::max(radius, Angle(center, corner[c]));
        }
        radius += 1e-9;
        for (int s : segments) {
          if (Angle(center, mid[s]) > radius + half[s] + 1e-9) continue;
          // The great circle misses the (gnomonically convex) cell if all
          // four corners lie strictly on one side.
          int pos = 0, neg = 0;
          for (const Eigen::Vector3d& x : corner) {
            const double d = x.dot(normal[s]);
            const double margin = 1e-12 * x.norm() * normal[s].norm();
            pos += d > margin;
            neg += d < -margin;
          }
          if (pos == 4 || neg == 4) continue;
          cell->lines.push_back(s);
        }
        for (int b : sets) {
          if (Angle(center, basis.support_cap(b).axis) <=
              radius + set_radius[b] + 1e-9) {
            cell->sets.push_back(b);
          }
        }
        if (cell->lines.size() > kSplitLines && depth < kMaxDepth) {
          for (int q = 0; q < 4; ++q) {
            cell->children[q] =
                build(f, uc + 0.5 * h * ((q & 1) ? 1 : -1),
                      vc + 0.5 * h * ((q >> 1) ? 1 : -1), 0.5 * h, cell->lines,
                      cell->sets, depth + 1);
          }
          cell->lines.clear();
          cell->sets.clear();
          return cell;
        }
        cell->slow = cell->lines.size() > kMaxLines;
        for (int s : cell->lines) {
          const Eigen::Vector3d ka = knots.row(segments_[s][0]).transpose();
          const Eigen::Vector3d kb = knots.row(segments_[s][1]).transpose();
          cell->normals.push_back(ka.cross(kb));
          // Twice PerturbedDetSign's filter: beyond it the float sign is the
          // exact one; within it PerturbedDetSign decides.
          cell->bounds.push_back(2e-13 * ka.cwiseAbs().sum() *
                                 kb.cwiseAbs().sum());
        }
        return cell;
      };
  std::vector<int> all_segments(ns), all_sets(basis.size());
  for (int s = 0; s < ns; ++s) all_segments[s] = s;
  for (int b = 0; b < basis.size(); ++b) all_sets[b] = b;
  tbb::parallel_for(0, 6 * g * g, [&](int index) {
    const int f = index / (g * g), i = (index / g) % g, j = index % g;
    const double h = 1.0 / g;
    cells_[index] = build(f, -1.0 + h * (2 * i + 1), -1.0 + h * (2 * j + 1), h,
                          all_segments, all_sets, 0);
  });
  // Number the leaves (the order EvaluateMany sorts by).
  int next = 0;
  std::function<void(Cell*)> number = [&](Cell* cell) {
    if (cell->children[0]) {
      for (auto& child : cell->children) number(child.get());
    } else {
      cell->index = next++;
    }
  };
  for (auto& root : cells_) number(root.get());
}

PiecewiseSurface::~PiecewiseSurface() = default;

int64_t PiecewiseSurface::num_regions() const {
  int64_t n = 0;
  std::function<void(const Cell&)> count = [&](const Cell& cell) {
    if (cell.children[0]) {
      for (const auto& child : cell.children) count(*child);
      return;
    }
    std::shared_lock<std::shared_mutex> lock(cell.mutex);
    n += static_cast<int64_t>(cell.regions.size());
  };
  for (const auto& c : cells_) count(*c);
  return n;
}

const PiecewiseSurface::Cell& PiecewiseSurface::Locate(const Eigen::Vector3d& p,
                                                       double* s,
                                                       double* t) const {
  int k = 0;
  p.cwiseAbs().maxCoeff(&k);
  const int f = 2 * k + (p[k] < 0 ? 1 : 0);
  Eigen::Vector3d a, e1, e2;
  FaceFrame(f, &a, &e1, &e2);
  const double w = p.dot(a);
  const double u = p.dot(e1) / w, v = p.dot(e2) / w;
  const int g = grid_;
  const int i =
      std::clamp(static_cast<int>(std::floor((u + 1.0) * 0.5 * g)), 0, g - 1);
  const int j =
      std::clamp(static_cast<int>(std::floor((v + 1.0) * 0.5 * g)), 0, g - 1);
  const Cell* cell = cells_[(f * g + i) * g + j].get();
  while (cell->children[0]) {
    cell =
        cell->children[(u >= cell->uc ? 1 : 0) + (v >= cell->vc ? 2 : 0)].get();
  }
  *s = (u - cell->uc) / cell->h;
  *t = (v - cell->vc) / cell->h;
  return *cell;
}

const double* PiecewiseSurface::Region(const Cell& cell,
                                       const Eigen::Vector3d& p) const {
  const Eigen::MatrixX3d& knots = spline_.knots();
  uint64_t key = 0;
  const double p1 = p.cwiseAbs().sum();
  for (size_t l = 0; l < cell.lines.size(); ++l) {
    const double v = p.dot(cell.normals[l]);
    bool positive;
    if (std::abs(v) > cell.bounds[l] * p1) {
      positive = v > 0;
    } else {
      const auto& seg = segments_[cell.lines[l]];
      positive = PerturbedDetSign(p, knots.row(seg[0]).transpose(),
                                  knots.row(seg[1]).transpose()) > 0;
    }
    if (positive) key |= uint64_t{1} << l;
  }
  {
    std::shared_lock<std::shared_mutex> lock(cell.mutex);
    auto it = cell.regions.find(key);
    if (it != cell.regions.end()) return it->second;
  }
  // N = sum B_i c_i and I = sum B_i on p's region (the polynomial of a
  // piece does not depend on which point of the region built it).
  std::vector<double> poly(4 * size_, 0.0), piece(size_);
  const DcbBasis& basis = spline_.basis();
  for (int b : cell.sets) {
    std::fill(piece.begin(), piece.end(), 0.0);
    if (!basis.AddPiecePolynomial(b, p, cell.origin, cell.e1, cell.e2,
                                  piece.data())) {
      continue;
    }
    const Eigen::RowVector3d c = spline_.control_points().row(b);
    for (int m = 0; m < size_; ++m) {
      for (int d = 0; d < 3; ++d) poly[d * size_ + m] += c[d] * piece[m];
      poly[3 * size_ + m] += piece[m];
    }
  }
  std::unique_lock<std::shared_mutex> lock(cell.mutex);
  auto it = cell.regions.find(key);
  if (it == cell.regions.end()) {
    cell.coefficients.emplace_back();
    std::copy(poly.begin(), poly.end(), cell.coefficients.back().begin());
    it = cell.regions.emplace(key, cell.coefficients.back().data()).first;
  }
  return it->second;
}

void PiecewiseSurface::Eval(const Eigen::Vector3d& p, Eigen::Vector3d* position,
                            Eigen::Vector3d* normal) const {
  double s, t;
  const Cell& cell = Locate(p, &s, &t);
  if (cell.slow) {
    // The same position with or without the normal.
    *position = spline_.Evaluate(p.normalized());
    if (normal != nullptr) {
      *normal =
          spline_.EvaluateDifferential(p.normalized(), JetOrder::kGradient)
              .normal;
    }
    return;
  }
  const double* coefficients = Region(cell, p);
  const int k = spline_.degree();
  double mono[36], ds[36], dt[36];
  double sp[8], tp[8];
  sp[0] = tp[0] = 1.0;
  for (int e = 1; e <= k; ++e) {
    sp[e] = sp[e - 1] * s;
    tp[e] = tp[e - 1] * t;
  }
  for (int n = 0; n <= k; ++n)
    for (int j = 0; j <= n; ++j) {
      const int i = n - j, m = MonomialIndex(i, j);
      mono[m] = sp[i] * tp[j];
      ds[m] = i > 0 ? i * sp[i - 1] * tp[j] : 0.0;
      dt[m] = j > 0 ? j * sp[i] * tp[j - 1] : 0.0;
    }
  double v[4] = {0, 0, 0, 0}, vs[4] = {0, 0, 0, 0}, vt[4] = {0, 0, 0, 0};
  for (int d = 0; d < 4; ++d) {
    const double* cd = coefficients + d * size_;
    for (int m = 0; m < size_; ++m) {
      v[d] += cd[m] * mono[m];
      if (normal) {
        vs[d] += cd[m] * ds[m];
        vt[d] += cd[m] * dt[m];
      }
    }
  }
  if (spline_.basis_form() == BasisForm::kRaw) {
    // F = N / |x|^k (the raw basis extended homogeneously of degree 0) at
    // the point x of the cell's plane, with its derivatives in s and t.
    const Eigen::Vector3d x = cell.origin + s * cell.e1 + t * cell.e2;
    const double r2 = x.squaredNorm();
    const double rk = std::pow(r2, 0.5 * k);
    v[3] = rk;
    vs[3] = k * rk / r2 * x.dot(cell.e1);
    vt[3] = k * rk / r2 * x.dot(cell.e2);
  }
  const double inv = 1.0 / v[3];
  *position = Eigen::Vector3d(v[0], v[1], v[2]) * inv;
  if (normal == nullptr) return;
  Eigen::Vector3d fs, ft;
  for (int d = 0; d < 3; ++d) {
    fs[d] = (vs[d] - (*position)[d] * vs[3]) * inv;
    ft[d] = (vt[d] - (*position)[d] * vt[3]) * inv;
  }
  const Eigen::Vector3d cross = fs.cross(ft);
  const double len = cross.norm();
  *normal = len > 0 ? Eigen::Vector3d(cross / len) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d PiecewiseSurface::Evaluate(const Eigen::Vector3d& p) const {
  Eigen::Vector3d position;
  Eval(p, &position, nullptr);
  return position;
}

void PiecewiseSurface::EvaluateWithNormal(const Eigen::Vector3d& p,
                                          Eigen::Vector3d* position,
                                          Eigen::Vector3d* normal) const {
  Eval(p, position, normal);
}

void PiecewiseSurface::EvaluateMany(const Eigen::MatrixX3d& directions,
                                    Eigen::MatrixX3d* positions,
                                    Eigen::MatrixX3d* normals) const {
  positions->resize(directions.rows(), 3);
  if (normals) normals->resize(directions.rows(), 3);
  // Cell by cell (stable), so that a cell's regions stay in cache.
  std::vector<std::pair<int, Eigen::Index>> order(directions.rows());
  for (Eigen::Index r = 0; r < directions.rows(); ++r) {
    double s, t;
    const Cell& cell = Locate(directions.row(r).transpose(), &s, &t);
    order[r] = {cell.index, r};
  }
  std::sort(order.begin(), order.end());
  tbb::parallel_for(Eigen::Index{0}, directions.rows(), [&](Eigen::Index o) {
    const Eigen::Index r = order[o].second;
    Eigen::Vector3d x, n;
    Eval(directions.row(r).transpose(), &x, normals ? &n : nullptr);
    positions->row(r) = x.transpose();
    if (normals) normals->row(r) = n.transpose();
  });
}

}  // namespace sdcb
