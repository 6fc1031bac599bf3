#include "sdcb/core/param/parameterization_distortion.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <random>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {

using Eigen::Vector3d;

Vector3d RandomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vector3d(n(rng), n(rng), n(rng)).normalized();
}

// Icosahedron subdivided `levels` times, vertices on S^2, faces outward.
TriangleMesh Icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  m.vertices.resize(12, 3);
  m.vertices << -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0,
      -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1;
  m.vertices.rowwise().normalize();
  m.faces.resize(20, 3);
  m.faces << 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
      11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9,
      4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1;
  for (int l = 0; l < levels; ++l) {
    std::vector<Vector3d> v;
    for (int i = 0; i < m.num_vertices(); ++i)
      v.push_back(m.vertices.row(i).transpose());
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      mid[key] = static_cast<int>(v.size()) - 1;
      return mid[key];
    };
    Eigen::MatrixX3i faces(4 * m.num_faces(), 3);
    for (int f = 0; f < m.num_faces(); ++f) {
      const int a = m.faces(f, 0), b = m.faces(f, 1), c = m.faces(f, 2);
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      faces.row(4 * f) << a, ab, ca;
      faces.row(4 * f + 1) << b, bc, ab;
      faces.row(4 * f + 2) << c, ca, bc;
      faces.row(4 * f + 3) << ab, bc, ca;
    }
    m.faces = faces;
    m.vertices.resize(v.size(), 3);
    for (size_t i = 0; i < v.size(); ++i) m.vertices.row(i) = v[i].transpose();
  }
  return m;
}

TEST(ParameterizationDistortion, AffineStretchGivesSingularValueRatio) {
  // Map the flat triangle m to A m with A = R diag(s1, s2) R^T: its singular
  // values are s1 and s2, so eq. (10) must give s1/s2 + s2/s1.
  const Vector3d m0(0.1, -0.3, 0.0), m1(1.3, 0.2, 0.0), m2(0.4, 0.9, 0.0);
  const double s1 = 2.5, s2 = 0.7, angle = 0.6;
  Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(angle, Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d a =
      rotation * Vector3d(s1, s2, 1.0).asDiagonal() * rotation.transpose();
  const MeshTriangleShape shape = ComputeMeshTriangleShape(m0, m1, m2, 1.0);
  const Vector3d t0 = a * m0, t1 = a * m1, t2 = a * m2;
  const double weighted = shape.cot[0] * (t2 - t1).squaredNorm() +
                          shape.cot[1] * (t0 - t2).squaredNorm() +
                          shape.cot[2] * (t1 - t0).squaredNorm();
  const double flat_area = 0.5 * (t1 - t0).cross(t2 - t0).norm();
  EXPECT_NEAR(AngleDistortionFormula(weighted, flat_area), s1 / s2 + s2 / s1,
              1e-12);
  // The area ratio of the map is s1 * s2.
  EXPECT_NEAR(AreaDistortionFormula(shape.area, flat_area),
              s1 * s2 + 1.0 / (s1 * s2), 1e-12);
}

TEST(ParameterizationDistortion, SmallSimilarTriangleOnSphere) {
  // A small sphere triangle and a scaled copy of its chord triangle as the
  // mesh triangle: a similarity, so E_angle = 2 * chord area / spherical
  // area = 2 - O(h^2).
  std::mt19937 rng(7);
  for (int i = 0; i < 20; ++i) {
    const Vector3d c = RandomUnit(rng);
    const Vector3d s0 = (c + 0.1 * RandomUnit(rng)).normalized();
    const Vector3d s1 = (c + 0.1 * RandomUnit(rng)).normalized();
    const Vector3d s2 = (c + 0.1 * RandomUnit(rng)).normalized();
    if (Det3(s0, s1, s2) <= 0) continue;
    const MeshTriangleShape shape =
        ComputeMeshTriangleShape(3 * s0, 3 * s1, 3 * s2, 1.0);
    const double chord_area = 0.5 * (s1 - s0).cross(s2 - s0).norm();
    EXPECT_NEAR(AngleDistortion(shape, s0, s1, s2),
                2.0 * chord_area / SphericalTriangleArea(s0, s1, s2), 1e-12);
    EXPECT_NEAR(AngleDistortion(shape, s0, s1, s2), 2.0, 0.02);
  }
}

TEST(ParameterizationDistortion, SphereMeshMappedToItself) {
  // E_angle = 2 - O(h^2): its gap to 2 shrinks about 4x per subdivision
  // (h halves). E_area = r + 1/r with r = 1 + O(h^2) the spherical / chord
  // area ratio, so E_area - 2 = (r - 1)^2 / r = O(h^4): about 16x.
  double previous_gap = 0.0, previous_angle_gap = 0.0;
  for (int levels = 2; levels <= 4; ++levels) {
    const TriangleMesh sphere = Icosphere(levels);
    auto d = MeasureParameterizationDistortion(sphere, sphere.vertices);
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(d->flipped_triangles, 0);
    const double angle_gap = 2.0 - d->angle_distortion_avg;
    EXPECT_GT(angle_gap, 0.0);
    EXPECT_LE(d->angle_distortion_max, 2.0);
    const double gap = d->area_distortion_avg - 2.0;
    EXPECT_GT(gap, 0.0);
    if (levels > 2) {
      EXPECT_NEAR(previous_gap / gap, 16.0, 3.0) << levels;
      EXPECT_NEAR(previous_angle_gap / angle_gap, 4.0, 0.6) << levels;
    }
    previous_gap = gap;
    previous_angle_gap = angle_gap;
    EXPECT_LT(d->area_distortion_max - 2.0, 1e-2);
  }
}

TEST(ParameterizationDistortion, SphericalAreaSumsToFourPi) {
  const TriangleMesh sphere = Icosphere(3);
  double total = 0.0;
  for (int f = 0; f < sphere.num_faces(); ++f) {
    total += SphericalTriangleArea(
        sphere.vertices.row(sphere.faces(f, 0)).transpose(),
        sphere.vertices.row(sphere.faces(f, 1)).transpose(),
        sphere.vertices.row(sphere.faces(f, 2)).transpose());
  }
  EXPECT_NEAR(total, 4.0 * kPi, 1e-10);
  // Octant triangle: area pi/2 (Girard: 3 right angles - pi).
  EXPECT_NEAR(SphericalTriangleArea(Vector3d::UnitX(), Vector3d::UnitY(),
                                    Vector3d::UnitZ()),
              kPi / 2, 1e-14);
}

TEST(ParameterizationDistortion, FlippedTrianglesAreCounted) {
  TriangleMesh sphere = Icosphere(1);
  Eigen::MatrixX3d mirrored = sphere.vertices;
  mirrored.col(0) *= -1.0;  // reflection: every triangle flips
  auto d = MeasureParameterizationDistortion(sphere, mirrored);
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->flipped_triangles, sphere.num_faces());
}

