#include "sdcb/core/sphere/perturbed_predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/LU>
#include <algorithm>
#include <utility>
#include <vector>

#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Eigen::Vector3d Point(const Eigen::MatrixX3d& knots, int index) {
  if (index == kOriginIndex) return Eigen::Vector3d::Zero();
  return knots.row(index).transpose();
}

// One term of det(M + E) as a polynomial in eps, where M (4 x 4) has rows
// (x, y, z, 1) of the four points sorted by index and E holds the
// perturbations of columns 0..2. The term takes `size` entries
// (rows[i], cols[i]) from E; its coefficient is sign_factor times the minor
// of M without those rows and columns.
struct Term {
  int size = 0;
  std::array<int, 3> rows{};
  std::array<int, 3> cols{};
  int sign_factor = 1;
  std::vector<int> keys_descending;  // 3 * row + column, for the ordering
  std::vector<int> free_rows;        // rows of M not in the term, ascending
  std::vector<int> free_cols;        // columns 0..2 not in the term, ascending
};

// Fills the term's free rows and perturbed columns.
void SetFreeRowsAndColumns(Term* t) {
  const auto taken = [](const std::array<int, 3>& used, int size, int x) {
    return std::find(used.begin(), used.begin() + size, x) !=
           used.begin() + size;
  };
  for (int r = 0; r < 4; ++r) {
    if (!taken(t->rows, t->size, r)) t->free_rows.push_back(r);
  }
  for (int c = 0; c < 3; ++c) {
    if (!taken(t->cols, t->size, c)) t->free_cols.push_back(c);
  }
}

// Determinant of M with each of the term's rows replaced by the unit row of
// its column: the coefficient of the term (it forces the permutation).
double Coefficient(Eigen::Matrix4d m, const Term& t) {
  for (int i = 0; i < t.size; ++i) {
    m.row(t.rows[i]).setZero();
    m(t.rows[i], t.cols[i]) = 1;
  }
  return m.determinant();
}

double Minor(const Eigen::Matrix4d& m, const Term& t) {
  std::vector<int> cols = t.free_cols;
  cols.push_back(3);  // the column of ones is never perturbed
  Eigen::MatrixXd sub(t.free_rows.size(), cols.size());
  for (size_t i = 0; i < t.free_rows.size(); ++i) {
    for (size_t j = 0; j < cols.size(); ++j)
      sub(i, j) = m(t.free_rows[i], cols[j]);
  }
  return sub.determinant();
}

// All non-empty terms in increasing order of their eps exponent, which is
// sum 2^key over their entries (key 3 * row + column: row order = knot
// index order, so this matches the keys 3 * index + column of the header).
// Comparing decreasing key lists lexicographically (a proper prefix being
// smaller) orders these sums. Row 0 is not perturbed if it is the origin.
std::vector<Term> BuildTermOrder(bool origin_first) {
  std::vector<Term> terms;
  Term current;
  std::array<bool, 3> used = {false, false, false};
  auto enumerate = [&](auto&& self, int r) -> void {
    if (r == 4) {
      if (current.size > 0) terms.push_back(current);
      return;
    }
    self(self, r + 1);
    if (r == 0 && origin_first) return;
    for (int c = 0; c < 3; ++c) {
      if (used[c]) continue;
      used[c] = true;
      current.rows[current.size] = r;
      current.cols[current.size] = c;
      ++current.size;
      self(self, r + 1);
      --current.size;
      used[c] = false;
    }
  };
  enumerate(enumerate, 0);
  // Any matrix with non-zero minors fixes the sign relating coefficient
  // and minor (it depends only on the positions).
  Eigen::Matrix4d generic;
  generic << 0.31, -0.72, 0.55, 1, 0.93, 0.18, -0.41, 1, -0.27, 0.64, 0.86, 1,
      0.49, -0.83, -0.15, 1;
  for (Term& t : terms) {
    SetFreeRowsAndColumns(&t);
    for (int i = 0; i < t.size; ++i)
      t.keys_descending.push_back(3 * t.rows[i] + t.cols[i]);
    std::sort(t.keys_descending.rbegin(), t.keys_descending.rend());
    t.sign_factor = Coefficient(generic, t) * Minor(generic, t) > 0 ? 1 : -1;
  }
  std::sort(terms.begin(), terms.end(), [](const Term& a, const Term& b) {
    return std::lexicographical_compare(
        a.keys_descending.begin(), a.keys_descending.end(),
        b.keys_descending.begin(), b.keys_descending.end());
  });
  return terms;
}

