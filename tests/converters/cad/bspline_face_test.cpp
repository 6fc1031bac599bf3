// Tests of converters/cad/bspline_face: the basis against the Cox-de Boor
// recursion written out by its definition (knot vector, 0/0 = 0), its
// derivatives against differences of that, partition of unity and linear
// precision (Greville abscissae), and the Bezier spans of Boehm's insertion
// against the face evaluated by the basis.
#include "sdcb/converters/cad/bspline_face.h"

#include <gtest/gtest.h>

#include <random>

namespace sdcb {
namespace {

// N_{i,p}(x) on the clamped knot vector of `breaks`, by the recursion of
// the definition (the last span closed at its right end).
double CoxDeBoor(const std::vector<double>& t, int i, int p, double x) {
  if (p == 0) {
    const bool last = t[i + 1] == t.back() && t[i] < t[i + 1];
    return (t[i] <= x && (x < t[i + 1] || (last && x == t[i + 1]))) ? 1.0 : 0.0;
  }
  double value = 0.0;
  if (t[i + p] > t[i]) {
    value += (x - t[i]) / (t[i + p] - t[i]) * CoxDeBoor(t, i, p - 1, x);
  }
  if (t[i + p + 1] > t[i + 1]) {
    value += (t[i + p + 1] - x) / (t[i + p + 1] - t[i + 1]) *
             CoxDeBoor(t, i + 1, p - 1, x);
  }
  return value;
}

std::vector<double> Clamped(const KnotBreaks& b) {
  std::vector<double> t(4, b.front());
  t.insert(t.end(), b.begin() + 1, b.end() - 1);
  t.insert(t.end(), 4, b.back());
  return t;
}

KnotBreaks RandomBreaks(int spans, std::mt19937* rng) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  KnotBreaks b = {-1.0, 1.0};
  while (static_cast<int>(b.size()) < spans + 1) b.push_back(d(*rng));
  std::sort(b.begin(), b.end());
  return b;
}

TEST(BSplineFaceTest, BasisMatchesTheRecursionOfTheDefinition) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (int spans : {1, 2, 5, 9}) {
    const KnotBreaks b = RandomBreaks(spans, &rng);
    const std::vector<double> t = Clamped(b);
    for (int k = 0; k < 200; ++k) {
      const double x = k == 0 ? -1.0 : (k == 1 ? 1.0 : d(rng));
      const int s = KnotSpan(b, x);
      ASSERT_LE(b[s], x);
      ASSERT_LE(x, b[s + 1]);
      double n[4], dn[4];
      CubicBSplineBasis(b, s, x, n, dn);
      double sum = 0.0;
      for (int i = 0; i < spans + 3; ++i) {
        const double expected = CoxDeBoor(t, i, 3, x);
        const double got = (i >= s && i <= s + 3) ? n[i - s] : 0.0;
        EXPECT_NEAR(got, expected, 1e-12) << "pole " << i << " x " << x;
        sum += got;
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      // Derivatives against central differences inside the span.
      const double h = 1e-6;
      if (x - h > b[s] && x + h < b[s + 1]) {
        for (int r = 0; r < 4; ++r) {
          const double fd =
              (CoxDeBoor(t, s + r, 3, x + h) - CoxDeBoor(t, s + r, 3, x - h)) /
              (2 * h);
          EXPECT_NEAR(dn[r], fd, 1e-5 * (1.0 + std::abs(fd)));
        }
      }
    }
  }
}

TEST(BSplineFaceTest, GrevilleAbscissaeReproduceLinearFunctions) {
  std::mt19937 rng(11);
  BSplineFace face;
  face.u_breaks = RandomBreaks(6, &rng);
  face.v_breaks = RandomBreaks(3, &rng);
  const int nu = face.num_u(), nv = face.num_v();
  EXPECT_EQ(GrevilleAbscissa(face.u_breaks, 0), -1.0);
  EXPECT_EQ(GrevilleAbscissa(face.u_breaks, nu - 1), 1.0);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double u = GrevilleAbscissa(face.u_breaks, i);
      const double v = GrevilleAbscissa(face.v_breaks, j);
      face.poles.push_back(Eigen::Vector3d(2 * u + 1, 3 * v - u, 0.5));
    }
  }
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (int k = 0; k < 100; ++k) {
    const double u = d(rng), v = d(rng);
    Eigen::Vector3d du, dv;
    const Eigen::Vector3d p = face.Evaluate(u, v, &du, &dv);
    EXPECT_TRUE(p.isApprox(Eigen::Vector3d(2 * u + 1, 3 * v - u, 0.5), 1e-12));
    EXPECT_TRUE(du.isApprox(Eigen::Vector3d(2, -1, 0), 1e-10));
    EXPECT_NEAR((dv - Eigen::Vector3d(0, 3, 0)).norm(), 0.0, 1e-10);
  }
}

TEST(BSplineFaceTest, BezierSpansAreTheFace) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  BSplineFace face;
  face.u_breaks = RandomBreaks(4, &rng);
  face.v_breaks = RandomBreaks(3, &rng);
  for (int k = 0; k < face.num_u() * face.num_v(); ++k) {
    face.poles.push_back(Eigen::Vector3d(d(rng), d(rng), d(rng)));
  }
  const std::vector<BicubicPatch> patches = face.BezierPatches();
  ASSERT_EQ(patches.size(), 4u * 3u);
  for (int cv = 0; cv < 3; ++cv) {
    for (int cu = 0; cu < 4; ++cu) {
      const BicubicPatch& patch = patches[cv * 4 + cu];
      for (int k = 0; k < 20; ++k) {
        const double s = (d(rng) + 1) / 2, t = (d(rng) + 1) / 2;
        const double u =
            face.u_breaks[cu] + s * (face.u_breaks[cu + 1] - face.u_breaks[cu]);
        const double v =
            face.v_breaks[cv] + t * (face.v_breaks[cv + 1] - face.v_breaks[cv]);
        EXPECT_LT((patch.Evaluate(s, t) - face.Evaluate(u, v)).norm(), 1e-12);
      }
    }
  }
}

}  // namespace
}  // namespace sdcb
