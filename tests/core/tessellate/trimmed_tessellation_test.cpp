// Tessellation of trimmed analytic surfaces (core/tessellate/trim_pattern.h
// through TessellateAdaptively): the kept region only, the trims as its
// boundary. Oracles: the trim polygons' closed-form sides and areas
// (spherical triangles), the sphere's distance function.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"
#include "sdcb/core/tessellate/feature_pattern.h"
#include "sdcb/core/tessellate/trim_pattern.h"
#include "testing/analytic_surfaces.h"

namespace sdcb {
namespace {

using testing::EllipsoidSampler;

// A circle of n points at angular radius acos(cos_radius) around `axis`,
// ordered so that the cap around the axis lies on its left (keep_cap) or on
// its right (the cap is a hole).
struct Circle {
  Eigen::Vector3d axis;
  double cos_radius;
  int n;
  bool keep_cap;
};

TrimLoop LoopOf(const Circle& c) {
  const Eigen::Vector3d z = c.axis.normalized();
  const Eigen::Vector3d e1 = z.unitOrthogonal(), e2 = z.cross(e1);
  const double s = std::sqrt(1.0 - c.cos_radius * c.cos_radius);
  TrimLoop loop;
  loop.points.resize(c.n, 3);
  for (int i = 0; i < c.n; ++i) {
    const double t = 2.0 * kPi * i / c.n * (c.keep_cap ? 1.0 : -1.0);
    loop.points.row(i) =
        (c.cos_radius * z + s * (std::cos(t) * e1 + std::sin(t) * e2))
            .normalized()
            .transpose();
  }
  return loop;
}

// The polygon's sides in cap order (cap on the left): normals a x b,
// computed once per circle.
const std::vector<Eigen::Vector3d>& CapSideNormals(const Circle& c) {
  static std::map<std::array<double, 5>, std::vector<Eigen::Vector3d>> cache;
  std::vector<Eigen::Vector3d>& normals =
      cache[{c.axis[0], c.axis[1], c.axis[2], c.cos_radius, double(c.n)}];
  if (!normals.empty()) return normals;
  Circle ccw = c;
  ccw.keep_cap = true;
  const TrimLoop loop = LoopOf(ccw);
  for (int i = 0; i < c.n; ++i) {
    const Eigen::Vector3d a = loop.points.row(i);
    const Eigen::Vector3d b = loop.points.row((i + 1) % c.n);
    normals.push_back(a.cross(b).normalized());
  }
  return normals;
}

// Signed depth of p inside the convex cap polygon: the smallest
// dot(p, side normal); > 0 strictly inside.
double CapDepth(const Circle& c, const Eigen::Vector3d& p) {
  double depth = 1e300;
  for (const Eigen::Vector3d& n : CapSideNormals(c)) {
    depth = std::min(depth, p.dot(n));
  }
  return depth;
}

// Closed form: the cap polygon's area as a fan of spherical triangles from
// its axis (Van Oosterom and Strackee).
double CapPolygonArea(const Circle& c) {
  Circle ccw = c;
  ccw.keep_cap = true;
  const TrimLoop loop = LoopOf(ccw);
  const Eigen::Vector3d z = c.axis.normalized();
  double area = 0.0;
  for (int i = 0; i < c.n; ++i) {
    const Eigen::Vector3d a = loop.points.row(i);
    const Eigen::Vector3d b = loop.points.row((i + 1) % c.n);
    area += 2.0 *
            std::atan2(z.dot(a.cross(b)), 1.0 + z.dot(a) + a.dot(b) + b.dot(z));
  }
  return area;
}

double KeptArea(const std::vector<Circle>& circles) {
  double area = 0.0;
  bool any_cap = false;
  for (const Circle& c : circles) {
    if (c.keep_cap) {
      area += CapPolygonArea(c);
      any_cap = true;
    } else {
      area -= CapPolygonArea(c);
    }
  }
  return any_cap ? area : 4.0 * kPi + area;
}

// Signed: >= 0 on the kept side of every circle (inside a kept cap, outside
// a hole), the depth below zero otherwise.
double KeptDepth(const std::vector<Circle>& circles, const Eigen::Vector3d& p) {
  double depth = 1e300;
  for (const Circle& c : circles) {
    const double d = CapDepth(c, p);
    depth = std::min(depth, c.keep_cap ? d : -d);
  }
  return depth;
}

// Angle from p to the nearest side of any circle's polygon.
double AngleToTrims(const std::vector<Circle>& circles,
                    const Eigen::Vector3d& p) {
  double best = 1e300;
  for (const Circle& c : circles) {
    Circle ccw = c;
    ccw.keep_cap = true;
    // Far from the circle's polygon (a quick bound): no side is nearer.
    const double to_circle =
        std::abs(std::acos(std::clamp(p.dot(c.axis.normalized()), -1.0, 1.0)) -
                 std::acos(c.cos_radius));
    if (to_circle > 2.0 * kPi / c.n + best) continue;
    const TrimLoop loop = LoopOf(ccw);
    for (int i = 0; i < c.n; ++i) {
      const Eigen::Vector3d a = loop.points.row(i);
      const Eigen::Vector3d b = loop.points.row((i + 1) % c.n);
      const Eigen::Vector3d n = a.cross(b).normalized();
      const Eigen::Vector3d q = p - n * p.dot(n);
      double angle;
      if (a.cross(q).dot(n) >= 0.0 && q.cross(b).dot(n) >= 0.0) {
        angle = std::asin(std::min(1.0, std::abs(p.dot(n))));
      } else {
        // atan2, not acos: exact near 0.
        angle = std::min(std::atan2(p.cross(a).norm(), p.dot(a)),
                         std::atan2(p.cross(b).norm(), p.dot(b)));
      }
      best = std::min(best, angle);
    }
  }
  return best;
}

// Boundary loops of a triangle mesh: directed edges without their reverse,
// chained. -1 when the boundary is not a set of simple loops.
int CountBoundaryLoops(const Eigen::MatrixX3i& faces,
                       std::set<int>* boundary_vertices) {
  std::set<std::pair<int, int>> directed;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (!directed.insert({faces(f, k), faces(f, (k + 1) % 3)}).second) {
        return -1;  // non-manifold or inconsistently oriented
      }
    }
  }
  std::map<int, int> next;
  for (const auto& [a, b] : directed) {
    if (directed.count({b, a})) continue;
    if (next.count(a)) return -1;  // two boundary edges leave a
    next[a] = b;
    boundary_vertices->insert(a);
  }
  int loops = 0;
  std::set<int> seen;
  for (const auto& [start, unused] : next) {
    if (seen.count(start)) continue;
    ++loops;
    int v = start;
    do {
      seen.insert(v);
      const auto it = next.find(v);
      if (it == next.end()) return -1;
      v = it->second;
    } while (v != start);
  }
  return loops;
}

