// Tests of converters/cad/cad_network: the network of blobby.off's spline (2 x
// 2 faces per cube face): at 31 points of every side exactly one other face has
// the same sphere point (brute force over all faces and sides), the two faces
// meet there and their normals differ by at most the smoothness limit, and the
// distance to the spline at random points off the measuring lattice is within
// the tolerance plus a quarter.
#include "sdcb/converters/cad/cad_network.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "converters/blobby_spline.h"
#include "sdcb/core/common/constants.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

// (u, v) of side k of a face over its knots' box at t.
Eigen::Vector2d FaceSidePoint(const BSplineFace& face, int k, double t) {
  switch (k) {
    case 0:
      return {t, face.v_breaks.front()};
    case 1:
      return {face.u_breaks.back(), t};
    case 2:
      return {t, face.v_breaks.back()};
    default:
      return {face.u_breaks.front(), t};
  }
}

TEST(CadNetworkTest, BlobbyIsSmoothAcrossEdgesAndWithinTheTolerance) {
  const SphericalSpline blobby = testing::BlobbySpline();
  const SphericalSpline* spline = &blobby;
  CadNetworkOptions options;
  options.tolerance_percent = 0.2;
  options.smoothness_degrees = 0.5;
  options.face_grid = 2;
  auto net = FitCadNetwork(*spline, options);
  ASSERT_TRUE(net.ok()) << net.status().message();
  ASSERT_TRUE(net->within_tolerance) << net->stop_reason;
  ASSERT_EQ(net->faces.size(), 24u);
  const auto sphere = [&](int f, const Eigen::Vector2d& p) {
    return net->layout.Point(net->face_quad[f], p.x(), p.y());
  };

  // Every side point has exactly one other face whose side has the same
  // sphere point at the same t (brute force over all faces and sides);
  // there the faces meet, and their normals differ by the jump.
  double jump = 0.0;
  for (size_t f = 0; f < net->faces.size(); ++f) {
    const BSplineFace& face = net->faces[f];
    for (int k = 0; k < 4; ++k) {
      const KnotBreaks& along = k % 2 == 0 ? face.u_breaks : face.v_breaks;
      for (int q = 1; q < 32; ++q) {
        const double t =
            along.front() + (along.back() - along.front()) * q / 32;
        const Eigen::Vector2d a = FaceSidePoint(face, k, t);
        const Eigen::Vector3d p = sphere(static_cast<int>(f), a);
        int found = 0;
        for (size_t g = 0; g < net->faces.size(); ++g) {
          if (g == f) continue;
          for (int s = 0; s < 4; ++s) {
            const BSplineFace& other = net->faces[g];
            const KnotBreaks& b = s % 2 == 0 ? other.u_breaks : other.v_breaks;
            if (t < b.front() || t > b.back()) continue;
            const Eigen::Vector2d c = FaceSidePoint(other, s, t);
            if ((sphere(static_cast<int>(g), c) - p).norm() > 1e-12) continue;
            ++found;
            Eigen::Vector3d fu, fv, gu, gv;
            const Eigen::Vector3d x = face.Evaluate(a.x(), a.y(), &fu, &fv);
            const Eigen::Vector3d y = other.Evaluate(c.x(), c.y(), &gu, &gv);
            EXPECT_LT((x - y).norm(), 1e-12);
            const Eigen::Vector3d nf = fu.cross(fv), ng = gu.cross(gv);
            jump = std::max(jump, std::atan2(nf.cross(ng).norm(), nf.dot(ng)) *
                                      180.0 / kPi);
          }
        }
        EXPECT_EQ(found, 1) << "face " << f << " side " << k << " t " << t;
      }
    }
  }
  EXPECT_LE(jump, options.smoothness_degrees);
  EXPECT_GT(jump, 0.0);

  // The distance at random points (off the measuring lattice).
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> d(0.0, 1.0);
  double worst = 0.0;
  for (size_t f = 0; f < net->faces.size(); ++f) {
    const BSplineFace& face = net->faces[f];
    for (int k = 0; k < 1000; ++k) {
      const Eigen::Vector2d x(
          face.u_breaks.front() +
              d(rng) * (face.u_breaks.back() - face.u_breaks.front()),
          face.v_breaks.front() +
              d(rng) * (face.v_breaks.back() - face.v_breaks.front()));
      const Eigen::Vector3d s =
          spline->Evaluate(sphere(static_cast<int>(f), x));
      worst = std::max(worst, (face.Evaluate(x.x(), x.y()) - s).norm());
    }
  }
  EXPECT_LE(100.0 * worst, 1.25 * options.tolerance_percent);
  EXPECT_LE(100.0 * worst, 1.25 * net->max_distance_percent);
}

// The cow's first-round model folds (its spline's normal turns over on a
// few percent of the lattice): the tangent rows cannot hold there, the
// distance grows as the knots refine, and the fit stops in bounded time
// saying so; without a smoothness limit (180) it fits the distance alone.
TEST(CadNetworkTest, AFoldingSplineStopsWhenTheDistanceGrows) {
  auto model = ReadSdcbFile(testing::TestDataPath("cow_round0_v1.sdcb"));
  ASSERT_TRUE(model.ok());
  auto spline = SurfaceFromModel(*model);
  ASSERT_TRUE(spline.ok());
  CadNetworkOptions options;
  options.tolerance_percent = 0.2;
  options.smoothness_degrees = 1.0;
  auto net = FitCadNetwork(*spline, options);
  ASSERT_TRUE(net.ok());
  EXPECT_FALSE(net->within_tolerance);
  EXPECT_NE(net->stop_reason.find("the distance grew"), std::string::npos)
      << net->stop_reason;
  EXPECT_LT(net->rounds, options.max_rounds);
  EXPECT_GT(net->folded_points, 0);
  options.smoothness_degrees = 180.0;
  net = FitCadNetwork(*spline, options);
  ASSERT_TRUE(net.ok());
  EXPECT_TRUE(net->within_tolerance) << net->stop_reason;
  EXPECT_LE(net->max_distance_percent, 0.2);
}

}  // namespace
}  // namespace sdcb
