// Tests core/sphere/cube_atlas.*: the cube face and gnomonic coordinates of
// directions against their definition, direction -> uv -> texel ->
// direction round trips, texel centres -> uv, and the texture coordinates
// of an icosphere's tessellation mapped back to its directions.
#include "sdcb/core/sphere/cube_atlas.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {
namespace {

Eigen::Vector3d RandomDirection(std::mt19937* rng) {
  std::normal_distribution<double> g;
  return Eigen::Vector3d(g(*rng), g(*rng), g(*rng)).normalized();
}

// The direction a uv of `layout` names, from the layout's definition: tile
// column and row, then the gnomonic coordinates inside the tile.
Eigen::Vector3d DirectionOfUv(const CubeAtlasLayout& layout,
                              const Eigen::Vector2d& uv, int* part) {
  const double x = uv[0] * 3, y = uv[1] * 2 * layout.parts;
  const int col = std::min(2, static_cast<int>(x));
  const int row = std::min(2 * layout.parts - 1, static_cast<int>(y));
  *part = row / 2;
  const int face = 3 * (row % 2) + col;
  const double a = layout.extent * (2 * (x - col) - 1);
  const double b = layout.extent * (2 * (y - row) - 1);
  Eigen::Vector3d p;
  const int axis = face / 2;
  p[axis] = face % 2 == 0 ? 1 : -1;
  p[(axis + 1) % 3] = a;
  p[(axis + 2) % 3] = b;
  return p.normalized();
}

TEST(CubeAtlasTest, FaceAndGnomonicCoordinatesFollowTheDefinition) {
  const Eigen::Vector3d d = Eigen::Vector3d(0.5, -2.0, 0.25).normalized();
  EXPECT_EQ(CubeFaceOf(d), 3);  // axis y, negative
  const Eigen::Vector2d ab = GnomonicOnFace(d, 3);
  EXPECT_NEAR(ab[0], 0.125, 1e-15);  // z / |y|
  EXPECT_NEAR(ab[1], 0.25, 1e-15);   // x / |y|
  std::mt19937 rng(5);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d r = RandomDirection(&rng);
    const int face = CubeFaceOf(r);
    const int axis = face / 2;
    EXPECT_GE(std::abs(r[axis]), r.cwiseAbs().maxCoeff());
    EXPECT_EQ(face % 2 == 1, r[axis] < 0);
    const Eigen::Vector2d g = GnomonicOnFace(r, face);
    EXPECT_LE(g.cwiseAbs().maxCoeff(), 1.0);
    EXPECT_LT((DirectionOnFace(face, g) - r).norm(), 1e-14);
  }
}

TEST(CubeAtlasTest, DirectionToUvToTexelRoundTrips) {
  CubeAtlasLayout layout;
  layout.parts = 3;
  layout.tile = 64;
  // A texel spans at most 2 e / tile in gnomonic coordinates, less in
  // angle; half its diagonal bounds the distance to its centre.
  const double half_texel = std::sqrt(2.0) * layout.extent / layout.tile;
  std::mt19937 rng(7);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d d = RandomDirection(&rng);
    const int part = i % layout.parts;
    const int face = CubeFaceOf(d);
    const Eigen::Vector2d uv =
        CubeAtlasUv(layout, part, face, GnomonicOnFace(d, face));
    int uv_part = -1;
    EXPECT_LT((DirectionOfUv(layout, uv, &uv_part) - d).norm(), 1e-13);
    EXPECT_EQ(uv_part, part);
    const int x = static_cast<int>(uv[0] * layout.width());
    const int y = static_cast<int>(uv[1] * layout.height());
    const CubeAtlasTexel texel = CubeAtlasTexelAt(layout, x, y);
    EXPECT_EQ(texel.part, part);
    EXPECT_EQ(texel.face, face);
    EXPECT_LT((texel.direction - d).norm(), half_texel);
  }
}

TEST(CubeAtlasTest, TexelCentresMapToTheirUv) {
  CubeAtlasLayout layout;
  layout.parts = 2;
  layout.tile = 8;
  for (int y = 0; y < layout.height(); ++y) {
    for (int x = 0; x < layout.width(); ++x) {
      const CubeAtlasTexel t = CubeAtlasTexelAt(layout, x, y);
      const Eigen::Vector2d uv = CubeAtlasUv(
          layout, t.part, t.face, GnomonicOnFace(t.direction, t.face));
      ASSERT_NEAR(uv[0], (x + 0.5) / layout.width(), 1e-14);
      ASSERT_NEAR(uv[1], (y + 0.5) / layout.height(), 1e-14);
    }
  }
}

TEST(CubeAtlasTest, TessellationTexcoordsMapBackToItsDirections) {
  // Edges of about 3.6 degrees: near a cube corner a triangle's corners on
  // its face reach about 1 + 3 times its angle.
  const TriangleMesh sphere = MakeIcosphere(4);
  Eigen::MatrixX3d directions = sphere.vertices;
  directions.rowwise().normalize();
  CubeAtlasLayout layout;
  layout.parts = 2;
  layout.tile = 128;
  const CubeAtlasMesh m =
      CubeAtlasTexcoords(layout, 1, directions, sphere.faces);
  EXPECT_EQ(m.corners_beyond_extent, 0);
  ASSERT_EQ(m.faces.rows(), sphere.faces.rows());
  ASSERT_EQ(m.texcoords.rows(), static_cast<Eigen::Index>(m.vertex.size()));
  // Vertices are split at tile seams only: more than the input's, but not
  // every corner its own.
  EXPECT_GT(m.vertex.size(), static_cast<size_t>(directions.rows()));
  EXPECT_LT(m.vertex.size(), static_cast<size_t>(3 * sphere.faces.rows() / 2));
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    int tile_x = -1, tile_y = -1;
    for (int c = 0; c < 3; ++c) {
      const int v = m.faces(f, c);
      ASSERT_EQ(m.vertex[v], sphere.faces(f, c));
      const Eigen::Vector2d uv = m.texcoords.row(v).transpose();
      int part = -1;
      EXPECT_LT((DirectionOfUv(layout, uv, &part) -
                 directions.row(m.vertex[v]).transpose())
                    .norm(),
                1e-12);
      EXPECT_EQ(part, 1);
      // One tile per triangle, inside it (not on its edge).
      const double x = uv[0] * 3, y = uv[1] * 2 * layout.parts;
      if (c == 0) {
        tile_x = static_cast<int>(x);
        tile_y = static_cast<int>(y);
      }
      EXPECT_EQ(static_cast<int>(x), tile_x);
      EXPECT_EQ(static_cast<int>(y), tile_y);
      EXPECT_GT(x - tile_x, 0.0);
      EXPECT_LT(x - tile_x, 1.0);
    }
  }
}

}  // namespace
}  // namespace sdcb
