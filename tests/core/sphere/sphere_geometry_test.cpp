#include "sdcb/core/sphere/sphere_geometry.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "testing/random_sphere_points.h"
#include "testing/special_knots.h"

namespace sdcb {
namespace {

Eigen::MatrixX3d Rows(std::initializer_list<Eigen::Vector3d> rows) {
  Eigen::MatrixX3d m(rows.size(), 3);
  int i = 0;
  for (const Eigen::Vector3d& r : rows) m.row(i++) = r.transpose();
  return m;
}

TEST(InOpenHemisphere, ConstructedCases) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(),
                        y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  // Antipodal pair: the origin is on their segment.
  EXPECT_FALSE(InOpenHemisphere(Rows({x, -x, z})));
  // On a great circle: within an open semicircle or not (origin on an edge,
  // or inside the triangle).
  EXPECT_TRUE(InOpenHemisphere(Rows({x, (x + y).normalized(), y})));
  EXPECT_FALSE(InOpenHemisphere(Rows({x, y, (-x - y).normalized()})));
  EXPECT_FALSE(InOpenHemisphere(Rows({x, y, -x})));
  // Great-circle triples plus a pole: the pole cannot help if the circle's
  // knots surround the origin.
  EXPECT_FALSE(InOpenHemisphere(Rows({x, y, (-x - y).normalized(), z})));
  EXPECT_TRUE(InOpenHemisphere(Rows({x, y, (x + y).normalized(), -z})));
  // Tetrahedron around the origin, and one face of it.
  const Eigen::MatrixX3d cube = testing::CubeKnots();
  Eigen::MatrixX3d tetra(4, 3);
  tetra << cube.row(0), cube.row(3), cube.row(5), cube.row(6);
  EXPECT_FALSE(InOpenHemisphere(tetra));
  EXPECT_TRUE(InOpenHemisphere(tetra.topRows(3)));
  // The 16-gon's knots 0, 1, 8 (antipodal up to rounding: sin(pi) != 0)
  // with the pole: the exact test sees the tiny tilt.
  const Eigen::MatrixX3d gc = testing::GreatCirclePlusPoles(16);
  EXPECT_FALSE(InOpenHemisphere(
      Rows({gc.row(0), gc.row(1), gc.row(8), gc.row(9), gc.row(16)})));
}

// Random small sets: a direction found by search with every n . t > 0
// proves "inside"; the origin written as a nonnegative combination (the
// set holds a random tetrahedron around the origin) proves "not inside".
TEST(InOpenHemisphere, AgreesWithSearchAndCertificates) {
  const Eigen::MatrixX3d directions = testing::RandomUnitVectors(4000, 99);
  int inside = 0, outside = 0;
  for (unsigned seed = 0; seed < 200; ++seed) {
    const Eigen::MatrixX3d pts = testing::RandomUnitVectors(5, seed + 1000);
    bool found = false;
    for (int d = 0; d < directions.rows() && !found; ++d) {
      found = ((pts * directions.row(d).transpose()).array() > 1e-9).all();
    }
    if (found) {
      ++inside;
      EXPECT_TRUE(InOpenHemisphere(pts)) << seed;
    }
    // Certificate: if the origin is a nonnegative combination of 4 of them.
    for (int skip = 0; skip < 5; ++skip) {
      Eigen::Matrix<double, 3, 4> a;
      for (int j = 0, c = 0; j < 5; ++j) {
        if (j != skip) a.col(c++) = pts.row(j).transpose();
      }
      // Weights of the first three that cancel the fourth.
      const Eigen::Vector3d w = a.leftCols<3>().fullPivLu().solve(-a.col(3));
      if ((w.array() > 1e-6).all()) {
        ++outside;
        EXPECT_FALSE(InOpenHemisphere(pts)) << seed;
        break;
      }
    }
  }
  EXPECT_GT(inside, 20);
  EXPECT_GT(outside, 20);
}

}  // namespace
}  // namespace sdcb
