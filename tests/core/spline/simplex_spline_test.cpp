#include "sdcb/core/spline/simplex_spline.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/sphere/spherical_barycentric.h"
#include "sdcb/core/spline/simplex_spline_forest.h"
#include "testing/random_sphere_points.h"

namespace sdcb {
namespace {

const Eigen::Vector3d kCenter = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();

// k + 3 random knots in a cap of radius 0.5 rad.
Eigen::MatrixX3d LocalKnots(int degree, unsigned seed) {
  return testing::RandomUnitVectorsInCap(degree + 3, kCenter, 0.5, seed);
}

SimplexSpline MakeSpline(const Eigen::MatrixX3d& knots, unsigned seed = 0) {
  SimplexSplineOptions options;
  options.split_seed = seed;
  StatusOr<SimplexSpline> s = SimplexSpline::Create(knots, options);
  EXPECT_TRUE(s.ok()) << s.status().message();
  return std::move(s).value();
}

TEST(SphericalBarycentric, MatchesDeterminantRatiosOfEq2) {
  const Eigen::MatrixX3d t = testing::RandomUnitVectors(4, 3);
  const Eigen::Vector3d t0 = t.row(0), t1 = t.row(1), t2 = t.row(2),
                        p = t.row(3);
  const double d = t0.dot(t1.cross(t2));
  const Eigen::Vector3d b = SphericalBarycentric(p, t0, t1, t2);
  EXPECT_NEAR(b[0], p.dot(t1.cross(t2)) / d, 1e-14);
  EXPECT_NEAR(b[1], t0.dot(p.cross(t2)) / d, 1e-14);
  EXPECT_NEAR(b[2], t0.dot(t1.cross(p)) / d, 1e-14);
  // Reproduces p: p = b0 t0 + b1 t1 + b2 t2.
  EXPECT_LT((b[0] * t0 + b[1] * t1 + b[2] * t2 - p).norm(), 1e-13);
}

TEST(SimplexSpline, DegreeZeroIsScaledHalfOpenIndicator) {
  const Eigen::MatrixX3d knots = LocalKnots(0, 11);
  const SimplexSpline s = MakeSpline(knots);
  const Eigen::Vector3d t0 = knots.row(0), t1 = knots.row(1), t2 = knots.row(2);
  const double inv_det = 1.0 / std::abs(t0.dot(t1.cross(t2)));
  const Eigen::Vector3d mid = (t0 + t1 + t2).normalized();
  const double reach =
      std::acos(std::min({mid.dot(t0), mid.dot(t1), mid.dot(t2)}));
  const Eigen::MatrixX3d points =
      testing::RandomUnitVectorsInCap(400, mid, 1.2 * reach, 12);
  int inside = 0;
  for (int r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r);
    const bool in = testing::InsideSphericalHull(p, knots);
    inside += in;
    EXPECT_EQ(s.Value(p), in ? inv_det : 0.0);
  }
  EXPECT_GT(inside, 20);
}

TEST(HalfOpenTriangle, FanAroundAKnotCountsEveryPointOnce) {
  // A knot c surrounded by 7 knots: the 7 fan triangles tile a region; its
  // points on shared edges and the knot c itself are counted exactly once.
  const Eigen::Vector3d c = kCenter;
  Eigen::Vector3d e_u = Eigen::Vector3d::UnitX().cross(c).normalized();
  Eigen::Vector3d e_v = c.cross(e_u);
  std::vector<Eigen::Vector3d> ring;
  for (int i = 0; i < 7; ++i) {
    const double a = 2 * kPi * i / 7 + 0.1 * std::sin(3.0 * i);
    ring.push_back(
        (c + 0.3 * (std::cos(a) * e_u + std::sin(a) * e_v)).normalized());
  }
  std::vector<Eigen::Vector3d> tests = {c};
  for (int i = 0; i < 7; ++i) {
    tests.push_back((c + ring[i]).normalized());  // On a spoke.
    tests.push_back((ring[i] + ring[(i + 1) % 7] + 2 * c).normalized());
  }
  for (const Eigen::Vector3d& p : tests) {
    int count = 0;
    for (int i = 0; i < 7; ++i) {
      count += InHalfOpenTriangle(p, c, ring[i], ring[(i + 1) % 7]);
    }
    EXPECT_EQ(count, 1);
  }
}

TEST(SimplexSpline, ValueDoesNotDependOnTheSplitTriple) {
  for (int degree = 1; degree <= 5; ++degree) {
    const Eigen::MatrixX3d knots = LocalKnots(degree, 20 + degree);
    const SimplexSpline reference = MakeSpline(knots, 0);
    const Eigen::MatrixX3d points =
        testing::RandomUnitVectorsInCap(200, kCenter, 0.5, 30 + degree);
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const SimplexSpline other = MakeSpline(knots, seed);
      double scale = 0.0, worst = 0.0;
      for (int r = 0; r < points.rows(); ++r) {
        const Eigen::Vector3d p = points.row(r);
        const double a = reference.Value(p), b = other.Value(p);
        scale = std::max(scale, std::abs(a));
        worst = std::max(worst, std::abs(a - b));
      }
      EXPECT_GT(scale, 0.0);
      EXPECT_LE(worst, 1e-12 * scale)
          << "degree " << degree << " seed " << seed;
    }
  }
}

