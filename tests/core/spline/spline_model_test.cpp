// Tests core/spline_model.*: the normalizing transform against the closed
// form of a box, the mesh hash against its byte-level definition and
// published FNV-1a vectors, and every rule of ValidateSplineModel.
#include "sdcb/core/spline/spline_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "testing/spline_model_fixture.h"

namespace sdcb {
namespace {

using testing::MakeTestModel;

TriangleMesh Tetrahedron() {
  TriangleMesh m;
  m.vertices.resize(4, 3);
  m.vertices << 0.5, -1.25, 3.0,  //
      -7.0, 0.0, 1e-3,            //
      2.0, 4.0, -0.0,             //
      1.0 / 3.0, 2.0, 5.5;
  m.faces.resize(4, 3);
  m.faces << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
  return m;
}

TEST(NormalizingTransformTest, BoxClosedForm) {
  // Corners of [1,3] x [-2,6] x [0,1] plus interior points: centre (2,2,0.5),
  // largest side 8.
  TriangleMesh mesh;
  mesh.vertices.resize(10, 3);
  int row = 0;
  for (double x : {1.0, 3.0}) {
    for (double y : {-2.0, 6.0}) {
      for (double z : {0.0, 1.0}) mesh.vertices.row(row++) << x, y, z;
    }
  }
  mesh.vertices.row(row++) << 2.5, 0.0, 0.25;
  mesh.vertices.row(row++) << 1.5, 5.0, 0.75;
  StatusOr<NormalizingTransform> t = ComputeNormalizingTransform(mesh);
  ASSERT_TRUE(t.ok()) << t.status().message();
  EXPECT_EQ(t->scale, 8.0);
  EXPECT_EQ(t->translation, Eigen::Vector3d(2.0, 2.0, 0.5));

  const Eigen::MatrixX3d n = t->ToNormalized(mesh.vertices);
  // The normalized box is centred, its largest side is exactly 1.
  EXPECT_EQ(n.colwise().maxCoeff(), Eigen::RowVector3d(0.125, 0.5, 0.0625));
  EXPECT_EQ(n.colwise().minCoeff(), Eigen::RowVector3d(-0.125, -0.5, -0.0625));
  EXPECT_EQ(n(8, 0), (2.5 - 2.0) / 8.0);
  EXPECT_EQ(n(9, 1), (5.0 - 2.0) / 8.0);
  // Inverse: input = scale * normalized + translation (exact here: powers of
  // two).
  EXPECT_EQ(t->ToInput(n), mesh.vertices);
}

TEST(NormalizingTransformTest, MatchesBruteForceBoundingBox) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-50.0, 80.0);
  TriangleMesh mesh;
  mesh.vertices.resize(200, 3);
  for (int i = 0; i < 200; ++i) {
    mesh.vertices.row(i) << u(rng), 0.1 * u(rng), 0.01 * u(rng);
  }
  double lo[3], hi[3];
  for (int c = 0; c < 3; ++c) {
    lo[c] = hi[c] = mesh.vertices(0, c);
    for (int i = 1; i < 200; ++i) {
      lo[c] = std::min(lo[c], mesh.vertices(i, c));
      hi[c] = std::max(hi[c], mesh.vertices(i, c));
    }
  }
  StatusOr<NormalizingTransform> t = ComputeNormalizingTransform(mesh);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->scale, hi[0] - lo[0]);  // x has the largest spread
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(t->translation[c], 0.5 * (lo[c] + hi[c]));
  }
  const Eigen::MatrixX3d back = t->ToInput(t->ToNormalized(mesh.vertices));
  EXPECT_LT((back - mesh.vertices).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::MatrixX3d n = t->ToNormalized(mesh.vertices);
  EXPECT_NEAR(n.col(0).maxCoeff() - n.col(0).minCoeff(), 1.0, 1e-15);
}

TEST(NormalizingTransformTest, RejectsDegenerateMeshes) {
  TriangleMesh empty;
  EXPECT_EQ(ComputeNormalizingTransform(empty).status().code(),
            StatusCode::kInvalidInput);
  TriangleMesh point;
  point.vertices = Eigen::MatrixX3d::Constant(3, 3, 2.0);
  const Status s = ComputeNormalizingTransform(point).status();
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("single point"), std::string::npos);
  TriangleMesh nan = Tetrahedron();
  nan.vertices(2, 1) = std::nan("");
  EXPECT_EQ(ComputeNormalizingTransform(nan).status().code(),
            StatusCode::kInvalidInput);
}

