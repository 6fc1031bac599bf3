#include "sdcb/core/param/spherical_parameterization.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/param/parameterization_distortion.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "testing/finger_mesh.h"
#include "testing/off_test_mesh.h"

namespace sdcb {
namespace {

TriangleMesh Load(const std::string& name) {
  return testing::LoadOffTestMesh(name);
}

// Independent check of the bijection: unit length, every face positively
// oriented by the exact predicate, spherical areas summing to 4*pi.
void ExpectBijection(const TriangleMesh& mesh, const Eigen::MatrixX3d& sphere) {
  ASSERT_EQ(sphere.rows(), mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    ASSERT_NEAR(sphere.row(v).norm(), 1.0, 1e-12) << v;
  }
  double total = 0.0;
  int flipped = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = sphere.row(mesh.faces(f, 0)).transpose();
    const Eigen::Vector3d b = sphere.row(mesh.faces(f, 1)).transpose();
    const Eigen::Vector3d c = sphere.row(mesh.faces(f, 2)).transpose();
    flipped += Det3Sign(a, b, c) <= 0;
    total += SphericalTriangleArea(a, b, c);
  }
  EXPECT_EQ(flipped, 0);
  EXPECT_NEAR(total, 4.0 * kPi, 1e-8);
}

struct Case {
  const char* mesh;
  double lambda;
};

class BijectionTest : public ::testing::TestWithParam<Case> {};

TEST_P(BijectionTest, NoFlippedTriangles) {
  const TriangleMesh mesh = Load(GetParam().mesh);
  SphericalParameterizationOptions options;
  options.lambda = GetParam().lambda;
  auto param = ParameterizeOnSphere(mesh, options);
  ASSERT_TRUE(param.ok()) << param.status().message();
  ExpectBijection(mesh, param->sphere);
  auto d = MeasureParameterizationDistortion(mesh, param->sphere);
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->flipped_triangles, 0);
}

// CGAL's closed genus-0 meshes up to ~6.5K vertices at the three lambdas
// of the issue; fandisk and bunny00 at lambda = 1 (the bench covers the
// rest; docs/PARAMETERIZATION.md lists the numbers).
INSTANTIATE_TEST_SUITE_P(
    CgalMeshes, BijectionTest,
    ::testing::Values(
        Case{"sphere966.off", 0.2}, Case{"sphere966.off", 1},
        Case{"sphere966.off", 10}, Case{"spool.off", 0.2}, Case{"spool.off", 1},
        Case{"spool.off", 10}, Case{"oblong.off", 0.2}, Case{"oblong.off", 1},
        Case{"oblong.off", 10}, Case{"cube-meshed.off", 0.2},
        Case{"cube-meshed.off", 1}, Case{"cube-meshed.off", 10},
        Case{"ellipe0.003.off", 0.2}, Case{"ellipe0.003.off", 1},
        Case{"ellipe0.003.off", 10}, Case{"blobby.off", 0.2},
        Case{"blobby.off", 1}, Case{"blobby.off", 10}, Case{"cow.off", 0.2},
        Case{"cow.off", 1}, Case{"cow.off", 10}, Case{"fandisk.off", 1},
        // Long thin limbs: regions of the coarse map shrink to
        // ~1e-9 (regression: float determinants lost their
        // sign there and vertex splits found no position).
        Case{"cactus.off", 1}, Case{"dino.off", 1}, Case{"bunny00.off", 1}),
    [](const ::testing::TestParamInfo<Case>& info) {
      char lambda[32];
      std::snprintf(lambda, sizeof(lambda), "%g", info.param.lambda);
      std::string name = std::string(info.param.mesh) + "_lambda_" + lambda;
      for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      }
      return name;
    });

TEST(SphericalParameterization, ResultDoesNotDependOnThreadCount) {
  const TriangleMesh mesh = Load("cow.off");
  SphericalParameterizationOptions one, two;
  one.threads = 1;
  two.threads = 2;
  auto a = ParameterizeOnSphere(mesh, one);
  auto b = ParameterizeOnSphere(mesh, two);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_TRUE(a->sphere == b->sphere);  // bit for bit
}