TEST(SimplexSpline, NonNegativeAndSupportedOnTheConvexHull) {
  for (int degree = 1; degree <= 4; ++degree) {
    const Eigen::MatrixX3d knots = LocalKnots(degree, 40 + degree);
    const SimplexSpline s = MakeSpline(knots);
    const Eigen::MatrixX3d points =
        testing::RandomUnitVectorsInCap(300, kCenter, 0.7, 50 + degree);
    for (int r = 0; r < points.rows(); ++r) {
      const Eigen::Vector3d p = points.row(r);
      const double v = s.Value(p);
      EXPECT_GE(v, 0.0);
      if (!testing::InsideSphericalHull(p, knots)) {
        EXPECT_EQ(v, 0.0);
      }
    }
  }
}

TEST(SimplexSpline, HomogeneousOfDegreeK) {
  const Eigen::MatrixX3d knots = LocalKnots(3, 60);
  const SimplexSpline s = MakeSpline(knots);
  const Eigen::Vector3d p = kCenter;
  EXPECT_NEAR(s.Value(2.0 * p), 8.0 * s.Value(p), 1e-12 * s.Value(p) * 8);
}

// Smallest distance from p to a plane through two knots: keeps finite
// differences inside one polynomial piece.
double DistanceToKnotPlanes(const Eigen::Vector3d& p,
                            const Eigen::MatrixX3d& t) {
  double d = 1e9;
  for (int i = 0; i < t.rows(); ++i)
    for (int j = i + 1; j < t.rows(); ++j) {
      const Eigen::Vector3d n = Eigen::Vector3d(t.row(i))
                                    .cross(Eigen::Vector3d(t.row(j)))
                                    .normalized();
      d = std::min(d, std::abs(n.dot(p)));
    }
  return d;
}

