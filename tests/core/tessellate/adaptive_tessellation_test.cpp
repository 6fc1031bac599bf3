#include "sdcb/core/tessellate/adaptive_tessellation.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <iostream>
#include <map>
#include <random>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/mesh/self_intersections.h"
#include "sdcb/core/tessellate/optimal_triangle_count.h"
#include "testing/analytic_surfaces.h"

namespace sdcb {
namespace {

using testing::EllipsoidSampler;

TriangleMesh ToMesh(const Tessellation& t) {
  TriangleMesh m;
  m.vertices = t.positions;
  m.faces = t.faces;
  return m;
}

// Largest distance from `points` to the mesh (CGAL's AABB tree):
// independent of the tessellator's certificate.
double PointsToMesh(const Tessellation& t, const Eigen::MatrixX3d& p) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Triangles = std::vector<K::Triangle_3>;
  using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
  Triangles triangles;
  auto point = [&](int v) {
    return K::Point_3(t.positions(v, 0), t.positions(v, 1), t.positions(v, 2));
  };
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f) {
    triangles.emplace_back(point(t.faces(f, 0)), point(t.faces(f, 1)),
                           point(t.faces(f, 2)));
  }
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  double worst = 0.0;
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    const double d2 =
        tree.squared_distance(K::Point_3(p(i, 0), p(i, 1), p(i, 2)));
    worst = std::max(worst, std::sqrt(d2));
  }
  return worst;
}

// Largest distance from dense surface samples (the barycentric lattice of
// order `order` of every domain face, mapped by the surface) to the mesh.
double SurfaceToMesh(const Tessellation& t, const SurfaceSampler& s,
                     int order) {
  std::vector<Eigen::Vector3d> directions;
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f) {
    for (int i = 0; i <= order; ++i)
      for (int j = 0; i + j <= order; ++j) {
        const double a = double(i) / order, b = double(j) / order,
                     c = 1.0 - a - b;
        directions.push_back((a * t.directions.row(t.faces(f, 0)) +
                              b * t.directions.row(t.faces(f, 1)) +
                              c * t.directions.row(t.faces(f, 2)))
                                 .normalized()
                                 .transpose());
      }
  }
  Eigen::MatrixX3d d(directions.size(), 3), p;
  for (size_t i = 0; i < directions.size(); ++i) d.row(i) = directions[i];
  s.Sample(d, &p, nullptr);
  return PointsToMesh(t, p);
}

// The larger of the distance from the flat triangles to the ellipsoid
// (dense barycentric samples, exact point-ellipsoid distance) and
// SurfaceToMesh.
double MeasuredHausdorff(const Tessellation& t, const EllipsoidSampler& s,
                         int order) {
  double worst = SurfaceToMesh(t, s, order);
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f) {
    for (int i = 0; i <= order; ++i)
      for (int j = 0; i + j <= order; ++j) {
        const Eigen::Vector3d x =
            (i * t.positions.row(t.faces(f, 0)) +
             j * t.positions.row(t.faces(f, 1)) +
             (order - i - j) * t.positions.row(t.faces(f, 2)))
                .transpose() /
            double(order);
        worst = std::max(worst, s.Distance(x));
      }
  }
  return worst;
}