TEST(MeshHashTest, Fnv1aPublishedVectors) {
  EXPECT_EQ(Fnv1a64("", 0), 0xcbf29ce484222325ULL);
  EXPECT_EQ(Fnv1a64("a", 1), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(Fnv1a64("foobar", 6), 0x85944171f73967e8ULL);
}

// The byte sequence of HashTriangleMesh's definition, built independently.
std::string HashInputBytes(const TriangleMesh& m) {
  std::string bytes;
  const auto put = [&](uint64_t v, int n) {
    for (int i = 0; i < n; ++i)
      bytes += static_cast<char>((v >> (8 * i)) & 0xFF);
  };
  put(m.vertices.rows(), 8);
  put(m.faces.rows(), 8);
  for (int i = 0; i < m.vertices.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      uint64_t bits;
      const double d = m.vertices(i, c);
      std::memcpy(&bits, &d, 8);
      put(bits, 8);
    }
  }
  for (int i = 0; i < m.faces.rows(); ++i) {
    for (int c = 0; c < 3; ++c) put(static_cast<uint32_t>(m.faces(i, c)), 4);
  }
  return bytes;
}

TEST(MeshHashTest, MatchesDefinition) {
  const TriangleMesh mesh = Tetrahedron();
  const std::string bytes = HashInputBytes(mesh);
  ASSERT_EQ(bytes.size(), 16u + 4 * 24 + 4 * 12);
  EXPECT_EQ(HashTriangleMesh(mesh), Fnv1a64(bytes.data(), bytes.size()));
  EXPECT_EQ(HashTriangleMesh(TriangleMesh()),
            Fnv1a64(std::string(16, '\0').data(), 16));
}

TEST(MeshHashTest, EqualMeshesHashEqualAnyChangeDiffers) {
  const TriangleMesh mesh = Tetrahedron();
  const TriangleMesh copy = mesh;
  const uint64_t h = HashTriangleMesh(mesh);
  EXPECT_EQ(HashTriangleMesh(copy), h);
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) {
      for (double dir : {-1.0, 1.0}) {
        TriangleMesh m = mesh;
        m.vertices(i, c) = std::nextafter(m.vertices(i, c), dir * 1e300);
        EXPECT_NE(HashTriangleMesh(m), h) << i << " " << c << " " << dir;
      }
    }
  }
  TriangleMesh zero = mesh;  // vertex 2 has z = -0.0
  zero.vertices(2, 2) = 0.0;
  EXPECT_NE(HashTriangleMesh(zero), h);
  TriangleMesh index = mesh;
  index.faces(3, 1) = 0;
  EXPECT_NE(HashTriangleMesh(index), h);
  TriangleMesh swapped = mesh;  // same faces, different order
  swapped.faces.row(0).swap(swapped.faces.row(1));
  EXPECT_NE(HashTriangleMesh(swapped), h);
}

// --- ValidateSplineModel -----------------------------------------------------

void ExpectInvalid(const SplineModel& m, const std::string& fragment) {
  const Status s = ValidateSplineModel(m);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << fragment;
  EXPECT_NE(s.message().find(fragment), std::string::npos)
      << "message: " << s.message() << "\nexpected to contain: " << fragment;
}

TEST(ValidateSplineModelTest, BruteForceModelsAreValid) {
  // Knots spread over the sphere, so every small cap is the side of its
  // plane without the origin.
  const int n = 30;
  for (int k = 0; k <= 3; ++k) {
    const SplineModel m = MakeTestModel(k, n, 4, 10 + k);
    // The j-facet count of points in convex position: 2(k+1)(n-k-2).
    size_t configurations = 0;
    for (const ConfigurationSet& s : m.configurations.sets) {
      configurations += s.boundaries.size();
    }
    EXPECT_EQ(configurations, static_cast<size_t>(2 * (k + 1) * (n - k - 2)));
    const Status s = ValidateSplineModel(m);
    EXPECT_TRUE(s.ok()) << "degree " << k << ": " << s.message();
  }
}