TEST(SimplexSpline, GradientAndHessianMatchCentralDifferences) {
  // Central differences with one Richardson step (error O(h^4)).
  const double h = 1e-4;
  for (int degree = 1; degree <= 5; ++degree) {
    const Eigen::MatrixX3d knots = LocalKnots(degree, 70 + degree);
    const SimplexSpline s = MakeSpline(knots);
    auto value_fd = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& e) {
      auto c = [&](double k) {
        return (s.Value(p + k * e) - s.Value(p - k * e)) / (2 * k);
      };
      return (4 * c(h / 2) - c(h)) / 3;
    };
    auto gradient_fd = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& e) {
      auto c = [&](double k) -> Eigen::Vector3d {
        return (s.Evaluate(p + k * e, JetOrder::kGradient).gradient -
                s.Evaluate(p - k * e, JetOrder::kGradient).gradient) /
               (2 * k);
      };
      return Eigen::Vector3d((4 * c(h / 2) - c(h)) / 3);
    };
    const Eigen::MatrixX3d points =
        testing::RandomUnitVectorsInCap(60, kCenter, 0.4, 80 + degree);
    // Tolerances relative to the largest derivative over the samples (M
    // vanishes to order k at its support's edge).
    std::vector<Eigen::Vector3d> tested;
    double gradient_scale = 0.0, hessian_scale = 0.0;
    for (int r = 0; r < points.rows(); ++r) {
      const Eigen::Vector3d p = points.row(r);
      if (DistanceToKnotPlanes(p, knots) < 1e-3 || s.Value(p) == 0.0) continue;
      tested.push_back(p);
      const ScalarJet jet = s.Evaluate(p, JetOrder::kHessian);
      gradient_scale = std::max(gradient_scale, jet.gradient.norm());
      hessian_scale = std::max(hessian_scale, jet.hessian.norm());
    }
    for (const Eigen::Vector3d& p : tested) {
      const ScalarJet jet = s.Evaluate(p, JetOrder::kHessian);
      EXPECT_DOUBLE_EQ(jet.value, s.Value(p));
      for (int a = 0; a < 3; ++a) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(a);
        EXPECT_NEAR(jet.gradient[a], value_fd(p, e), 1e-8 * gradient_scale);
        EXPECT_LE((jet.hessian.col(a) - gradient_fd(p, e)).norm(),
                  1e-8 * (hessian_scale + gradient_scale));
      }
    }
    EXPECT_GT(tested.size(), 10u) << "degree " << degree;
  }
}

// Derivatives d^j/dt^j at t = 0 of the degree-k polynomial interpolating f
// at the nodes s (exact for a polynomial piece).
Eigen::VectorXd PolynomialDerivatives(const std::vector<double>& s,
                                      const std::vector<double>& f, int k) {
  Eigen::MatrixXd v(k + 1, k + 1);
  Eigen::VectorXd y(k + 1);
  for (int i = 0; i <= k; ++i) {
    for (int j = 0; j <= k; ++j) v(i, j) = std::pow(s[i], j);
    y[i] = f[i];
  }
  Eigen::VectorXd a = v.fullPivLu().solve(y);
  double factorial = 1.0;
  for (int j = 0; j <= k; ++j) {
    if (j > 0) factorial *= j;
    a[j] *= factorial;
  }
  return a;
}