TEST(AdaptiveTessellationTest, SphereIsClosedWithinToleranceNearOptimum) {
  const double r = 2.0, eps = 1e-3;
  EllipsoidSampler sphere(Eigen::Vector3d(r, r, r));
  TessellationOptions options;
  options.tolerance = eps;
  StatusOr<Tessellation> t = TessellateAdaptively(sphere, options);
  ASSERT_TRUE(t.ok()) << t.status().message();
  StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(ToMesh(*t));
  ASSERT_TRUE(topology.ok());
  EXPECT_TRUE(topology->ok) << DescribeTopologyProblem(*topology);
  // Flat points are inside the sphere: their distance is r - |x|.
  double worst = 0.0;
  for (Eigen::Index f = 0; f < t->faces.rows(); ++f) {
    for (int i = 0; i <= 12; ++i)
      for (int j = 0; i + j <= 12; ++j) {
        const Eigen::Vector3d x =
            (i * t->positions.row(t->faces(f, 0)) +
             j * t->positions.row(t->faces(f, 1)) +
             (12 - i - j) * t->positions.row(t->faces(f, 2))) /
            12.0;
        worst = std::max(worst, r - x.norm());
      }
  }
  EXPECT_LE(worst, eps);
  EXPECT_LE(t->certified_distance, eps);
  EXPECT_GE(worst, 0.5 * eps);  // not grossly over-refined
  EXPECT_EQ(t->uncertified_faces, 0);
  // N_opt(eps) = 8 pi r / (3 sqrt(3) eps) for a sphere.
  const double optimum = 8.0 * kPi * r / (3.0 * std::sqrt(3.0) * eps);
  const double ratio = t->faces.rows() / optimum;
  std::cout << "sphere: " << t->faces.rows() << " faces, " << ratio
            << " x N_opt, measured " << worst << "\n";
  EXPECT_GE(ratio, 1.0);
  // Bisection alone gives 2.12 here (a uniform level sits between two
  // levels); the greedy simplification of the samples does better.
  EXPECT_LE(ratio, 1.95) << t->faces.rows() << " faces";
  // Vertices on the sphere with the analytic (radial) normals.
  for (Eigen::Index v = 0; v < t->positions.rows(); ++v) {
    EXPECT_NEAR(t->positions.row(v).norm(), r, 1e-12);
    EXPECT_NEAR(t->normals.row(v).dot(t->directions.row(v)), 1.0, 1e-12);
  }
}

TEST(AdaptiveTessellationTest, EllipsoidWithinToleranceBothWays) {
  EllipsoidSampler ellipsoid(Eigen::Vector3d(1.0, 0.5, 0.2));
  for (double eps : {1e-2, 1e-3}) {
    TessellationOptions options;
    options.tolerance = eps;
    StatusOr<Tessellation> t = TessellateAdaptively(ellipsoid, options);
    ASSERT_TRUE(t.ok());
    StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(ToMesh(*t));
    ASSERT_TRUE(topology.ok());
    EXPECT_TRUE(topology->ok) << DescribeTopologyProblem(*topology);
    const double measured = MeasuredHausdorff(*t, ellipsoid, 10);
    EXPECT_LE(measured, eps) << "eps " << eps;
    EXPECT_GE(measured, 0.4 * eps) << "eps " << eps;
  }
}

TEST(AdaptiveTessellationTest, AngleToleranceHolds) {
  EllipsoidSampler ellipsoid(Eigen::Vector3d(1.0, 0.5, 0.2));
  TessellationOptions options;
  options.tolerance = 0.05;  // coarse: the angle decides
  options.angle_degrees = 10.0;
  StatusOr<Tessellation> t = TessellateAdaptively(ellipsoid, options);
  ASSERT_TRUE(t.ok());
  // Independent: the analytic normal at dense points of each face's domain
  // against the flat face normal, for faces larger than the tolerance.
  for (Eigen::Index f = 0; f < t->faces.rows(); ++f) {
    const Eigen::Vector3d a = t->positions.row(t->faces(f, 0)),
                          b = t->positions.row(t->faces(f, 1)),
                          c = t->positions.row(t->faces(f, 2));
    if (std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()}) <=
        options.tolerance) {
      continue;
    }
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    Eigen::MatrixX3d d(66, 3), p, normals;
    int row = 0;
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; i + j <= 10; ++j) {
        d.row(row++) = (i * t->directions.row(t->faces(f, 0)) +
                        j * t->directions.row(t->faces(f, 1)) +
                        (10 - i - j) * t->directions.row(t->faces(f, 2)))
                           .normalized();
      }
    ellipsoid.Sample(d, &p, &normals);
    for (int k = 0; k < 66; ++k) {
      // The lattice of order 6 misses a little between its points.
      EXPECT_GE(normals.row(k).dot(n), std::cos(10.5 * kPi / 180.0));
    }
  }
}