TEST(ParameterizationDistortion, EnergyGradientMatchesFiniteDifferences) {
  std::mt19937 rng(3);
  for (double lambda : {0.2, 1.0, 10.0}) {
    for (int trial = 0; trial < 10; ++trial) {
      const Vector3d c = RandomUnit(rng);
      Vector3d s[3];
      for (auto& x : s) x = (c + 0.3 * RandomUnit(rng)).normalized();
      if (Det3(s[0], s[1], s[2]) < 0) std::swap(s[1], s[2]);
      const MeshTriangleShape shape =
          ComputeMeshTriangleShape(Vector3d(0, 0, 0), Vector3d(0.2, 0.01, 0.05),
                                   Vector3d(0.05, 0.15, -0.02), 1.0);
      Vector3d gradient;
      TriangleEnergy(shape, s[0], s[1], s[2], lambda, &gradient);
      for (int k = 0; k < 3; ++k) {
        const double h = 1e-6;
        Vector3d plus = s[0], minus = s[0];
        plus[k] += h;
        minus[k] -= h;
        const double fd = (TriangleEnergy(shape, plus, s[1], s[2], lambda) -
                           TriangleEnergy(shape, minus, s[1], s[2], lambda)) /
                          (2 * h);
        EXPECT_NEAR(gradient[k], fd, 1e-5 * (1.0 + std::abs(fd)))
            << lambda << " " << k;
      }
    }
  }
}

// The filtered sign against CGAL's exact predicate (Det3Sign): random
// triangles of every size down to edges of 1e-12, and triples exactly or
// almost on one great circle, where the filter must hand over.
TEST(ParameterizationDistortion, FilteredDet3SignIsExact) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int decided_by_filter = 0, total = 0;
  for (double size : {1.0, 1e-2, 1e-4, 1e-6, 1e-9, 1e-12}) {
    for (int trial = 0; trial < 2000; ++trial) {
      const Vector3d c = RandomUnit(rng);
      const Vector3d s1 =
          (c + size * Vector3d(unit(rng), unit(rng), unit(rng))).normalized();
      const Vector3d s2 =
          (c + size * Vector3d(unit(rng), unit(rng), unit(rng))).normalized();
      double det = 0.0;
      EXPECT_EQ(SmallTriangleDet3Sign(c, s1, s2, &det), Det3Sign(c, s1, s2));
      EXPECT_EQ(det, SmallTriangleDet3(c, s1, s2));
      ++total;
      decided_by_filter += std::abs(det) > 1e-14 * size * size;
    }
  }
  EXPECT_GT(decided_by_filter, total / 2);
  // On one great circle: exactly (coordinate planes, zero determinant) and
  // after rounding (a rotated great circle: tiny determinants of either
  // sign).
  const Vector3d x(1, 0, 0), y(0, 1, 0), xy = Vector3d(1, 1, 0).normalized();
  double det = 0.0;
  EXPECT_EQ(SmallTriangleDet3Sign(x, y, xy, &det), 0);
  EXPECT_EQ(SmallTriangleDet3Sign(x, xy, y, &det), 0);
  const Vector3d axis = RandomUnit(rng);
  const Vector3d u = axis.unitOrthogonal(), w = axis.cross(u);
  int nonzero = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double t[3] = {unit(rng), unit(rng) * 1e-3, unit(rng) * 1e-8};
    Vector3d s[3];
    for (int i = 0; i < 3; ++i) s[i] = std::cos(t[i]) * u + std::sin(t[i]) * w;
    const int exact = Det3Sign(s[0], s[1], s[2]);
    nonzero += exact != 0;
    EXPECT_EQ(SmallTriangleDet3Sign(s[0], s[1], s[2], &det), exact);
  }
  EXPECT_GT(nonzero, 0);
}