struct Outcome {
  Tessellation t;
  double seconds;
};

Outcome Tessellate(const SurfaceSampler& surface,
                   const std::vector<Circle>& circles, double tolerance) {
  TessellationOptions options;
  options.tolerance = tolerance;
  for (const Circle& c : circles) options.trims.push_back(LoopOf(c));
  const auto start = std::chrono::steady_clock::now();
  StatusOr<Tessellation> t = TessellateAdaptively(surface, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  EXPECT_TRUE(t.ok()) << t.status().message();
  if (!t.ok()) return {Tessellation{}, seconds};
  return {std::move(t).value(), seconds};
}

// Every check that needs no surface: vertices and face centroids on the kept
// side, the boundary the trims (as many loops, on the trim arcs).
void ExpectTrimmed(const std::vector<Circle>& circles, const Tessellation& t,
                   const char* name) {
  ASSERT_GT(t.faces.rows(), 0) << name;
  for (Eigen::Index v = 0; v < t.directions.rows(); ++v) {
    EXPECT_GE(KeptDepth(circles, t.directions.row(v).transpose()), -1e-12)
        << name << " vertex " << v;
  }
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f) {
    const Eigen::Vector3d c =
        (t.directions.row(t.faces(f, 0)) + t.directions.row(t.faces(f, 1)) +
         t.directions.row(t.faces(f, 2)))
            .normalized()
            .transpose();
    EXPECT_GT(KeptDepth(circles, c), 0.0) << name << " face " << f;
  }
  std::set<int> boundary;
  EXPECT_EQ(CountBoundaryLoops(t.faces, &boundary),
            static_cast<int>(circles.size()))
      << name;
  double worst = 0.0;
  for (int v : boundary) {
    worst = std::max(worst, AngleToTrims(circles, t.directions.row(v)));
  }
  EXPECT_LE(worst, 1e-12) << name;
}