TEST(AdaptiveTessellationTest, DeterministicAndOptionsChecked) {
  EllipsoidSampler ellipsoid(Eigen::Vector3d(1.0, 0.7, 0.4));
  TessellationOptions options;
  options.tolerance = 2e-3;
  StatusOr<Tessellation> a = TessellateAdaptively(ellipsoid, options);
  StatusOr<Tessellation> b = TessellateAdaptively(ellipsoid, options);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->faces, b->faces);
  EXPECT_EQ(a->positions, b->positions);
  options.tolerance = 0.0;
  EXPECT_FALSE(TessellateAdaptively(ellipsoid, options).ok());
  options.tolerance = 1e-3;
  options.angle_degrees = 0.0;
  EXPECT_FALSE(TessellateAdaptively(ellipsoid, options).ok());
  options.angle_degrees = 20.0;
  options.max_faces = 100;
  StatusOr<Tessellation> capped = TessellateAdaptively(ellipsoid, options);
  EXPECT_EQ(capped.status().code(), StatusCode::kInvalidInput);
}

// The unit sphere torn along its equator: the southern half has radius 1.2.
// No refinement of the domain makes a face across the tear pass, so only
// the budgets stop the tessellator.
class TornSphereSampler : public SurfaceSampler {
 public:
  void Sample(const Eigen::MatrixX3d& directions, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override {
    *positions = directions;
    for (Eigen::Index i = 0; i < directions.rows(); ++i) {
      if (directions(i, 2) < 0.0) positions->row(i) *= 1.2;
    }
    if (normals) *normals = directions;
  }
};

TEST(AdaptiveTessellationTest, SampleBudgetStopsASurfaceThatTears) {
  TornSphereSampler torn;
  TessellationOptions options;
  options.tolerance = 1e-3;
  options.max_samples = 200'000;
  StatusOr<Tessellation> t = TessellateAdaptively(torn, options);
  ASSERT_EQ(t.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(t.status().message().find("more than 200000 samples"),
            std::string::npos)
      << t.status().message();
  options.max_samples = 0;
  EXPECT_EQ(TessellateAdaptively(torn, options).status().code(),
            StatusCode::kInvalidArgument);
}

// Every face positively oriented on the domain (no folded-over domain
// triangle), Euler characteristic 2, spherical areas summing to 4 pi.
void ExpectDomainIsASphere(const Tessellation& t) {
  double area = 0.0;
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f) {
    const Eigen::Vector3d a = t.directions.row(t.faces(f, 0)),
                          b = t.directions.row(t.faces(f, 1)),
                          c = t.directions.row(t.faces(f, 2));
    ASSERT_GT(a.cross(b).dot(c), 0.0) << "domain face " << f << " inverted";
    area += 2.0 *
            std::atan2(a.dot(b.cross(c)), 1.0 + a.dot(b) + b.dot(c) + c.dot(a));
  }
  EXPECT_NEAR(area, 4.0 * kPi, 1e-8);
  std::map<std::pair<int, int>, int> edges;
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = t.faces(f, k), b = t.faces(f, (k + 1) % 3);
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [e, n] : edges) EXPECT_EQ(n, 2);
  EXPECT_EQ(t.positions.rows() - static_cast<Eigen::Index>(edges.size()) +
                t.faces.rows(),
            2);
}

// The domain is a sphere (above); the surface mesh is a closed, manifold
// genus-0 mesh (topology analysis) with no intersecting pair of triangles
// (CGAL).
void ExpectClosedSphereWithoutCrossings(const Tessellation& t) {
  ExpectDomainIsASphere(t);
  const TriangleMesh mesh = ToMesh(t);
  StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(mesh);
  ASSERT_TRUE(topology.ok());
  EXPECT_TRUE(topology->ok) << DescribeTopologyProblem(*topology);
  EXPECT_EQ(topology->genus, 0);
  StatusOr<SelfIntersectionReport> crossings = FindSelfIntersections(mesh);
  ASSERT_TRUE(crossings.ok());
  EXPECT_TRUE(crossings->checked);
  EXPECT_EQ(crossings->intersecting_pairs, 0);
}

void ExpectSameTessellation(const Tessellation& a, const Tessellation& b) {
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.directions, b.directions);
  EXPECT_EQ(a.positions, b.positions);
}