// The series branch of SphericalAreaFromParts against std::atan2 (the
// formula it replaces), across the switch-over at |det| = denominator / 8,
// and the area of small spherical triangles against Girard's theorem
// (angle excess), an independent closed form.
TEST(ParameterizationDistortion, SeriesAreaMatchesAtan2AndGirard) {
  for (double x = 1e-12; x < 2.0; x *= 1.07) {
    for (double sign : {1.0, -1.0}) {
      const double det = sign * x * 0.75, denominator = 0.75;
      const double expected = 2.0 * std::atan2(det, denominator);
      EXPECT_NEAR(SphericalAreaFromParts(det, denominator), expected,
                  4e-16 * std::abs(expected))
          << x;
    }
  }
  EXPECT_DOUBLE_EQ(SphericalAreaFromParts(1.0, -0.5),
                   2.0 * std::atan2(1.0, -0.5));
  std::mt19937 rng(5);
  for (double size : {0.3, 0.05, 1e-3}) {
    for (int trial = 0; trial < 50; ++trial) {
      const Vector3d c = RandomUnit(rng);
      Vector3d s[3];
      for (auto& p : s) p = (c + size * RandomUnit(rng)).normalized();
      if (Det3(s[0], s[1], s[2]) < 0) std::swap(s[1], s[2]);
      // Girard: the angle of the spherical triangle at corner i is the
      // angle between the tangents of the great circles to the others.
      double excess = -kPi;
      for (int i = 0; i < 3; ++i) {
        const Vector3d& p = s[i];
        const Vector3d da = s[(i + 1) % 3] - p, db = s[(i + 2) % 3] - p;
        const Vector3d a = da - da.dot(p) * p, b = db - db.dot(p) * p;
        excess += std::atan2(a.cross(b).norm(), a.dot(b));
      }
      const double det = SmallTriangleDet3(s[0], s[1], s[2]);
      const double denominator =
          1.0 + s[0].dot(s[1]) + s[1].dot(s[2]) + s[2].dot(s[0]);
      // Girard's form cancels pi: its own error is ~1e-15 absolute.
      EXPECT_NEAR(SphericalAreaFromParts(det, denominator), excess, 1e-14);
    }
  }
}

// An octahedron stretched along +x (vertex (2, 0, 0); the others at 1) maps
// by central projection onto the eight octants (pi / 2 each). Its +x faces
// have area 3 / 2, its -x faces sqrt(3) / 2 (total 6 + 2 sqrt(3)): at +x
// the ratio is 6 / (3 + sqrt(3)), at -x 2 sqrt(3) / (3 + sqrt(3)), at the
// four others (two faces of each kind) 1.
TEST(ParameterizationDistortion, VertexAreaRatioOfAStretchedOctahedron) {
  TriangleMesh m;
  m.vertices.resize(6, 3);
  m.vertices << 2, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  m.faces.resize(8, 3);
  m.faces << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0,
      3, 5;
  const Eigen::MatrixX3d sphere = m.vertices.rowwise().normalized();
  const auto ratio = VertexAreaRatio(m, sphere);
  ASSERT_TRUE(ratio.ok());
  const double r3 = std::sqrt(3.0);
  EXPECT_NEAR((*ratio)[0], 6 / (3 + r3), 1e-12);
  EXPECT_NEAR((*ratio)[1], 2 * r3 / (3 + r3), 1e-12);
  for (int v = 2; v < 6; ++v) EXPECT_NEAR((*ratio)[v], 1.0, 1e-12);
  // Either orientation of the map (a mirrored sphere).
  Eigen::MatrixX3d mirrored = sphere;
  mirrored.col(0) *= -1;
  EXPECT_NEAR((*VertexAreaRatio(m, mirrored))[0], 6 / (3 + r3), 1e-12);
  EXPECT_FALSE(VertexAreaRatio(m, sphere.topRows(5)).ok());
}

}  // namespace
}  // namespace sdcb
