// Tests of converters/cage/limit_surface: OpenSubdiv Bfr's limit stencils
// against OpenSubdiv Far's uniform refinement and exact limit masks (an
// independent code path), and the stencils' affine invariance.
#include "sdcb/converters/cage/limit_surface.h"

#include <gtest/gtest.h>

#include <random>

#include "sdcb/core/cage/sphere_cage_topology.h"
#include "testing/far_refinement.h"

namespace sdcb {
namespace {

// A cage on the sphere with extraordinary vertices of several valences and
// the closure templates (level 1 plus two rounds of local refinement),
// vertices jittered.
struct TestCage {
  SphereCage layout;
  Eigen::MatrixX3d positions;
  std::vector<std::vector<int>> faces;
};

TestCage MakeTestCage(CageCellShape shape) {
  auto topology = SphereCageTopology::Create(shape, 1);
  for (int round = 0; round < 2; ++round) {
    std::vector<int> cells;
    for (int f = 0; f < topology.cage().num_faces(); f += 3) {
      cells.push_back(topology.cage().face_cell[f]);
    }
    topology.Refine(cells);
  }
  TestCage t;
  t.layout = topology.cage();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  t.positions = t.layout.sphere_points;
  for (Eigen::Index i = 0; i < t.positions.rows(); ++i) {
    for (int k = 0; k < 3; ++k) t.positions(i, k) += jitter(rng);
  }
  for (const auto& f : t.layout.faces) {
    t.faces.emplace_back(f.begin(), f.begin() + t.layout.face_size);
  }
  return t;
}

class LimitSurfaceTest : public ::testing::TestWithParam<CageCellShape> {};

TEST_P(LimitSurfaceTest, StencilsAreAffineInvariant) {
  const TestCage t = MakeTestCage(GetParam());
  const bool loop = GetParam() == CageCellShape::kTriangle;
  auto limit = LimitSurface::Create(
      loop ? SubdivisionScheme::kLoop : SubdivisionScheme::kCatmullClark,
      t.layout.num_vertices(), t.layout.faces);
  ASSERT_TRUE(limit.ok()) << limit.status().message();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  int irregular = 0;
  LimitStencil s;
  for (int f = 0; f < limit->num_faces(); ++f) {
    irregular += !limit->IsRegular(f);
    double u = unit(rng), v = unit(rng);
    if (loop && u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    limit->Stencil(f, u, v, &s);
    double sum = 0, sum_u = 0, sum_v = 0;
    for (size_t k = 0; k < s.indices.size(); ++k) {
      sum += s.position[k];
      sum_u += s.du[k];
      sum_v += s.dv[k];
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_NEAR(sum_u, 0.0, 1e-10);
    EXPECT_NEAR(sum_v, 0.0, 1e-10);
  }
  // The cage does exercise extraordinary vertices.
  EXPECT_GT(irregular, 10);
}

// Far refines the cage once and evaluates the level-1 vertices at the limit:
// those are the limit surface at the face centres (Catmull-Clark), the edge
// midpoints and the corners of the level-0 faces.
TEST_P(LimitSurfaceTest, MatchesFarLimitOfTheFirstLevel) {
  namespace osd = OpenSubdiv;
  const TestCage t = MakeTestCage(GetParam());
  const bool loop = GetParam() == CageCellShape::kTriangle;
  auto limit = LimitSurface::Create(
      loop ? SubdivisionScheme::kLoop : SubdivisionScheme::kCatmullClark,
      t.layout.num_vertices(), t.layout.faces);
  ASSERT_TRUE(limit.ok());
  const testing::FarRefined far =
      testing::RefineWithFar(loop, t.positions, t.faces, 1);
  auto refiner =
      testing::MakeFarRefiner(loop, t.layout.num_vertices(), t.faces);
  refiner->RefineUniform(osd::Far::TopologyRefiner::UniformOptions(1));
  const osd::Far::TopologyLevel& base = refiner->GetLevel(0);
  const double corner_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const double tri_uv[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  double worst = 0;
  int compared = 0;
  for (int f = 0; f < limit->num_faces(); ++f) {
    const int n = loop ? 3 : 4;
    const auto edges = base.GetFaceEdges(f);
    for (int k = 0; k < n; ++k) {
      const double* a = loop ? tri_uv[k] : corner_uv[k];
      const double* b = loop ? tri_uv[(k + 1) % 3] : corner_uv[(k + 1) % 4];
      // Corner k: the child of vertex k.
      const int vc = base.GetVertexChildVertex(t.faces[f][k]);
      worst = std::max(worst, (limit->Evaluate(f, a[0], a[1], t.positions) -
                               far.limit.row(vc).transpose())
                                  .norm());
      // Edge k (corner k to k + 1): the child of the edge.
      const int ec = base.GetEdgeChildVertex(edges[k]);
      worst =
          std::max(worst, (limit->Evaluate(f, 0.5 * (a[0] + b[0]),
                                           0.5 * (a[1] + b[1]), t.positions) -
                           far.limit.row(ec).transpose())
                              .norm());
      compared += 2;
    }
    if (!loop) {
      const int fc = base.GetFaceChildVertex(f);
      worst = std::max(worst, (limit->Evaluate(f, 0.5, 0.5, t.positions) -
                               far.limit.row(fc).transpose())
                                  .norm());
      ++compared;
    }
  }
  EXPECT_GT(compared, 500);
  EXPECT_LT(worst, 1e-10);
}

// PreparedLimit (Bfr's patch points) evaluates what the stencils give:
// positions and derivatives at random parameters of every face, the
// irregular ones included.
TEST_P(LimitSurfaceTest, PreparedLimitEqualsTheStencils) {
  const TestCage t = MakeTestCage(GetParam());
  const bool loop = GetParam() == CageCellShape::kTriangle;
  auto limit = LimitSurface::Create(
      loop ? SubdivisionScheme::kLoop : SubdivisionScheme::kCatmullClark,
      t.layout.num_vertices(), t.layout.faces);
  ASSERT_TRUE(limit.ok());
  const PreparedLimit prepared(*limit, t.positions);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double worst = 0;
  int irregular = 0;
  for (int f = 0; f < limit->num_faces(); ++f) {
    irregular += !limit->IsRegular(f);
    for (int s = 0; s < 5; ++s) {
      double u = uniform(rng), v = uniform(rng);
      if (loop && u + v > 1) {
        u = 1 - u;
        v = 1 - v;
      }
      Eigen::Vector3d du, dv, eu, ev;
      const Eigen::Vector3d p = limit->Evaluate(f, u, v, t.positions, &du, &dv);
      const Eigen::Vector3d q = prepared.Evaluate(f, u, v, &eu, &ev);
      worst =
          std::max({worst, (p - q).norm(), (du - eu).norm(), (dv - ev).norm()});
    }
  }
  EXPECT_GT(irregular, 0);
  EXPECT_LT(worst, 1e-12);
}

TEST(LimitSurfaceCreateTest, RejectsBadTopology) {
  // A face referring to a missing vertex; an open cage (one quad).
  EXPECT_FALSE(
      LimitSurface::Create(SubdivisionScheme::kCatmullClark, 4, {{0, 1, 2, 7}})
          .ok());
  EXPECT_FALSE(
      LimitSurface::Create(SubdivisionScheme::kCatmullClark, 4, {}).ok());
}

INSTANTIATE_TEST_SUITE_P(Schemes, LimitSurfaceTest,
                         ::testing::Values(CageCellShape::kQuad,
                                           CageCellShape::kTriangle));

}  // namespace
}  // namespace sdcb