TEST(AdaptiveTessellationTest, RemeshedEllipsoidNearOptimumWithinTolerance) {
  // An anisotropic convex surface: N_opt by quadrature on the output; the
  // measured distance (dense, both ways, exact point-ellipsoid distance)
  // within eps; the count below what bisection alone gives (2.18 x N_opt).
  EllipsoidSampler ellipsoid(Eigen::Vector3d(1.0, 0.7, 0.4));
  const double eps = 2e-4;
  TessellationOptions options;
  options.tolerance = eps;
  StatusOr<Tessellation> t = TessellateAdaptively(ellipsoid, options);
  ASSERT_TRUE(t.ok()) << t.status().message();
  ExpectDomainIsASphere(*t);
  StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(ToMesh(*t));
  ASSERT_TRUE(topology.ok());
  EXPECT_TRUE(topology->ok) << DescribeTopologyProblem(*topology);
  EXPECT_EQ(t->uncertified_faces, 0);
  const double measured = MeasuredHausdorff(*t, ellipsoid, 8);
  EXPECT_LE(measured, eps);
  EXPECT_GE(measured, 0.7 * eps);  // the budget is used
  StatusOr<CurvatureIntegrals> k =
      IntegrateCurvature(ellipsoid, t->directions, t->faces, 1);
  ASSERT_TRUE(k.ok());
  const double ratio = t->faces.rows() / OptimalTriangleCount(*k, eps);
  std::cout << "ellipsoid: " << t->faces.rows() << " faces, " << ratio
            << " x N_opt, measured " << measured / eps << " eps\n";
  EXPECT_GE(ratio, 1.0);
  EXPECT_LE(ratio, 1.9);
}

TEST(AdaptiveTessellationTest, ShearedParameterizationCostsLittle) {
  // The certificate measures the distance from the surface to the mesh near
  // each face (its own triangle or, for points the parameterization shears
  // beyond its edges, its neighbours'), not only to the triangle of the
  // face a point's domain triangle maps to: a parameterization that shears
  // patches sideways (the twisted ellipsoid: the same surface) must not
  // multiply the triangles. Independent checks: the distance measured
  // densely (exact point-ellipsoid distance one way, CGAL's AABB tree the
  // other) within the tolerance; no face turned over against the analytic
  // normal (the ellipsoid's gradient at the vertex) and no pair of
  // triangles intersecting (CGAL).
  const Eigen::Vector3d axes(1.0, 0.7, 0.4);
  const double eps = 1e-3;
  TessellationOptions options;
  options.tolerance = eps;
  EllipsoidSampler plain(axes);
  testing::TwistedEllipsoidSampler twisted(axes, 3.0);
  StatusOr<Tessellation> a = TessellateAdaptively(plain, options);
  StatusOr<Tessellation> b = TessellateAdaptively(twisted, options);
  ASSERT_TRUE(a.ok() && b.ok());
  ExpectClosedSphereWithoutCrossings(*b);
  EXPECT_EQ(b->uncertified_faces, 0);
  for (Eigen::Index f = 0; f < b->faces.rows(); ++f) {
    const Eigen::Vector3d p0 = b->positions.row(b->faces(f, 0)),
                          p1 = b->positions.row(b->faces(f, 1)),
                          p2 = b->positions.row(b->faces(f, 2));
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
    for (const Eigen::Vector3d& p : {p0, p1, p2}) {
      const Eigen::Vector3d gradient = p.cwiseQuotient(axes.cwiseProduct(axes));
      ASSERT_GT(n.dot(gradient), 0.0) << "face " << f << " turned over";
    }
  }
  const double measured = MeasuredHausdorff(*b, twisted, 12);
  EXPECT_LE(measured, eps);
  EXPECT_GE(measured, 0.7 * eps);
  std::cout << "twisted ellipsoid: " << b->faces.rows() << " faces against "
            << a->faces.rows() << " untwisted, measured " << measured / eps
            << " eps\n";
  EXPECT_LE(b->faces.rows(), 1.3 * a->faces.rows());
}