TEST(ValidateSplineModelTest, RejectsEachViolation) {
  const SplineModel good = MakeTestModel(2, 8, 3);
  ASSERT_TRUE(ValidateSplineModel(good).ok());
  ASSERT_GE(good.configurations.sets.size(), 2u);
  {
    SplineModel m = good;
    m.degree = 6;
    m.configurations.degree = 6;
    ExpectInvalid(m, "degree 6");
  }
  {
    SplineModel m = good;
    m.configurations.degree = 1;
    ExpectInvalid(m, "configurations have degree 1");
  }
  {
    SplineModel m = good;
    m.knots.conservativeResize(5, 3);
    ExpectInvalid(m, "needs at least 6");
  }
  {
    SplineModel m = good;
    m.knots(3, 1) = std::numeric_limits<double>::infinity();
    ExpectInvalid(m, "knot coordinate is not finite");
  }
  {
    SplineModel m = good;
    m.knots.row(4) *= 1.0 + 1e-8;
    ExpectInvalid(m, "knot 4 is not a unit vector");
  }
  {
    SplineModel m = good;
    m.knots.row(4) *= 1.0 + 1e-12;  // within tolerance
    EXPECT_TRUE(ValidateSplineModel(m).ok());
  }
  {
    SplineModel m = good;
    m.configurations.sets.clear();
    m.control_points.resize(0, 3);
    ExpectInvalid(m, "no basis functions");
  }
  {
    SplineModel m = good;
    m.configurations.sets[1].knots.pop_back();
    ExpectInvalid(m, "basis function 1 has 4 knots");
  }
  {
    SplineModel m = good;
    m.configurations.sets[0].knots.back() = 8;
    ExpectInvalid(m, "refers to knot 8, out of range");
  }
  {
    SplineModel m = good;
    auto& k = m.configurations.sets[0].knots;
    std::swap(k[0], k[1]);
    ExpectInvalid(m, "not strictly ascending");
  }
  {
    SplineModel m = good;
    m.configurations.sets[0].boundaries.clear();
    ExpectInvalid(m, "0 boundary triples");
  }
  {
    SplineModel m = good;
    auto& set = m.configurations.sets[0];
    set.boundaries.assign(11, set.boundaries[0]);  // C(5,3) = 10
    ExpectInvalid(m, "11 boundary triples; expected 1..10");
  }
  {
    SplineModel m = good;
    auto& set = m.configurations.sets[0];
    int outside = 0;
    while (std::binary_search(set.knots.begin(), set.knots.end(), outside)) {
      ++outside;
    }
    std::array<int, 3> t = {set.knots[0], set.knots[1], outside};
    std::sort(t.begin(), t.end());
    set.boundaries = {t};
    ExpectInvalid(m, "which is not in the set");
  }
  {
    SplineModel m = good;
    auto& set = m.configurations.sets[0];
    set.boundaries = {{set.knots[0], set.knots[1], set.knots[2]},
                      {set.knots[0], set.knots[1], set.knots[2]}};
    ExpectInvalid(m, "not sorted or repeat");
  }
  {
    SplineModel m = good;
    std::swap(m.configurations.sets[0], m.configurations.sets[1]);
    ExpectInvalid(m, "out of order");
  }
  {
    SplineModel m = good;
    m.control_points.conservativeResize(m.control_points.rows() - 1, 3);
    ExpectInvalid(m, "control points for");
  }
  {
    SplineModel m = good;
    m.control_points(1, 2) = std::nan("");
    ExpectInvalid(m, "control point coordinate is not finite");
  }
  {
    SplineModel m = good;
    m.transform.scale = 0.0;
    ExpectInvalid(m, "finite scale > 0");
  }
  {
    SplineModel m = good;
    m.transform.translation[2] = -std::numeric_limits<double>::infinity();
    ExpectInvalid(m, "finite translation");
  }
  {
    SplineModel m = good;
    m.statistics.rounds[1].folded_area_percent = std::nan("");
    ExpectInvalid(m, "round 1 has a non-finite value");
  }
  {
    SplineModel m = good;
    m.statistics.final_result.knots = -1;
    ExpectInvalid(m, "final fit statistics has a negative count");
  }
  {
    SplineModel m = good;
    m.basis_form = static_cast<BasisForm>(7);
    ExpectInvalid(m, "unknown basis form");
  }
  {
    SplineModel m = good;
    m.statistics.options.lambda = std::nan("");
    ExpectInvalid(m, "recorded fit option");
  }
  {
    SplineModel m = good;
    m.source.num_faces = -3;
    ExpectInvalid(m, "negative count");
  }
  {
    SplineModel m = good;
    m.source.num_vertices = 4;
    ExpectInvalid(m, "3 sphere parameters for a source mesh of 4 vertices");
  }
  {
    SplineModel m = good;
    m.parameters(2, 0) += 1e-6;
    ExpectInvalid(m, "vertex 2 is not a unit vector");
  }
  {
    SplineModel m = good;
    m.parameters.resize(0, 3);  // not stored: fine
    EXPECT_TRUE(ValidateSplineModel(m).ok());
  }
}

}  // namespace
}  // namespace sdcb