const std::vector<Term>& TermOrder(bool origin_first) {
  static const std::vector<Term> with_origin = BuildTermOrder(true);
  static const std::vector<Term> without_origin = BuildTermOrder(false);
  return origin_first ? with_origin : without_origin;
}

// Exact sign of the minor of M (rows p[r] = (x, y, z, 1)) without the
// term's rows and columns. Column 3 always remains, so the minor is an
// orient2d of three projected points, a difference of two coordinates, or 1.
int MinorSign(const std::array<Eigen::Vector3d, 4>& p, const Term& t) {
  const std::vector<int>& rows = t.free_rows;
  const std::vector<int>& cols = t.free_cols;
  if (t.size == 3) return 1;
  if (t.size == 2) {  // det[[a_c, 1], [b_c, 1]] = a_c - b_c
    const double a = p[rows[0]][cols[0]], b = p[rows[1]][cols[0]];
    return a > b ? 1 : (a < b ? -1 : 0);
  }
  // det[[a_u, a_v, 1], [b_u, b_v, 1], [c_u, c_v, 1]] = orient2d(a, b, c).
  auto project = [&](int r) {
    return Kernel::Point_2(p[rows[r]][cols[0]], p[rows[r]][cols[1]]);
  };
  const CGAL::Orientation o =
      CGAL::orientation(project(0), project(1), project(2));
  return o == CGAL::POSITIVE ? 1 : (o == CGAL::NEGATIVE ? -1 : 0);
}

}  // namespace

namespace internal {

int SymbolicOrient3dSign(const Eigen::MatrixX3d& knots,
                         const std::array<int, 4>& rows) {
  // Sort the rows by index (the origin, -1, first), tracking the parity.
  std::array<int, 4> sorted = rows;
  int parity = 1;
  for (int i = 1; i < 4; ++i) {
    for (int j = i; j > 0 && sorted[j - 1] > sorted[j]; --j) {
      std::swap(sorted[j - 1], sorted[j]);
      parity = -parity;
    }
  }
  std::array<Eigen::Vector3d, 4> p;
  for (int r = 0; r < 4; ++r) p[r] = Point(knots, sorted[r]);
  for (const Term& t : TermOrder(sorted[0] == kOriginIndex)) {
    const int s = MinorSign(p, t);
    // orient3d = -det(M) (subtract row 0, expand along the last column).
    if (s != 0) return -parity * t.sign_factor * s;
  }
  return 0;  // unreachable: the terms with three entries have minor 1
}

}  // namespace internal

int PerturbedOrient3dSign(const Eigen::MatrixX3d& knots, int i, int j, int k,
                          int l) {
  const int exact = Orient3dSign(Point(knots, i), Point(knots, j),
                                 Point(knots, k), Point(knots, l));
  if (exact != 0) return exact;
  return internal::SymbolicOrient3dSign(knots, {i, j, k, l});
}

int PerturbedCapSide(const Eigen::MatrixX3d& knots, int a, int b, int c,
                     int q) {
  return PerturbedCap(knots, a, b, c).Contains(q) ? 1 : -1;
}

PerturbedPlane::PerturbedPlane(const Eigen::MatrixX3d& knots, int a, int b,
                               int c)
    : knots_(knots),
      corners_{a, b, c},
      points_{knots.row(a).transpose(), knots.row(b).transpose(),
              knots.row(c).transpose()} {}

int PerturbedPlane::Side(int q) const {
  const int side = Orient3dSign(points_[0], points_[1], points_[2],
                                knots_.row(q).transpose());
  if (side != 0) return side;
  return internal::SymbolicOrient3dSign(
      knots_, {corners_[0], corners_[1], corners_[2], q});
}

int PerturbedPlane::OriginSide() const {
  return PerturbedOrient3dSign(knots_, corners_[0], corners_[1], corners_[2],
                               kOriginIndex);
}

// Inside the smaller cap: on the other side of the plane than the origin.
PerturbedCap::PerturbedCap(const Eigen::MatrixX3d& knots, int a, int b, int c)
    : plane_(knots, a, b, c), origin_side_(plane_.OriginSide()) {}

}  // namespace sdcb