TEST(SphericalParameterization, LargerLambdaTradesAngleForArea) {
  // Sec. 4.3 / Table 1: more weight on E_area lowers it and raises E_angle.
  const TriangleMesh mesh = Load("cow.off");
  double previous_angle = 0.0, previous_area = 1e300;
  for (double lambda : {0.2, 1.0, 10.0}) {
    SphericalParameterizationOptions options;
    options.lambda = lambda;
    auto param = ParameterizeOnSphere(mesh, options);
    ASSERT_TRUE(param.ok());
    auto d = MeasureParameterizationDistortion(mesh, param->sphere);
    ASSERT_TRUE(d.ok());
    EXPECT_GT(d->angle_distortion_avg, previous_angle) << lambda;
    EXPECT_LT(d->area_distortion_avg, previous_area) << lambda;
    previous_angle = d->angle_distortion_avg;
    previous_area = d->area_distortion_avg;
  }
}

TEST(SphericalParameterization, OptimizationLowersTheEnergy) {
  // The returned energy is eq. (12) at the result: recompute it from the
  // per-face distortions (independent of the optimizer's bookkeeping).
  const TriangleMesh mesh = Load("spool.off");
  auto param = ParameterizeOnSphere(mesh, {});
  ASSERT_TRUE(param.ok());
  auto d = MeasureParameterizationDistortion(mesh, param->sphere);
  ASSERT_TRUE(d.ok());
  double energy = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    energy += d->face_mesh_area[f] * d->face_angle_distortion[f] *
              d->face_area_distortion[f];  // lambda = 1
  }
  EXPECT_NEAR(param->energy, energy, 1e-6 * energy);
  // Lower bound of eq. (12): E_angle, E_area >= 2 (up to O(h^2)) on a mesh
  // of area 4*pi gives 16*pi; a good map is within a small factor of it.
  EXPECT_GT(energy, 0.95 * 16.0 * kPi);
  EXPECT_LT(energy, 1.6 * 16.0 * kPi);
}

// Eq. (12) recomputed from the per-face distortions of `sphere`.
double RecomputedEnergy(const TriangleMesh& mesh,
                        const Eigen::MatrixX3d& sphere, double lambda) {
  auto d = MeasureParameterizationDistortion(mesh, sphere);
  EXPECT_TRUE(d.ok());
  EXPECT_EQ(d->flipped_triangles, 0);
  double energy = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    energy += d->face_mesh_area[f] * d->face_angle_distortion[f] *
              std::pow(d->face_area_distortion[f], lambda);
  }
  return energy;
}

TEST(SphericalParameterization, GlobalStageLowersTheEnergyAndStaysBijective) {
  // The optional global L-BFGS stage starts from the sweeps' result, so it
  // may only lower eq. (12) (recomputed independently from the per-face
  // metrics); at lambda = 10 on the cow the sweeps stall far from a
  // minimum and the global stage must find a clearly lower energy.
  const TriangleMesh mesh = Load("cow.off");
  SphericalParameterizationOptions sweeps_only;
  sweeps_only.lambda = 10.0;
  SphericalParameterizationOptions global = sweeps_only;
  global.global_iterations = 60;
  auto a = ParameterizeOnSphere(mesh, sweeps_only);
  auto b = ParameterizeOnSphere(mesh, global);
  ASSERT_TRUE(a.ok() && b.ok());
  ExpectBijection(mesh, b->sphere);
  const double ea = RecomputedEnergy(mesh, a->sphere, 10.0);
  const double eb = RecomputedEnergy(mesh, b->sphere, 10.0);
  EXPECT_NEAR(b->energy, eb, 1e-6 * eb);
  EXPECT_LT(eb, 0.95 * ea);
  // Same bits with one thread.
  global.threads = 1;
  auto c = ParameterizeOnSphere(mesh, global);
  ASSERT_TRUE(c.ok());
  EXPECT_TRUE(b->sphere == c->sphere);
}

TEST(SphericalParameterization, LargeLevelsStopAtTheirTolerance) {
  // Only levels of more than large_level_vertices use large_level_tolerance:
  // at the cow's vertex count the result is the default's bit for bit; one
  // below it, the finest levels stop at a loose tolerance and end at a
  // clearly higher (recomputed) energy, still a bijection.
  const TriangleMesh mesh = Load("cow.off");
  SphericalParameterizationOptions below, loose;
  below.large_level_vertices = mesh.num_vertices();
  loose.large_level_vertices = 1000;
  loose.large_level_tolerance = 0.05;
  auto a = ParameterizeOnSphere(mesh, {});
  auto b = ParameterizeOnSphere(mesh, below);
  auto c = ParameterizeOnSphere(mesh, loose);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_TRUE(a->sphere == b->sphere);
  ExpectBijection(mesh, c->sphere);
  EXPECT_GT(RecomputedEnergy(mesh, c->sphere, 1.0),
            1.01 * RecomputedEnergy(mesh, a->sphere, 1.0));
}