// Along a straight line x(t) = x0 + t d in R^3 (its central projection is a
// great-circle arc) M is a piecewise polynomial of degree k in t, with
// breaks where the line crosses the planes through pairs of knots. At each
// crossing of a knot segment, the polynomials interpolated on both sides
// give the one-sided derivatives: orders < k agree, order k jumps.
TEST(SimplexSpline, CkMinus1AcrossKnotLinesAndKthDerivativeJumps) {
  for (int degree = 2; degree <= 5; ++degree) {
    const Eigen::MatrixX3d knots = LocalKnots(degree, 90 + degree);
    const SimplexSpline s = MakeSpline(knots);
    const int m = degree + 3;
    // One-sided derivatives at each knot-segment crossing, in units of the
    // sampling interval delta (derivative j times delta^j).
    std::vector<Eigen::VectorXd> left, right;
    double value_scale = 0.0;
    for (int line = 0; line < 8; ++line) {
      const Eigen::MatrixX3d dirs = testing::RandomUnitVectors(1, 100 + line);
      const Eigen::Vector3d x0 = kCenter;
      const Eigen::Vector3d r = dirs.row(0).transpose();
      const Eigen::Vector3d d = (r - r.dot(x0) * x0).normalized();
      struct Break {
        double t;
        bool on_segment;
      };
      std::vector<Break> breaks;
      for (int i = 0; i < m; ++i)
        for (int j = i + 1; j < m; ++j) {
          const Eigen::Vector3d ti = knots.row(i), tj = knots.row(j);
          const Eigen::Vector3d n = ti.cross(tj);
          const double t = -n.dot(x0) / n.dot(d);
          if (std::abs(t) > 1.0) continue;
          const Eigen::Vector3d q = x0 + t * d;
          const bool between = ti.cross(q).dot(n) > 0 && q.cross(tj).dot(n) > 0;
          breaks.push_back({t, between});
        }
      std::sort(breaks.begin(), breaks.end(),
                [](const Break& a, const Break& b) { return a.t < b.t; });
      for (size_t b = 1; b + 1 < breaks.size(); ++b) {
        if (!breaks[b].on_segment) continue;
        const double ts = breaks[b].t;
        const double delta =
            std::min(ts - breaks[b - 1].t, breaks[b + 1].t - ts);
        if (delta < 2e-3) continue;
        std::vector<double> nodes, fl, fr;
        for (int j = 0; j <= degree; ++j) {
          const double u = 0.1 + 0.8 * j / degree;
          nodes.push_back(u);
          fl.push_back(s.Value(x0 + (ts - u * delta) * d));
          fr.push_back(s.Value(x0 + (ts + u * delta) * d));
          value_scale = std::max({value_scale, fl.back(), fr.back()});
        }
        Eigen::VectorXd dl = PolynomialDerivatives(nodes, fl, degree);
        for (int j = 1; j <= degree; j += 2) dl[j] = -dl[j];  // s = -t.
        left.push_back(dl);
        right.push_back(PolynomialDerivatives(nodes, fr, degree));
      }
    }
    ASSERT_GT(value_scale, 0.0);
    int crossings = 0, jumps = 0;
    for (size_t c = 0; c < left.size(); ++c) {
      for (int j = 0; j < degree; ++j) {
        EXPECT_LE(std::abs(left[c][j] - right[c][j]), 1e-8 * value_scale)
            << "degree " << degree << " derivative " << j;
      }
      // Where M is not negligible next to the crossing, order k jumps.
      const double local = std::max(left[c].cwiseAbs().maxCoeff(),
                                    right[c].cwiseAbs().maxCoeff());
      if (local < 1e-3 * value_scale) continue;
      ++crossings;
      if (std::abs(left[c][degree] - right[c][degree]) > 1e-6 * local) ++jumps;
    }
    EXPECT_GE(crossings, 5) << "degree " << degree;
    // The jump is a lower-dimensional spline along the segment, small near
    // its ends: nearly every crossing shows it clearly.
    EXPECT_GE(jumps, 0.9 * crossings) << "degree " << degree;
  }
}

TEST(SimplexSpline, RejectsBadKnotSets) {
  EXPECT_FALSE(SimplexSpline::Create(Eigen::MatrixX3d(2, 3)).ok());
  EXPECT_FALSE(SimplexSpline::Create(testing::RandomUnitVectors(9, 1)).ok());
  EXPECT_EQ(SimplexSpline::Create(2.0 * testing::RandomUnitVectors(5, 1))
                .status()
                .code(),
            StatusCode::kInvalidArgument);
  Eigen::MatrixX3d great_circle(4, 3);
  for (int i = 0; i < 4; ++i)
    great_circle.row(i) << std::cos(i), std::sin(i), 0;
  const StatusOr<SimplexSpline> s = SimplexSpline::Create(great_circle);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), StatusCode::kInvalidInput);
}

// Random k + 3 of `knots`, ascending (the order the forest requires).
std::vector<int> RandomSubset(int num_knots, int size, unsigned seed) {
  std::vector<int> all(num_knots);
  for (int i = 0; i < num_knots; ++i) all[i] = i;
  for (int i = 0; i < size; ++i) {
    seed = seed * 1664525u + 1013904223u;
    std::swap(all[i], all[i + seed % (num_knots - i)]);
  }
  std::vector<int> subset(all.begin(), all.begin() + size);
  std::sort(subset.begin(), subset.end());
  return subset;
}

