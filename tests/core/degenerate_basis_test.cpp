// The basis built on configurations of exactly degenerate knot sets (issue 4:
// "the resulting basis passes the basis issue's tests"): co-circular
// quadruples, great circles and symmetric polyhedra are resolved by the
// configurations' symbolic perturbation, and the basis built on the result
// must still be nonnegative, local and normalizable everywhere.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/dcb_basis.h"
#include "core/delaunay_configurations.h"
#include "tests/core/random_sphere_points.h"
#include "tests/core/special_knots.h"

namespace sdcb {
namespace {

void ExpectValidBasis(const Eigen::MatrixX3d& knots, int degree,
                      const std::string& name) {
  SCOPED_TRACE(name + ", degree " + std::to_string(degree));
  auto configurations = ComputeDelaunayConfigurations(knots, degree);
  ASSERT_TRUE(configurations.ok()) << configurations.status().message();
  auto basis = DcbBasis::Create(knots, *configurations);
  ASSERT_TRUE(basis.ok()) << basis.status().message();
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(3000, 17);
  double min_i = 1e300, max_i = 0;
  std::vector<BasisValue> values;
  for (int r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r);
    basis->NonzeroValues(p, &values);
    double sum = 0;
    for (const BasisValue& v : values) {
      ASSERT_GE(v.value, 0.0);
      // Locality: the value comes from a basis whose support cap holds p.
      const SphericalCap& cap = basis->support_cap(v.index);
      EXPECT_GE(cap.axis.dot(p), cap.cos_radius - 1e-12);
      sum += v.value;
    }
    EXPECT_NEAR(sum, basis->Normalization(p), 1e-12 * (1 + sum));
    min_i = std::min(min_i, sum);
    max_i = std::max(max_i, sum);
    if (degree == 0) {
      // Degree 0: exactly one triangle holds p, with B = 1.
      ASSERT_EQ(values.size(), 1u);
      EXPECT_NEAR(values[0].value, 1.0, 1e-12);
    }
  }
  EXPECT_GT(min_i, 0.0);
  EXPECT_LT(max_i, 10.0);
}

TEST(DegenerateBasisTest, PolyhedraGreatCirclesAndGrids) {
  struct Case {
    std::string name;
    Eigen::MatrixX3d knots;
  };
  const std::vector<Case> cases = {
      {"icosahedron", testing::IcosahedronKnots()},
      {"cube", testing::CubeKnots()},
      {"great circle + poles", testing::GreatCirclePlusPoles(16)},
      {"lat-long grid", testing::LatLongGrid(5, 8)}};
  for (const Case& c : cases) {
    const int max_degree = std::min<int>(3, static_cast<int>(c.knots.rows()) - 4);
    for (int degree = 0; degree <= max_degree; ++degree) {
      ExpectValidBasis(c.knots, degree, c.name);
    }
  }
}

}  // namespace
}  // namespace sdcb