// On the unit sphere: every face within the tolerance (1 - |x| on a lattice,
// flat points lie inside) and the area between the closed form scaled by
// (1 - tolerance)^2 (radial projection onto the sphere) and the closed form.
void ExpectOnUnitSphere(const std::vector<Circle>& circles,
                        const Tessellation& t, double eps, const char* name) {
  double worst = 0.0, area = 0.0;
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f) {
    const Eigen::Vector3d x0 = t.positions.row(t.faces(f, 0));
    const Eigen::Vector3d x1 = t.positions.row(t.faces(f, 1));
    const Eigen::Vector3d x2 = t.positions.row(t.faces(f, 2));
    area += 0.5 * (x1 - x0).cross(x2 - x0).norm();
    for (int i = 0; i <= 12; ++i)
      for (int j = 0; i + j <= 12; ++j) {
        const Eigen::Vector3d x = (i * x0 + j * x1 + (12 - i - j) * x2) / 12.0;
        worst = std::max(worst, 1.0 - x.norm());
      }
  }
  EXPECT_LE(worst, eps) << name;
  EXPECT_LE(t.certified_distance, eps) << name;
  const double expected = KeptArea(circles);
  EXPECT_LE(area, expected) << name;
  EXPECT_GE(area, expected * (1.0 - eps) * (1.0 - eps)) << name;
  std::cout << name << ": " << t.faces.rows() << " faces, "
            << t.positions.rows() << " vertices, area " << area << " vs "
            << expected << ", measured " << worst << "\n";
}

constexpr double kEps = 1e-3;

TEST(TrimmedTessellationTest, CapOfOneLatitudeLoop) {
  const std::vector<Circle> circles = {
      {Eigen::Vector3d::UnitZ(), 0.5, 64, true}};
  EllipsoidSampler sphere(Eigen::Vector3d::Ones());
  const Outcome o = Tessellate(sphere, circles, kEps);
  std::cout << "cap: " << o.seconds << " s\n";
  ExpectTrimmed(circles, o.t, "cap");
  ExpectOnUnitSphere(circles, o.t, kEps, "cap");
}

TEST(TrimmedTessellationTest, TubeOfTwoLoops) {
  const std::vector<Circle> circles = {
      {Eigen::Vector3d::UnitZ(), 0.5, 64, false},
      {-Eigen::Vector3d::UnitZ(), 0.5, 48, false}};
  EllipsoidSampler sphere(Eigen::Vector3d::Ones());
  const Outcome o = Tessellate(sphere, circles, kEps);
  std::cout << "tube: " << o.seconds << " s\n";
  ExpectTrimmed(circles, o.t, "tube");
  ExpectOnUnitSphere(circles, o.t, kEps, "tube");
}

TEST(TrimmedTessellationTest, SphereWithThreeHoles) {
  const std::vector<Circle> circles = {
      {Eigen::Vector3d(1, 0.2, 0.1), 0.9, 40, false},
      {Eigen::Vector3d(-0.5, 0.8, -0.3), 0.8, 64, false},
      {Eigen::Vector3d(0.1, -0.7, -0.7), 0.95, 32, false}};
  EllipsoidSampler sphere(Eigen::Vector3d::Ones());
  const Outcome o = Tessellate(sphere, circles, kEps);
  std::cout << "three holes: " << o.seconds << " s\n";
  ExpectTrimmed(circles, o.t, "three holes");
  ExpectOnUnitSphere(circles, o.t, kEps, "three holes");
}

