#include "core/perturbed_predicates.h"

#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

#include "core/sphere_geometry.h"

namespace sdcb {
namespace {

using Exact = CGAL::Exact_rational;
using ExactMatrix = std::array<std::array<Exact, 4>, 4>;

Eigen::Vector3d Point(const Eigen::MatrixX3d& knots, int index) {
  if (index == kOriginIndex) return Eigen::Vector3d::Zero();
  return knots.row(index).transpose();
}

// Determinant by cofactor expansion along the first row (4 x 4 at most,
// evaluated only for exact degeneracies, so speed does not matter).
Exact Determinant(const std::vector<std::vector<Exact>>& m) {
  const int n = static_cast<int>(m.size());
  if (n == 1) return m[0][0];
  Exact sum = 0;
  for (int col = 0; col < n; ++col) {
    if (CGAL::is_zero(m[0][col])) continue;
    std::vector<std::vector<Exact>> minor;
    for (int r = 1; r < n; ++r) {
      std::vector<Exact> row;
      for (int c = 0; c < n; ++c) {
        if (c != col) row.push_back(m[r][c]);
      }
      minor.push_back(std::move(row));
    }
    const Exact term = m[0][col] * Determinant(minor);
    if (col % 2 == 0) {
      sum += term;
    } else {
      sum -= term;
    }
  }
  return sum;
}

// One term of det(M + E) as a polynomial in eps: the perturbed entries
// (row, column) taken from E, and their keys sorted in decreasing order.
struct Term {
  std::vector<std::pair<int, int>> entries;
  std::vector<int> keys_descending;
};

// Exponent of a term is sum 2^key: comparing the decreasing key lists
// lexicographically (a proper prefix being smaller) orders the exponents.
bool LowerOrder(const Term& a, const Term& b) {
  return std::lexicographical_compare(
      a.keys_descending.begin(), a.keys_descending.end(),
      b.keys_descending.begin(), b.keys_descending.end());
}

}  // namespace

namespace internal {

int SymbolicOrient3dSign(const Eigen::MatrixX3d& knots,
                         const std::array<int, 4>& rows) {
  // M has rows (x, y, z, 1); orient3d = -det(M) (subtract row 0 from the
  // others and expand along the last column).
  std::vector<std::vector<Exact>> m(4, std::vector<Exact>(4));
  for (int r = 0; r < 4; ++r) {
    const Eigen::Vector3d p = Point(knots, rows[r]);
    for (int c = 0; c < 3; ++c) m[r][c] = p[c];
    m[r][3] = 1;
  }
  // All partial matchings of perturbed entries (distinct rows and columns).
  std::vector<Term> terms;
  Term current;
  std::array<bool, 3> column_used = {false, false, false};
  std::function<void(int)> enumerate = [&](int r) {
    if (r == 4) {
      terms.push_back(current);
      return;
    }
    enumerate(r + 1);                     // row r takes its entry from M
    if (rows[r] == kOriginIndex) return;  // the origin is not perturbed
    for (int c = 0; c < 3; ++c) {
      if (column_used[c]) continue;
      column_used[c] = true;
      current.entries.emplace_back(r, c);
      enumerate(r + 1);
      current.entries.pop_back();
      column_used[c] = false;
    }
  };
  enumerate(0);
  for (Term& t : terms) {
    for (const auto& [r, c] : t.entries) {
      t.keys_descending.push_back(3 * rows[r] + c);
    }
    std::sort(t.keys_descending.rbegin(), t.keys_descending.rend());
  }
  std::sort(terms.begin(), terms.end(), LowerOrder);
  // The coefficient of a term is det(M) with each of its rows replaced by
  // the unit row of its column: that forces the permutation through it.
  for (const Term& t : terms) {
    std::vector<std::vector<Exact>> mt = m;
    for (const auto& [r, c] : t.entries) {
      for (int cc = 0; cc < 4; ++cc) mt[r][cc] = (cc == c) ? 1 : 0;
    }
    const CGAL::Sign sign = CGAL::sign(Determinant(mt));
    if (sign != CGAL::ZERO) return sign == CGAL::POSITIVE ? -1 : 1;
  }
  return 0;  // unreachable for valid input: the top term is +-1
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

PerturbedCap::PerturbedCap(const Eigen::MatrixX3d& knots, int a, int b, int c)
    : knots_(knots),
      corners_{a, b, c},
      origin_side_(PerturbedOrient3dSign(knots, a, b, c, kOriginIndex)) {}

bool PerturbedCap::Contains(int q) const {
  // Inside the smaller cap: on the other side of the plane than the origin.
  return PerturbedOrient3dSign(knots_, corners_[0], corners_[1], corners_[2],
                               q) != origin_side_;
}

}  // namespace sdcb
