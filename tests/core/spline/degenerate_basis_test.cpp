// The basis built on configurations of exactly degenerate knot sets (issue 4:
// "the resulting basis passes the basis issue's tests"): co-circular
// quadruples, great circles and symmetric polyhedra are resolved by the
// configurations' symbolic perturbation, and the basis built on the result
// must be the limit of the perturbed knots' basis: nonnegative, local,
// deterministic and with I > 0, or refused with kInvalidInput.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sdcb/core/sphere/perturbed_predicates.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "testing/random_sphere_points.h"
#include "testing/special_knots.h"

namespace sdcb {
namespace {

struct Case {
  std::string name;
  Eigen::MatrixX3d knots;
  int max_degree;
};

void ExpectValidBasis(const Eigen::MatrixX3d& knots, int degree,
                      const std::string& name) {
  SCOPED_TRACE(name + ", degree " + std::to_string(degree));
  auto configurations = ComputeDelaunayConfigurations(knots, degree);
  ASSERT_TRUE(configurations.ok()) << configurations.status().message();
  auto basis = DcbBasis::Create(knots, *configurations);
  ASSERT_TRUE(basis.ok()) << basis.status().message();
  // Deterministic: a second construction gives bit-identical values.
  auto again = DcbBasis::Create(knots, *configurations);
  ASSERT_TRUE(again.ok());
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(3000, 17);
  double min_i = 1e300, max_i = 0;
  std::vector<BasisValue> values, repeated;
  for (int r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r);
    basis->NonzeroValues(p, &values);
    again->NonzeroValues(p, &repeated);
    ASSERT_EQ(values.size(), repeated.size());
    double sum = 0;
    for (size_t v = 0; v < values.size(); ++v) {
      ASSERT_EQ(values[v].index, repeated[v].index);
      ASSERT_EQ(values[v].value, repeated[v].value);
      ASSERT_GE(values[v].value, 0.0);
      // Locality: the value comes from a basis whose support cap holds p.
      const SphericalCap& cap = basis->support_cap(values[v].index);
      EXPECT_GE(cap.axis.dot(p), cap.cos_radius - 1e-12);
      sum += values[v].value;
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
  // Few random knots give large I at high degree whatever their pairs: the
  // 40 random knots below reach 18.5 at degree 4 with or without the knot
  // 1e-9 away (measured), the regular sets stay below 5 at degree 4.
  EXPECT_LT(max_i, 25.0);
}

void ExpectRefused(const Eigen::MatrixX3d& knots, int degree,
                   const std::string& name, const std::string& reason) {
  SCOPED_TRACE(name + ", degree " + std::to_string(degree));
  auto configurations = ComputeDelaunayConfigurations(knots, degree);
  ASSERT_TRUE(configurations.ok()) << configurations.status().message();
  auto basis = DcbBasis::Create(knots, *configurations);
  ASSERT_FALSE(basis.ok());
  EXPECT_EQ(basis.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(basis.status().message().find(reason), std::string::npos)
      << basis.status().message();
}

TEST(DegenerateBasisTest, PolyhedraGreatCirclesGridsRingsAndClosePairs) {
  const std::vector<Case> cases = {
      {"icosahedron", testing::IcosahedronKnots(), 3},
      {"cube", testing::CubeKnots(), 1},
      {"great circle + poles", testing::GreatCirclePlusPoles(16), 1},
      {"lat-long grid", testing::LatLongGrid(5, 8), 4},
      {"staggered rings",
       testing::StaggeredRings({-70, -45, -20, 15, 40, 65}, 7), 4},
      {"two knots 1e-9 apart", testing::RandomWithClosePair(40, 1e-9, 3), 4},
      {"two knots 1e-9 apart, seed 8",
       testing::RandomWithClosePair(60, 1e-9, 8), 3}};
  for (const Case& c : cases) {
    for (int degree = 0; degree <= c.max_degree; ++degree) {
      ExpectValidBasis(c.knots, degree, c.name);
    }
  }
}

// Inputs that are refused, and why: a boundary triple X_B on a great circle
// whose set X~ (and a child X~ \ x_j with a nonzero cofactor) is not in an
// open hemisphere (antipodal knots: the 16-gon and the cube contain
// antipodal pairs). Then |det X_B| M(p | X~) of the perturbed knots has no
// bounded limit: moving the knots by a random eps instead of the symbolic
// perturbation, max I grows like 1 / eps (great circle + poles, degree 2:
// 153, 1.5e4, 1.5e6 at eps = 1e-2, 1e-4, 1e-6; docs/BASIS.md).
// The great circle + poles at degree 1 needs the limit terms (boundary
// triples of three equator knots around the origin; their sets hold an
// antipodal pair); their derivatives match central differences of values.
TEST(DegenerateBasisTest, LimitTermsOnTheGreatCircleAndTheirDerivatives) {
  const Eigen::MatrixX3d knots = testing::GreatCirclePlusPoles(16);
  auto configurations = ComputeDelaunayConfigurations(knots, 1);
  ASSERT_TRUE(configurations.ok());
  auto basis = DcbBasis::Create(knots, *configurations);
  ASSERT_TRUE(basis.ok()) << basis.status().message();
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(400, 31);
  int with_terms = 0, checked = 0;
  for (int i = 0; i < basis->size(); ++i) {
    if (basis->num_limit_terms(i) == 0) continue;
    ++with_terms;
    EXPECT_FALSE(basis->has_simplex_spline(i));
    for (int r = 0; r < points.rows(); ++r) {
      const Eigen::Vector3d p = points.row(r);
      const ScalarJet jet = basis->Evaluate(i, p, JetOrder::kGradient);
      EXPECT_NEAR(jet.value, basis->Value(i, p), 1e-14);
      if (jet.value == 0.0) continue;
      // Degree 1: piecewise linear; skip points near a kink.
      const double h = 1e-6;
      Eigen::Vector3d fd;
      bool smooth = true;
      for (int a = 0; a < 3 && smooth; ++a) {
        const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(a);
        const double plus = basis->Value(i, p + e),
                     minus = basis->Value(i, p - e), mid = basis->Value(i, p);
        fd[a] = (plus - minus) / (2 * h);
        smooth = std::abs(plus - 2 * mid + minus) < 1e-12;
      }
      if (!smooth) continue;
      ++checked;
      EXPECT_LT((fd - jet.gradient).norm(), 1e-6 * (1 + jet.gradient.norm()));
    }
  }
  EXPECT_GT(with_terms, 0);
  EXPECT_GT(checked, 10);
}

TEST(DegenerateBasisTest, RefusesSetsWithoutABoundedLimit) {
  const std::string reason = "not in an open hemisphere";
  ExpectRefused(testing::GreatCirclePlusPoles(16), 2, "great circle + poles",
                reason);
  ExpectRefused(testing::GreatCirclePlusPoles(16), 3, "great circle + poles",
                reason);
  ExpectRefused(testing::CubeKnots(), 3, "cube", reason);
}

// Too few knots for the degree leave part of the sphere outside every
// support (I = 0 on ~4.5% of random points for the cube at degree 2, ~1% for
// the icosahedron at degree 4, before the coverage check). Not a matter of
// degeneracy: the cube moved by a random 1e-3 (generic knots) has the same
// kind of hole at degree 3. Create refuses them all.
TEST(DegenerateBasisTest, RefusesBasesThatLeaveAHole) {
  const std::string reason = "leaves a hole";
  ExpectRefused(testing::CubeKnots(), 2, "cube", reason);
  ExpectRefused(testing::IcosahedronKnots(), 4, "icosahedron", reason);
  Eigen::MatrixX3d moved =
      testing::CubeKnots() + 1e-3 * testing::RandomUnitVectors(8, 5);
  moved.rowwise().normalize();
  ExpectRefused(moved, 3, "cube moved by 1e-3", reason);
  // The check can be turned off; the hole is then real: I = 0 at a point
  // where no configuration set's knots surround p (so no B_i can be > 0).
  auto configurations = ComputeDelaunayConfigurations(testing::CubeKnots(), 2);
  ASSERT_TRUE(configurations.ok());
  DcbBasisOptions unchecked;
  unchecked.coverage_samples = 0;
  auto basis =
      DcbBasis::Create(testing::CubeKnots(), *configurations, unchecked);
  ASSERT_TRUE(basis.ok());
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(3000, 17);
  int holes = 0;
  for (int r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r);
    if (basis->Normalization(p) > 0) continue;
    ++holes;
  }
  EXPECT_GT(holes, 30);
}

// Oracle for the limit terms: a degree-k set whose boundary lies on a circle
// at height h above the origin (the cap z > h / sqrt(1 + h^2) holds the north
// pole and k - 1 more knots) is generic for h != 0, and its B_h = |det X_B|
// M(p | X~) (ordinary recursion) must tend to the basis built at h = 0 (flat
// X_B: limit terms) as h -> 0, from the side the symbolic perturbation
// picks. Corners spread over more than a semicircle (not in an open
// hemisphere): a nonzero limit; within a semicircle: the limit 0.
TEST(DegenerateBasisTest, FlatBoundaryIsTheLimitOfTiltedOnes) {
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(2000, 23);
  for (int degree = 1; degree <= 3; ++degree) {
    for (bool spread : {true, false}) {
      SCOPED_TRACE("degree " + std::to_string(degree) +
                   (spread ? ", spread corners" : ", corners in a semicircle"));
      const std::vector<double> angles =
          spread ? std::vector<double>{0.1, 2.9, 4.4}
                 : std::vector<double>{0.1, 1.2, 2.5};
      auto make = [&](double h) {
        Eigen::MatrixX3d knots(degree + 3, 3);
        for (int j = 0; j < 3; ++j) {
          knots.row(j) << std::cos(angles[j]), std::sin(angles[j]), h;
        }
        knots.row(3) << 0, 0, 1;
        for (int j = 4; j < degree + 3; ++j) {
          const double a = 1.0 + 1.7 * j, lat = 0.5 + 0.2 * j;
          knots.row(j) << std::cos(lat) * std::cos(a),
              std::cos(lat) * std::sin(a), std::sin(lat);
        }
        knots.rowwise().normalize();
        return knots;
      };
      DelaunayConfigurations configurations;
      configurations.degree = degree;
      ConfigurationSet set;
      for (int j = 0; j < degree + 3; ++j) set.knots.push_back(j);
      set.boundaries = {{0, 1, 2}};
      configurations.sets = {set};
      const Eigen::MatrixX3d flat = make(0.0);
      // The symbolic perturbation (by knot index) puts the pole inside the
      // hemisphere of the flat triple, as the tilt h > 0 does.
      ASSERT_EQ(PerturbedCapSide(flat, 0, 1, 2, 3), 1);
      // One basis function covers only its support: no coverage check.
      DcbBasisOptions single;
      single.coverage_samples = 0;
      auto limit = DcbBasis::Create(flat, configurations, single);
      ASSERT_TRUE(limit.ok()) << limit.status().message();
      EXPECT_EQ(limit->num_limit_terms(0) > 0, spread);
      double previous = 1e300, scale = 0;
      for (double h : {1e-3, 1e-5, 1e-7}) {
        const Eigen::MatrixX3d tilted = make(h);
        ASSERT_EQ(
            CapSide(tilted.row(0), tilted.row(1), tilted.row(2), tilted.row(3)),
            1);
        auto generic = DcbBasis::Create(tilted, configurations, single);
        ASSERT_TRUE(generic.ok()) << generic.status().message();
        EXPECT_EQ(generic->num_limit_terms(0), 0);
        double diff = 0;
        for (int r = 0; r < points.rows(); ++r) {
          const Eigen::Vector3d p = points.row(r);
          const double b0 = limit->Value(0, p), bh = generic->Value(0, p);
          diff = std::max(diff, std::abs(b0 - bh));
          scale = std::max(scale, std::abs(b0));
        }
        // Linear convergence: each step of h / 100 divides the gap by ~100
        // (measured 0.0059, 5.9e-5, 5.9e-7 at degree 1).
        EXPECT_LT(diff, previous / 50);
        previous = diff;
      }
      EXPECT_LT(previous, 1e-5);
      if (spread) {
        EXPECT_GT(scale, 0.5);
      } else {
        EXPECT_EQ(scale, 0.0);
      }
    }
  }
}

}  // namespace
}  // namespace sdcb