TEST(TrimmedTessellationTest, DiskWhoseHoleIsMoreThanAHemisphere) {
  // The kept disk is a cap of radius acos(0.6) (53 degrees) on an
  // ellipsoid: the hole is the other 80 % of the sphere.
  const std::vector<Circle> circles = {
      {Eigen::Vector3d(0.3, -0.2, 1.0), 0.6, 64, true}};
  EllipsoidSampler ellipsoid(Eigen::Vector3d(1.0, 0.6, 0.4));
  const Outcome o = Tessellate(ellipsoid, circles, kEps);
  std::cout << "disk on ellipsoid: " << o.seconds << " s, " << o.t.faces.rows()
            << " faces\n";
  ExpectTrimmed(circles, o.t, "disk");
  EXPECT_LE(o.t.certified_distance, kEps);
  // On the sphere, with the area oracle.
  EllipsoidSampler sphere(Eigen::Vector3d::Ones());
  const Outcome s = Tessellate(sphere, circles, kEps);
  ExpectTrimmed(circles, s.t, "disk on sphere");
  ExpectOnUnitSphere(circles, s.t, kEps, "disk on sphere");
}

TEST(TrimmedTessellationTest, DenseTrimPoints) {
  // 4000 points on circles of radius 0.05 rad (sides 8e-5 rad long): a hole,
  // and a kept disk whose hole is all the rest of the sphere.
  int64_t samples[2] = {0, 0};
  for (const bool keep_cap : {false, true}) {
    const std::vector<Circle> circles = {
        {Eigen::Vector3d(0.2, 0.3, -1.0), std::cos(0.05), 4000, keep_cap}};
    EllipsoidSampler sphere(Eigen::Vector3d::Ones());
    const Outcome a = Tessellate(sphere, circles, kEps);
    const char* name = keep_cap ? "dense disk" : "dense hole";
    std::cout << name << ": " << a.seconds << " s (simplify "
              << a.t.seconds.simplify << "), " << a.t.samples << " samples, "
              << a.t.faces.rows() << " faces\n";
    ExpectTrimmed(circles, a.t, name);
    EXPECT_LE(a.t.certified_distance, kEps);
    samples[keep_cap] = a.t.samples;
  }
  // Only the kept region is refined: the disk (0.06 % of the sphere) takes
  // far fewer samples than its complement.
  EXPECT_LT(3 * samples[1], samples[0]);
}

TEST(TrimmedTessellationTest, HemisphereOfAGreatCircle) {
  // Every side on one great circle: the trim points are coplanar with the
  // centre, the degenerate case of the Delaunay hull.
  const std::vector<Circle> circles = {
      {Eigen::Vector3d(0.1, -0.2, 1.0), 0.0, 100, true}};
  EllipsoidSampler sphere(Eigen::Vector3d::Ones());
  const Outcome o = Tessellate(sphere, circles, kEps);
  ExpectTrimmed(circles, o.t, "hemisphere");
  ExpectOnUnitSphere(circles, o.t, kEps, "hemisphere");
}

TEST(TrimmedTessellationTest, NearlyCoincidentTrimPoints) {
  // Two consecutive points 1e-11 apart (a scan's boundary, unwelded): the
  // perturbed hull separates them, and the loop is the boundary as always.
  TrimLoop loop = LoopOf({Eigen::Vector3d::UnitZ(), 0.5, 32, false});
  loop.points.row(1) =
      (loop.points.row(0) + 1e-11 * loop.points.row(2)).normalized();
  EllipsoidSampler sphere(Eigen::Vector3d::Ones());
  TessellationOptions options;
  options.tolerance = kEps;
  options.trims = {loop};
  StatusOr<Tessellation> t = TessellateAdaptively(sphere, options);
  ASSERT_TRUE(t.ok()) << t.status().message();
  std::set<int> boundary;
  EXPECT_EQ(CountBoundaryLoops(t->faces, &boundary), 1);
  EXPECT_GE(boundary.size(), 32u);  // every trim point, maybe midpoints
  // Both points of the pair are boundary vertices.
  int pair = 0;
  for (int v : boundary) {
    for (int r = 0; r < 2; ++r) {
      if ((t->directions.row(v) - loop.points.row(r)).norm() == 0.0) ++pair;
    }
  }
  EXPECT_EQ(pair, 2);
}