TEST(SphericalParameterization, LargeLevelsRunFewSweepsAndSkipOneNearTheInput) {
  // The cow (2,904 vertices) from a 150-vertex base: levels of 300, 600,
  // 1,200 and 2,400 vertices, then the input. With levels above 1,000
  // vertices large, the 2,400 one is within sqrt(2) of the input and is not
  // made (one level fewer); one sweep per large level ends at a clearly
  // higher energy than 100, both bijections. With the threshold at the
  // vertex count nothing is large: the default's result bit for bit.
  const TriangleMesh mesh = Load("cow.off");
  SphericalParameterizationOptions plain;
  plain.base_vertices = 150;
  SphericalParameterizationOptions at_count = plain;
  at_count.large_level_vertices = mesh.num_vertices();
  SphericalParameterizationOptions large = plain;
  large.large_level_vertices = 1000;
  large.large_level_tolerance = plain.finest_tolerance;
  large.large_level_sweeps = 100;
  SphericalParameterizationOptions one_sweep = large;
  one_sweep.large_level_sweeps = 1;
  auto a = ParameterizeOnSphere(mesh, plain);
  auto b = ParameterizeOnSphere(mesh, at_count);
  auto c = ParameterizeOnSphere(mesh, large);
  auto d = ParameterizeOnSphere(mesh, one_sweep);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok() && d.ok());
  ASSERT_EQ(a->base_vertices, 150);
  EXPECT_EQ(a->levels, 6);
  EXPECT_TRUE(a->sphere == b->sphere);
  EXPECT_EQ(c->levels, 5);
  EXPECT_EQ(d->levels, 5);
  ExpectBijection(mesh, c->sphere);
  ExpectBijection(mesh, d->sphere);
  EXPECT_GT(RecomputedEnergy(mesh, d->sphere, 1.0),
            1.01 * RecomputedEnergy(mesh, c->sphere, 1.0));
}

// A finger 60 radii long: from the base mesh's vertex of highest degree the
// Tutte embedding shrinks along the finger below double precision (a
// folded triangle); from the graph center it does not.
TEST(SphericalParameterization, LongThinPartEmbedsFromTheGraphCenter) {
  const TriangleMesh mesh = testing::FingerMesh(0.1, 6.0, 0.05);
  ASSERT_GT(mesh.num_vertices(), 6000);
  const auto map = ParameterizeOnSphere(mesh, {});
  ASSERT_TRUE(map.ok()) << map.status().message();
  ExpectBijection(mesh, map->sphere);
}

TEST(SphericalParameterization, RejectsBadInput) {
  SphericalParameterizationOptions options;
  options.lambda = -1.0;
  EXPECT_EQ(
      ParameterizeOnSphere(Load("sphere966.off"), options).status().code(),
      StatusCode::kInvalidArgument);
  const auto genus3 = ParameterizeOnSphere(Load("elephant.off"), {});
  EXPECT_EQ(genus3.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(genus3.status().message().find("genus 3"), std::string::npos);
  EXPECT_EQ(ParameterizeOnSphere(Load("mushroom.off"), {}).status().code(),
            StatusCode::kUnsupported);
}

TEST(SphericalParameterization, CheckBijectionCatchesAFold) {
  const TriangleMesh mesh = Load("sphere966.off");
  Eigen::MatrixX3d sphere = mesh.vertices.rowwise().normalized();
  EXPECT_TRUE(CheckSphericalBijection(mesh, sphere).ok());
  Eigen::MatrixX3d folded = sphere;
  folded.row(mesh.faces(0, 0)) = -folded.row(mesh.faces(0, 0));
  EXPECT_FALSE(CheckSphericalBijection(mesh, folded).ok());
  Eigen::MatrixX3d off = sphere;
  off.row(5) *= 1.0 + 1e-9;
  EXPECT_FALSE(CheckSphericalBijection(mesh, off).ok());
}

}  // namespace
}  // namespace sdcb