TEST(AdaptiveTessellationTest, NarrowBumpsWithinToleranceMeasuredDensely) {
  // A sphere with 40 narrow bumps (curvature changing sign within a few
  // faces): the tessellation certifies on dense surface samples and a
  // lattice per final face, and neither holds a bump's top for sure. The
  // surface's largest distance to the mesh, measured densely (CGAL's AABB
  // tree: an order-12 lattice of every face plus a fine grid over every
  // bump), and the flat triangles' distance to the surface (bounded by
  // their radial offset |x| - r(x / |x|), which is at least the distance)
  // are within eps; the mesh is a closed genus-0 manifold without
  // intersecting triangles; 1 and 2 threads give the same output.
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Vector3d> centres;
  for (int k = 0; k < 40; ++k) {
    centres.push_back(
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized());
  }
  const double height = 3e-3, width = 1e-3;
  const testing::BumpySphereSampler surface(centres, height, width);
  const double eps = 1e-3;
  std::vector<Eigen::Vector3d> around;
  for (const Eigen::Vector3d& c : centres) {
    const Eigen::Vector3d a = c.unitOrthogonal(), b = c.cross(a);
    const double reach = 4.0 * std::sqrt(width);
    for (int i = -40; i <= 40; ++i)
      for (int j = -40; j <= 40; ++j) {
        around.push_back((c + reach * (i * a + j * b) / 40.0).normalized());
      }
  }
  Eigen::MatrixX3d directions(around.size(), 3), peaks;
  for (size_t i = 0; i < around.size(); ++i) directions.row(i) = around[i];
  surface.Sample(directions, &peaks, nullptr);
  TessellationOptions options;
  options.tolerance = eps;
  StatusOr<Tessellation> t = Tessellation();
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    t = TessellateAdaptively(surface, options);
  }
  StatusOr<Tessellation> one = Tessellation();
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = TessellateAdaptively(surface, options);
  }
  ASSERT_TRUE(t.ok() && one.ok());
  ExpectSameTessellation(*t, *one);
  ExpectClosedSphereWithoutCrossings(*t);
  EXPECT_EQ(t->uncertified_faces, 0);
  const double surface_to_mesh =
      std::max(SurfaceToMesh(*t, surface, 12), PointsToMesh(*t, peaks));
  double flat_to_surface = 0.0;
  const int order = 12;
  std::vector<Eigen::Vector3d> flat;
  for (Eigen::Index f = 0; f < t->faces.rows(); ++f) {
    for (int i = 0; i <= order; ++i)
      for (int j = 0; i + j <= order; ++j) {
        flat.push_back((i * t->positions.row(t->faces(f, 0)) +
                        j * t->positions.row(t->faces(f, 1)) +
                        (order - i - j) * t->positions.row(t->faces(f, 2)))
                           .transpose() /
                       double(order));
      }
  }
  Eigen::MatrixX3d radial(flat.size(), 3), on_surface;
  for (size_t i = 0; i < flat.size(); ++i) {
    radial.row(i) = flat[i].normalized().transpose();
  }
  surface.Sample(radial, &on_surface, nullptr);
  for (size_t i = 0; i < flat.size(); ++i) {
    flat_to_surface = std::max(
        flat_to_surface, std::abs(flat[i].norm() - on_surface.row(i).norm()));
  }
  std::cout << "bumpy sphere: " << t->faces.rows() << " faces, surface to "
            << "mesh " << surface_to_mesh / eps << " eps, mesh to surface "
            << flat_to_surface / eps << " eps, certified "
            << t->certified_distance / eps << " eps\n";
  EXPECT_LE(surface_to_mesh, eps);
  EXPECT_LE(flat_to_surface, eps);
  EXPECT_LE(t->certified_distance, eps);
}