TEST(TrimmedTessellationTest, SameBytesForAnyThreadCount) {
  const std::vector<Circle> circles = {
      {Eigen::Vector3d::UnitZ(), 0.5, 64, false},
      {Eigen::Vector3d(1, 0, -1), 0.9, 20, false}};
  EllipsoidSampler ellipsoid(Eigen::Vector3d(1.0, 0.7, 0.5));
  const Outcome a = Tessellate(ellipsoid, circles, kEps);
  Outcome b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    b = Tessellate(ellipsoid, circles, kEps);
  }
  EXPECT_EQ(a.t.faces, b.t.faces);
  EXPECT_EQ(a.t.positions, b.t.positions);
  EXPECT_EQ(a.t.normals, b.t.normals);
}

TEST(TrimmedTessellationTest, RefusesTouchingTrimsAndCreasesWithTrims) {
  // Loop 2 has a point exactly at the midpoint of a side of loop 1: the side
  // can never become an edge. One sentence, no endless splitting.
  TrimLoop one = LoopOf({Eigen::Vector3d::UnitZ(), 0.5, 16, false});
  const Eigen::Vector3d m =
      (one.points.row(0) + one.points.row(1)).normalized();
  const Eigen::Vector3d e = m.cross(Eigen::Vector3d::UnitZ()).normalized();
  TrimLoop two;
  two.points.resize(3, 3);
  two.points.row(0) = m.transpose();
  two.points.row(1) =
      (m - 0.1 * Eigen::Vector3d::UnitZ() + 0.05 * e).normalized().transpose();
  two.points.row(2) =
      (m - 0.1 * Eigen::Vector3d::UnitZ() - 0.05 * e).normalized().transpose();
  StatusOr<SphereTriangulation> p = TrimmedPattern({one, two});
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.status().code(), StatusCode::kInvalidInput)
      << p.status().message();

  EllipsoidSampler sphere(Eigen::Vector3d::Ones());
  const SphereTriangulation ico = SphereTriangulation::Icosphere(0);
  TessellationOptions options;
  options.initial_pattern = &ico;
  options.trims = {LoopOf({Eigen::Vector3d::UnitZ(), 0.5, 16, false})};
  StatusOr<Tessellation> t = TessellateAdaptively(sphere, options);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.status().code(), StatusCode::kInvalidArgument);
}

TEST(TrimmedTessellationTest, PatternHasEveryTrimSideAsAChain) {
  const std::vector<TrimLoop> loops = {
      LoopOf({Eigen::Vector3d::UnitZ(), 0.99, 200, false}),
      LoopOf({Eigen::Vector3d(0, 1, 1), 0.0, 7, true})};
  StatusOr<SphereTriangulation> p = TrimmedPattern(loops);
  ASSERT_TRUE(p.ok()) << p.status().message();
  EXPECT_EQ(p->arc_ends().size(), 207u);
  // Every face positive and every arc's interior vertices on its circle.
  for (int f = 0; f < p->num_face_slots(); ++f) {
    EXPECT_TRUE(p->IsPositive(p->face(f)));
  }
  for (int v = 0; v < p->num_vertices(); ++v) {
    const int arc = p->vertex_arc(v);
    if (arc < 0) continue;
    const Eigen::Vector3d a = p->vertex(p->arc_ends()[arc][0]);
    const Eigen::Vector3d b = p->vertex(p->arc_ends()[arc][1]);
    EXPECT_LE(std::abs(p->vertex(v).dot(a.cross(b).normalized())), 1e-15);
  }
  StatusOr<std::vector<char>> kept = KeptFaceSlots(*p);
  ASSERT_TRUE(kept.ok()) << kept.status().message();
}

}  // namespace
}  // namespace sdcb