// The forest merges the recursions of splines that share knots; each
// spline's own recursion (SimplexSpline) is the oracle, bit for bit, with
// calls interleaved across splines, orders and points (the per-point memo).
TEST(SimplexSplineForest, MatchesEverySplineBitForBit) {
  for (int round = 0; round < 2; ++round) {
    // Two forests in turn, at the same points: the memo of the first must
    // not leak into the second.
    const Eigen::MatrixX3d knots =
        testing::RandomUnitVectorsInCap(11, kCenter, 0.6, 200 + round);
    SimplexSplineForest forest;
    std::vector<SimplexSpline> splines;
    for (int s = 0; s < 30; ++s) {
      const int size = s % 3 == 0 ? 6 : 7;
      const std::vector<int> subset = RandomSubset(11, size, 17 * s + round);
      Eigen::MatrixX3d local(size, 3);
      for (int j = 0; j < size; ++j) local.row(j) = knots.row(subset[j]);
      StatusOr<SimplexSpline> spline = SimplexSpline::Create(local);
      ASSERT_TRUE(spline.ok()) << spline.status().message();
      EXPECT_EQ(forest.Add(*spline, subset), s);
      splines.push_back(std::move(spline).value());
    }
    // Shared subsets are stored once.
    int separate = 0;
    for (const SimplexSpline& s : splines) separate += s.num_nodes();
    EXPECT_LT(forest.num_nodes(), separate);
    const Eigen::MatrixX3d points =
        testing::RandomUnitVectorsInCap(150, kCenter, 0.6, 300);
    int nonzero = 0;
    for (Eigen::Index r = 0; r < points.rows(); ++r) {
      const Eigen::Vector3d p = points.row(r).transpose();
      for (int s = 0; s < forest.size(); ++s) {
        const ScalarJet h = forest.Evaluate(s, p, JetOrder::kHessian);
        const ScalarJet expected = splines[s].Evaluate(p, JetOrder::kHessian);
        ASSERT_EQ(forest.Value(s, p), splines[s].Value(p));
        ASSERT_EQ(h.value, expected.value);
        ASSERT_EQ(h.gradient, expected.gradient);
        ASSERT_EQ(h.hessian, expected.hessian);
        const ScalarJet g = forest.Evaluate(s, p, JetOrder::kGradient);
        ASSERT_EQ(g.gradient, expected.gradient);
        nonzero += expected.value != 0.0;
      }
    }
    EXPECT_GT(nonzero, 500);  // the points meet the supports
  }
}

// At(p) prepares a point once for many splines: each value is that of the
// spline's own recursion, bit for bit, in any order of the splines, and a
// point's values do not leak into the next point's (nearby points share
// most nodes, so a stale memo would show).
TEST(SimplexSplineForest, PointValuesMatchEverySplineBitForBit) {
  const Eigen::MatrixX3d knots =
      testing::RandomUnitVectorsInCap(12, kCenter, 0.6, 400);
  SimplexSplineForest forest;
  std::vector<SimplexSpline> splines;
  for (int s = 0; s < 40; ++s) {
    const std::vector<int> subset = RandomSubset(12, 7, 31 * s + 5);
    Eigen::MatrixX3d local(7, 3);
    for (int j = 0; j < 7; ++j) local.row(j) = knots.row(subset[j]);
    StatusOr<SimplexSpline> spline = SimplexSpline::Create(local);
    ASSERT_TRUE(spline.ok()) << spline.status().message();
    forest.Add(*spline, subset);
    splines.push_back(std::move(spline).value());
  }
  forest.FinishAdding();
  const Eigen::MatrixX3d points =
      testing::RandomUnitVectorsInCap(200, kCenter, 0.6, 401);
  int nonzero = 0;
  for (Eigen::Index r = 0; r < points.rows(); ++r) {
    // Every other point a hair away from the previous one.
    const Eigen::Vector3d p =
        r % 2 == 1 ? Eigen::Vector3d((points.row(r - 1).transpose() +
                                      1e-9 * points.row(r).transpose())
                                         .normalized())
                   : Eigen::Vector3d(points.row(r).transpose());
    const SimplexSplineForest::PointValues at = forest.At(p);
    for (int s = forest.size() - 1; s >= 0; s -= (r % 3) + 1) {
      const double expected = splines[s].Value(p);
      ASSERT_EQ(at.value(s), expected) << "spline " << s << " point " << r;
      nonzero += expected != 0.0;
    }
  }
  EXPECT_GT(nonzero, 300);
}

}  // namespace
}  // namespace sdcb
