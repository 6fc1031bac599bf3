#include "sdcb/core/sphere/perturbed_predicates.h"

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <vector>

#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {

// Independent oracle: the perturbation with a concrete eps = 2^-16, in exact
// rational arithmetic. Coordinate j of knot i moves by eps^(2^rank), rank
// the position of 3 i + j among the keys of the four points (only the order
// of the keys matters). For integer coordinates in [-2, 2] every non-zero
// coefficient of det(M + E) is an integer >= 1 and the others sum to less
// than 73 * 24 * eps < 1/30 of the leading term, so this eps is small enough.
int ConcreteEpsilonOrientSign(const Eigen::MatrixX3d& points,
                              std::array<int, 4> idx) {
  std::vector<int> keys;
  for (int i : idx) {
    if (i == kOriginIndex) continue;
    for (int c = 0; c < 3; ++c) keys.push_back(3 * i + c);
  }
  std::sort(keys.begin(), keys.end());
  const mpq_class eps(1, 1 << 16);
  std::array<std::array<mpq_class, 4>, 4> m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 3; ++c) {
      if (idx[r] == kOriginIndex) {
        m[r][c] = 0;
        continue;
      }
      const int rank = static_cast<int>(
          std::lower_bound(keys.begin(), keys.end(), 3 * idx[r] + c) -
          keys.begin());
      mpq_class power = eps;
      for (int k = 0; k < rank; ++k) power *= power;  // eps^(2^rank)
      m[r][c] = mpq_class(points(idx[r], c)) + power;
    }
    m[r][3] = 1;
  }
  // det by the permutation (Leibniz) formula.
  std::array<int, 4> perm = {0, 1, 2, 3};
  mpq_class det = 0;
  do {
    int inversions = 0;
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) inversions += perm[i] > perm[j];
    }
    mpq_class prod = 1;
    for (int r = 0; r < 4; ++r) prod *= m[r][perm[r]];
    if (inversions % 2) {
      det -= prod;
    } else {
      det += prod;
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  return -sgn(det);  // orient3d = -det[[p, 1]]
}

// Integer points full of degeneracies: coplanar and co-circular quadruples,
// planes through the origin, repeated coordinates.
Eigen::MatrixX3d DegeneratePoints() {
  const std::vector<std::array<double, 3>> rows = {
      {1, 1, 1},   {1, 1, -1},  {1, -1, 1}, {1, -1, -1}, {-1, 1, 1},
      {-1, 1, -1}, {-1, -1, 1}, {1, 0, 0},  {0, 1, 0},   {0, 0, 1},
      {-1, 0, 0},  {2, 0, 0},   {0, 2, -1}, {1, 1, 0}};
  Eigen::MatrixX3d m(rows.size(), 3);
  for (size_t i = 0; i < rows.size(); ++i)
    m.row(i) << rows[i][0], rows[i][1], rows[i][2];
  return m;
}

TEST(PerturbedPredicatesTest, MatchesConcreteEpsilonOracleOnDegeneratePoints) {
  const Eigen::MatrixX3d p = DegeneratePoints();
  const int n = static_cast<int>(p.rows());
  int degenerate = 0;
  for (int a = -1; a < n; ++a) {  // -1: the origin
    for (int b = a + 1; b < n; ++b) {
      for (int c = b + 1; c < n; ++c) {
        for (int d = c + 1; d < n; ++d) {
          // An unsorted argument order exercises the parity bookkeeping.
          const std::array<int, 4> idx = {c, a, d, b};
          const int got =
              PerturbedOrient3dSign(p, idx[0], idx[1], idx[2], idx[3]);
          ASSERT_NE(got, 0);
          EXPECT_EQ(got, ConcreteEpsilonOrientSign(p, idx))
              << a << " " << b << " " << c << " " << d;
          auto row = [&](int i) {
            return i == kOriginIndex ? Eigen::Vector3d::Zero().eval()
                                     : Eigen::Vector3d(p.row(i).transpose());
          };
          degenerate += Orient3dSign(row(a), row(b), row(c), row(d)) == 0;
        }
      }
    }
  }
  EXPECT_GT(degenerate, 100);  // the set really exercises the perturbation
}

TEST(PerturbedPredicatesTest, AntisymmetricUnderSwaps) {
  const Eigen::MatrixX3d p = DegeneratePoints();
  std::mt19937 rng(5);
  for (int trial = 0; trial < 500; ++trial) {
    std::array<int, 14> all;
    for (int i = 0; i < 14; ++i) all[i] = i;
    std::shuffle(all.begin(), all.end(), rng);
    std::array<int, 4> q = {all[0], all[1], all[2], all[3]};
    if (trial % 3 == 0) q[trial % 4] = kOriginIndex;
    const int s = PerturbedOrient3dSign(p, q[0], q[1], q[2], q[3]);
    std::swap(q[trial % 4], q[(trial + 1) % 4]);
    EXPECT_EQ(PerturbedOrient3dSign(p, q[0], q[1], q[2], q[3]), -s);
  }
}

TEST(PerturbedPredicatesTest, AgreesWithUnperturbedCapSideWhenThatIsDecided) {
  std::mt19937 rng(17);
  std::normal_distribution<double> normal;
  Eigen::MatrixX3d knots(40, 3);
  for (int i = 0; i < 40; ++i) {
    knots.row(i) =
        Eigen::RowVector3d(normal(rng), normal(rng), normal(rng)).normalized();
  }
  for (int a = 0; a < 10; ++a) {
    for (int q = 10; q < 40; ++q) {
      const int unperturbed = CapSide(knots.row(a), knots.row(a + 10),
                                      knots.row(a + 20), knots.row(q));
      if (q == a + 10 || q == a + 20) continue;
      ASSERT_NE(unperturbed, 0);
      EXPECT_EQ(PerturbedCapSide(knots, a, a + 10, a + 20, q), unperturbed);
    }
  }
}

TEST(PerturbedPredicatesTest, CapSideIsDecidedForCoCircularKnots) {
  // Four knots on the equator: every cap of three of them is a hemisphere
  // (plane through the origin) and the fourth is on its circle.
  Eigen::MatrixX3d knots(4, 3);
  knots << 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0;
  for (int q = 0; q < 4; ++q) {
    std::array<int, 3> t;
    int m = 0;
    for (int i = 0; i < 4; ++i) {
      if (i != q) t[m++] = i;
    }
    const int side = PerturbedCapSide(knots, t[0], t[1], t[2], q);
    EXPECT_TRUE(side == 1 || side == -1);
    // The cap does not depend on the order of its corners.
    EXPECT_EQ(PerturbedCapSide(knots, t[2], t[0], t[1], q), side);
    EXPECT_EQ(PerturbedCapSide(knots, t[1], t[0], t[2], q), side);
  }
}

}  // namespace
}  // namespace sdcb
