#include "sdcb/core/spline/dcb_basis.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "testing/brute_force_configurations.h"
#include "testing/random_sphere_points.h"

namespace sdcb {
namespace {

DcbBasis MakeBasis(const Eigen::MatrixX3d& knots, int degree) {
  const DelaunayConfigurations configurations =
      testing::BruteForceConfigurations(knots, degree);
  StatusOr<DcbBasis> basis = DcbBasis::Create(knots, configurations);
  EXPECT_TRUE(basis.ok()) << basis.status().message();
  return std::move(basis).value();
}

Eigen::MatrixX3d SetKnots(const DcbBasis& basis, int i) {
  const std::vector<int>& set = basis.configuration_set(i).knots;
  Eigen::MatrixX3d out(set.size(), 3);
  for (size_t j = 0; j < set.size(); ++j)
    out.row(j) = basis.knots().row(set[j]);
  return out;
}

TEST(DcbBasis, DegreeZeroIsTheIndicatorOfEachDelaunayTriangle) {
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(40, 1);
  const DcbBasis basis = MakeBasis(knots, 0);
  ASSERT_EQ(basis.size(), 2 * 40 - 4);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(2000, 2);
  for (int r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r);
    std::vector<BasisValue> values;
    basis.NormalizedValues(p, &values);
    ASSERT_EQ(values.size(), 1u);
    EXPECT_EQ(values[0].value, 1.0);
    // Oracle: plain barycentric positivity in the Delaunay triangle.
    EXPECT_TRUE(
        testing::InsideSphericalHull(p, SetKnots(basis, values[0].index)));
    EXPECT_NEAR(basis.Normalization(p), 1.0, 1e-14);
  }
  // Points on edges and at knots are counted exactly once (half-open).
  std::vector<Eigen::Vector3d> on_lines;
  for (int i = 0; i < basis.size(); ++i) {
    const std::vector<int>& t = basis.configuration_set(i).knots;
    for (int a = 0; a < 3; ++a) {
      on_lines.push_back(knots.row(t[a]).transpose());
      on_lines.push_back((knots.row(t[a]) + knots.row(t[(a + 1) % 3]))
                             .transpose()
                             .normalized());
    }
  }
  for (const Eigen::Vector3d& p : on_lines) {
    std::vector<BasisValue> values;
    basis.NonzeroValues(p, &values);
    ASSERT_EQ(values.size(), 1u);
    EXPECT_NEAR(values[0].value, 1.0, 1e-14);
  }
}

TEST(DcbBasis, PositiveLocalAndNormalizable) {
  const int n = 120, degree = 2;
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(n, 5);
  const DcbBasis basis = MakeBasis(knots, degree);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(1500, 6);
  double lowest = 1e9, highest = 0.0;
  std::vector<int> candidates;
  for (int r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r);
    basis.Candidates(p, &candidates);
    double sum = 0.0;
    for (int i = 0; i < basis.size(); ++i) {
      const double b = basis.Value(i, p);
      sum += b;
      EXPECT_GE(b, 0.0);
      if (b != 0.0) {
        // Local: nonzero only inside the hull of its k + 3 knots, and then
        // found by the support index.
        EXPECT_TRUE(testing::InsideSphericalHull(p, SetKnots(basis, i)));
        EXPECT_TRUE(
            std::binary_search(candidates.begin(), candidates.end(), i));
      }
    }
    EXPECT_NEAR(basis.Normalization(p), sum, 1e-14 * sum);
    lowest = std::min(lowest, sum);
    highest = std::max(highest, sum);
  }
  std::cout << "I(p) over 1500 random points, n = " << n << ", k = " << degree
            << ": min " << lowest << ", max " << highest << "\n";
  EXPECT_GT(lowest, 0.5);
  EXPECT_LT(highest, 2.0);
}

TEST(DcbBasis, WeightIsTheSumOfBoundaryDeterminants) {
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(30, 8);
  const DcbBasis basis = MakeBasis(knots, 3);
  for (int i = 0; i < basis.size(); ++i) {
    double w = 0.0;
    for (const auto& b : basis.configuration_set(i).boundaries) {
      Eigen::Matrix3d m;
      m << knots.row(b[0]), knots.row(b[1]), knots.row(b[2]);
      w += std::abs(m.determinant());
    }
    EXPECT_NEAR(basis.weight(i), w, 1e-14);
    const Eigen::Vector3d p = SetKnots(basis, i).colwise().sum().normalized();
    EXPECT_NEAR(basis.Value(i, p), w * basis.simplex_spline(i).Value(p),
                1e-14 * basis.Value(i, p));
  }
}

TEST(DcbBasis, RejectsInconsistentConfigurations) {
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(12, 9);
  DelaunayConfigurations c = testing::BruteForceConfigurations(knots, 1);
  DelaunayConfigurations bad = c;
  bad.sets[0].knots.pop_back();
  EXPECT_EQ(DcbBasis::Create(knots, bad).status().code(),
            StatusCode::kInvalidArgument);
  bad = c;
  bad.sets[0].knots.back() = 99;
  EXPECT_EQ(DcbBasis::Create(knots, bad).status().code(),
            StatusCode::kInvalidArgument);
  bad = c;
  bad.degree = 9;
  EXPECT_FALSE(DcbBasis::Create(knots, bad).ok());
}

}  // namespace
}  // namespace sdcb
