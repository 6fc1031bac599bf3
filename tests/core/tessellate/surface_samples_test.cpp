#include "sdcb/core/tessellate/surface_samples.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/tessellate/face_verification.h"
#include "sdcb/core/tessellate/sampled_certificate.h"
#include "testing/analytic_surfaces.h"

namespace sdcb {
namespace {

// Area of the spherical triangle (a, b, c) (Van Oosterom and Strackee).
double SphericalArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& c) {
  const double numerator = a.dot(b.cross(c));
  const double denominator = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
  return 2.0 * std::atan2(std::abs(numerator), denominator);
}

TEST(SurfaceSamplesTest, CoarsePatternHoldsEverySampleInItsFace) {
  // With coarse_scale, the samples keep the coarser pattern the refinement
  // passed through. Checked from its definition: its faces triangulate the
  // sphere (FromFaces accepts them, spherical areas sum to 4 pi), every
  // sample that is not one of its vertices lies in the domain triangle of
  // the face it names (signed volumes against the three edge planes, brute
  // force), and the coarse pattern is the same as a sampling at the coarse
  // criteria alone.
  const testing::EllipsoidSampler surface(Eigen::Vector3d(1.0, 0.6, 0.3));
  SurfaceSampleOptions options;
  options.tolerance = 2e-3;
  options.error_fraction = 1.0 / 8.0;
  options.coarse_scale = 3.0;
  StatusOr<SurfaceSamples> s = SampleSurface(surface, options);
  ASSERT_TRUE(s.ok());
  const int nv = s->pattern.num_vertices();
  const int nf = static_cast<int>(s->coarse_faces.size());
  ASSERT_EQ(static_cast<int>(s->coarse_face_of.size()), nv);
  Eigen::MatrixX3d directions(nv, 3);
  for (int v = 0; v < nv; ++v) directions.row(v) = s->pattern.vertex(v);
  Eigen::MatrixX3i faces(nf, 3);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) faces(f, k) = s->coarse_faces[f][k];
  }
  ASSERT_TRUE(SphereTriangulation::FromFaces(directions, faces, true).ok());
  double area = 0.0;
  for (const auto& t : s->coarse_faces) {
    area += SphericalArea(directions.row(t[0]), directions.row(t[1]),
                          directions.row(t[2]));
  }
  EXPECT_NEAR(area, 4.0 * kPi, 1e-9);
  int coarse_vertices = 0, outside = 0;
  for (int v = 0; v < nv; ++v) {
    const int f = s->coarse_face_of[v];
    if (f < 0) {
      ++coarse_vertices;
      continue;
    }
    const Eigen::Vector3d p = directions.row(v);
    const auto& t = s->coarse_faces[f];
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector3d a = directions.row(t[e]);
      const Eigen::Vector3d b = directions.row(t[(e + 1) % 3]);
      if (a.cross(b).dot(p) < -1e-12) ++outside;
    }
  }
  EXPECT_EQ(outside, 0);
  EXPECT_LT(3 * coarse_vertices, nv);

  // The coarse pattern is where a sampling with the looser criteria stops.
  SurfaceSampleOptions coarse = options;
  coarse.coarse_scale = 0.0;
  coarse.error_fraction = options.error_fraction * options.coarse_scale;
  coarse.length_factor = options.length_factor * std::sqrt(3.0);
  StatusOr<SurfaceSamples> alone = SampleSurface(surface, coarse);
  ASSERT_TRUE(alone.ok());
  EXPECT_EQ(alone->pattern.num_vertices(), coarse_vertices);
  EXPECT_EQ(alone->pattern.num_faces(), nf);
}

TEST(SurfaceSamplesTest, StartFromCoarseMeasuresEverySample) {
  // SampledFaces::StartFromCoarse puts every sample inside the coarse face
  // that holds it and measures it: each face's error is the largest
  // distance of its samples to its flat triangle (brute force over all
  // samples, CGAL's point-triangle distance).
  const testing::EllipsoidSampler surface(Eigen::Vector3d(1.0, 0.6, 0.3));
  SurfaceSampleOptions options;
  options.tolerance = 2e-3;
  options.coarse_scale = 3.0;
  StatusOr<SurfaceSamples> s = SampleSurface(surface, options);
  ASSERT_TRUE(s.ok());
  const std::vector<int> coarse_face_of = s->coarse_face_of;
  SampledFaces faces(&*s, CertificateOptions{options.tolerance, 180.0});
  faces.StartFromCoarse();
  const SphereTriangulation& pattern = s->pattern;
  ASSERT_EQ(pattern.num_faces(), static_cast<int>(s->coarse_faces.size()));
  int held = 0;
  std::vector<double> largest(pattern.num_face_slots(), 0.0);
  for (int v = 0; v < pattern.num_vertices(); ++v) {
    const int f = coarse_face_of[v];
    if (f < 0) {
      EXPECT_TRUE(pattern.vertex_alive(v));
      continue;
    }
    EXPECT_FALSE(pattern.vertex_alive(v));
    const auto& t = pattern.face(f);
    const Eigen::Vector3d a = s->positions[t[0]], b = s->positions[t[1]],
                          c = s->positions[t[2]];
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    const auto point = [](const Eigen::Vector3d& x) {
      return K::Point_3(x[0], x[1], x[2]);
    };
    const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(
        point(s->positions[v]), K::Triangle_3(point(a), point(b), point(c)))));
    largest[f] = std::max(largest[f], d);
  }
  for (int f = 0; f < pattern.num_face_slots(); ++f) {
    held += static_cast<int>(faces.samples_in(f).size());
    EXPECT_NEAR(faces.error(f), largest[f], 1e-12);
  }
  int expected = 0;
  for (int f : coarse_face_of) expected += f >= 0;
  EXPECT_EQ(held, expected);
}

}  // namespace
}  // namespace sdcb