TEST(AdaptiveTessellationTest, SameBytesForAnyThreadCount) {
  EllipsoidSampler ellipsoid(Eigen::Vector3d(1.0, 0.6, 0.3));
  TessellationOptions options;
  options.tolerance = 1e-3;
  StatusOr<Tessellation> many = TessellateAdaptively(ellipsoid, options);
  tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
  StatusOr<Tessellation> one = TessellateAdaptively(ellipsoid, options);
  ASSERT_TRUE(many.ok() && one.ok());
  EXPECT_EQ(many->faces, one->faces);
  EXPECT_EQ(many->directions, one->directions);
  EXPECT_EQ(many->positions, one->positions);
  EXPECT_EQ(many->normals, one->normals);
}

TEST(AdaptiveTessellationTest, UniformLevels) {
  EXPECT_EQ(UniformLevelForVertices(12), 0);
  EXPECT_EQ(UniformLevelForVertices(40962), 6);
  EXPECT_EQ(UniformLevelForVertices(30000), 6);
  EllipsoidSampler sphere(Eigen::Vector3d(1, 1, 1));
  const Tessellation t = TessellateUniformly(sphere, 3);
  EXPECT_EQ(t.positions.rows(), 642);
  EXPECT_EQ(t.faces.rows(), 1280);
}

TEST(OptimalTriangleCountTest, SphereClosedForm) {
  const double r = 3.0;
  EllipsoidSampler sphere(Eigen::Vector3d(r, r, r));
  const Tessellation coarse = TessellateUniformly(sphere, 4);
  StatusOr<CurvatureIntegrals> k =
      IntegrateCurvature(sphere, coarse.directions, coarse.faces, 1);
  ASSERT_TRUE(k.ok());
  // Inscribed flat triangles: the area converges to 4 pi r^2 from below.
  EXPECT_NEAR(k->area, 4 * kPi * r * r, 2e-3 * 4 * kPi * r * r);
  EXPECT_NEAR(k->convex, 4 * kPi * r, 2e-3 * 4 * kPi * r);
  EXPECT_EQ(k->saddle, 0.0);
  EXPECT_NEAR(OptimalTriangleCount(*k, 1e-3), 4.8368 * r / 1e-3,
              3e-3 * 4.8368 * r / 1e-3);
}

// max |q - L| over a triangle for q = (x^2 - y^2) / 2, L its linear
// interpolant, by dense sampling (the brute-force oracle).
double SaddleError(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                   const Eigen::Vector2d& c) {
  auto q = [](const Eigen::Vector2d& p) {
    return 0.5 * (p.x() * p.x() - p.y() * p.y());
  };
  double worst = 0.0;
  const int n = 60;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double u = double(i) / n, v = double(j) / n, w = 1 - u - v;
      const Eigen::Vector2d p = u * a + v * b + w * c;
      worst =
          std::max(worst, std::abs(q(p) - (u * q(a) + v * q(b) + w * q(c))));
    }
  return worst;
}

TEST(OptimalTriangleCountTest, SaddleConstantIsTheBestAreaPerError) {
  // The claimed optimum: edges (s, 0), (-s/2, sqrt(5) s / 2) has area per
  // error 2 sqrt 5 (N = integral / (2 sqrt 5 eps)).
  const double s = 1.0;
  const Eigen::Vector2d a(0, 0), b(s, 0), c(s / 2, std::sqrt(5.0) * s / 2);
  const double area =
      0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  EXPECT_NEAR(area / SaddleError(a, b, c), 2 * std::sqrt(5.0), 1e-6);
  // No random triangle does better (the metric is invariant under
  // hyperbolic rotations, so random shapes cover all cases).
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  double best = 0.0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector2d p(g(rng), g(rng)), q(g(rng), g(rng)),
        r(g(rng), g(rng));
    const double ar =
        0.5 * std::abs((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
    best = std::max(best, ar / SaddleError(p, q, r));
  }
  EXPECT_LE(best, 2 * std::sqrt(5.0) * (1 + 1e-3));
  EXPECT_GE(best, 0.5 * 2 * std::sqrt(5.0));
  EXPECT_NEAR(kSaddleTriangleConstant, 1.0 / (2.0 * std::sqrt(5.0)), 1e-15);
  EXPECT_NEAR(kConvexTriangleConstant, 2.0 / (3.0 * std::sqrt(3.0)), 1e-15);
}

}  // namespace
}  // namespace sdcb
