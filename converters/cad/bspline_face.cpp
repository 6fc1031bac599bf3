#include "sdcb/converters/cad/bspline_face.h"

#include <algorithm>

namespace sdcb {
namespace {

// The clamped knot vector of `breaks`: -1 four times, the inner breaks,
// 1 four times.
std::vector<double> FullKnots(const KnotBreaks& breaks) {
  std::vector<double> t(4, breaks.front());
  t.insert(t.end(), breaks.begin() + 1, breaks.end() - 1);
  t.insert(t.end(), 4, breaks.back());
  return t;
}

// Inserts the knot x once into the clamped cubic knot vector t, whose poles
// are the rows of `poles` (Boehm).
void InsertKnot(double x, std::vector<double>* t, Eigen::MatrixXd* poles) {
  // The last i with t_i <= x.
  const int i =
      static_cast<int>(std::upper_bound(t->begin(), t->end(), x) - t->begin()) -
      1;
  const int n = static_cast<int>(poles->rows());
  Eigen::MatrixXd q(n + 1, poles->cols());
  for (int j = 0; j <= n; ++j) {
    if (j <= i - 3) {
      q.row(j) = poles->row(j);
    } else if (j <= i) {
      const double a = (x - (*t)[j]) / ((*t)[j + 3] - (*t)[j]);
      q.row(j) = (1.0 - a) * poles->row(j - 1) + a * poles->row(j);
    } else {
      q.row(j) = poles->row(j - 1);
    }
  }
  *poles = std::move(q);
  t->insert(t->begin() + i + 1, x);
}

// The Bezier poles (3 m + 1) of the cubic spline with `breaks` and `poles`
// (m + 3), by inserting every inner knot twice more.
std::vector<Eigen::Vector3d> BezierPoles(
    const KnotBreaks& breaks, const std::vector<Eigen::Vector3d>& poles) {
  std::vector<double> t = FullKnots(breaks);
  Eigen::MatrixXd p(static_cast<Eigen::Index>(poles.size()), 3);
  for (size_t k = 0; k < poles.size(); ++k) p.row(k) = poles[k].transpose();
  for (size_t k = 1; k + 1 < breaks.size(); ++k) {
    InsertKnot(breaks[k], &t, &p);
    InsertKnot(breaks[k], &t, &p);
  }
  std::vector<Eigen::Vector3d> out(p.rows());
  for (Eigen::Index k = 0; k < p.rows(); ++k) out[k] = p.row(k).transpose();
  return out;
}

}  // namespace

int KnotSpan(const KnotBreaks& breaks, double x) {
  const int m = static_cast<int>(breaks.size()) - 1;
  const int s =
      static_cast<int>(std::upper_bound(breaks.begin(), breaks.end(), x) -
                       breaks.begin()) -
      1;
  return std::clamp(s, 0, m - 1);
}

void CubicBSplineBasis(const KnotBreaks& breaks, int s, double x, double n[4],
                       double d[4]) {
  // Knot t_k of the clamped vector is breaks[clamp(k - 3)]; span s is
  // [t_{s+3}, t_{s+4}).
  const int m = static_cast<int>(breaks.size()) - 1;
  const auto t = [&](int k) { return breaks[std::clamp(k - 3, 0, m)]; };
  const int i = s + 3;
  double left[4], right[4], ndu[4][4];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= 3; ++j) {
    left[j] = x - t(i + 1 - j);
    right[j] = t(i + j) - x;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int r = 0; r < 4; ++r) n[r] = ndu[r][3];
  if (d != nullptr) {
    for (int r = 0; r < 4; ++r) {
      double value = 0.0;
      if (r >= 1) value += ndu[r - 1][2] / ndu[3][r - 1];
      if (r <= 2) value -= ndu[r][2] / ndu[3][r];
      d[r] = 3.0 * value;
    }
  }
}

Eigen::MatrixXd KnotInsertionMatrix(const KnotBreaks& coarse,
                                    const KnotBreaks& fine) {
  std::vector<double> t = FullKnots(coarse);
  Eigen::MatrixXd poles =
      Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(coarse.size()) + 2,
                                static_cast<Eigen::Index>(coarse.size()) + 2);
  for (size_t k = 1; k + 1 < fine.size(); ++k) {
    if (!std::binary_search(coarse.begin(), coarse.end(), fine[k])) {
      InsertKnot(fine[k], &t, &poles);
    }
  }
  return poles;
}

double GrevilleAbscissa(const KnotBreaks& breaks, int i) {
  const int m = static_cast<int>(breaks.size()) - 1;
  const auto t = [&](int k) { return breaks[std::clamp(k - 3, 0, m)]; };
  return (t(i + 1) + t(i + 2) + t(i + 3)) / 3.0;
}

Eigen::Vector3d BSplineFace::Evaluate(double u, double v, Eigen::Vector3d* du,
                                      Eigen::Vector3d* dv) const {
  const int su = KnotSpan(u_breaks, u), sv = KnotSpan(v_breaks, v);
  double nu[4], nv[4], dnu[4], dnv[4];
  CubicBSplineBasis(u_breaks, su, u, nu, dnu);
  CubicBSplineBasis(v_breaks, sv, v, nv, dnv);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d pu = Eigen::Vector3d::Zero(), pv = Eigen::Vector3d::Zero();
  const int stride = num_u();
  for (int b = 0; b < 4; ++b) {
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector3d& pole = poles[(sv + b) * stride + su + a];
      p += nu[a] * nv[b] * pole;
      pu += dnu[a] * nv[b] * pole;
      pv += nu[a] * dnv[b] * pole;
    }
  }
  if (du != nullptr) *du = pu;
  if (dv != nullptr) *dv = pv;
  return p;
}

std::vector<BicubicPatch> BSplineFace::BezierPatches() const {
  const int nu = num_u(), nv = num_v();
  const int mu = nu - 3, mv = nv - 3;
  const int bu = 3 * mu + 1, bv = 3 * mv + 1;
  // Rows along u first, then columns along v.
  std::vector<Eigen::Vector3d> rows(static_cast<size_t>(bu) * nv);
  for (int j = 0; j < nv; ++j) {
    const std::vector<Eigen::Vector3d> row = BezierPoles(
        u_breaks, std::vector<Eigen::Vector3d>(poles.begin() + j * nu,
                                               poles.begin() + (j + 1) * nu));
    std::copy(row.begin(), row.end(), rows.begin() + j * bu);
  }
  std::vector<Eigen::Vector3d> grid(static_cast<size_t>(bu) * bv);
  for (int i = 0; i < bu; ++i) {
    std::vector<Eigen::Vector3d> column(nv);
    for (int j = 0; j < nv; ++j) column[j] = rows[j * bu + i];
    column = BezierPoles(v_breaks, std::move(column));
    for (int j = 0; j < bv; ++j) grid[j * bu + i] = column[j];
  }
  std::vector<BicubicPatch> patches;
  patches.reserve(static_cast<size_t>(mu) * mv);
  for (int cv = 0; cv < mv; ++cv) {
    for (int cu = 0; cu < mu; ++cu) {
      BicubicPatch patch;
      for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
          patch.poles[4 * j + i] = grid[(3 * cv + j) * bu + 3 * cu + i];
        }
      }
      patches.push_back(patch);
    }
  }
  return patches;
}

}  // namespace sdcb
