// Tests of converters/cad/cad_layout: the cube-sphere map (derivatives against
// differences, outward orientation, the six faces meeting along their sides
// at the same parameter, found by brute force over every face and side, and
// tiling the sphere by Newton inverses); the quads of a feature layout tile the
// sphere (their areas, by quadrature of the maps' Jacobians, add up to 4 pi),
// keep their orientation, meet along shared sides at the same parameter
// (brute force over every quad and side), and their crease sides lie on the
// arcs' great circles. Oracles: closed forms (4 pi, the arcs' planes) and
// brute-force search, not the layout's own bookkeeping.
#include "sdcb/converters/cad/cad_layout.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "sdcb/converters/cad/gauss_legendre.h"
#include "sdcb/core/common/constants.h"

namespace sdcb {
namespace {

KnotFeatureArcs Arcs(const std::vector<Eigen::Vector3d>& corners,
                     const std::vector<std::array<int, 2>>& arcs) {
  KnotFeatureArcs a;
  a.corner_directions.resize(static_cast<Eigen::Index>(corners.size()), 3);
  for (size_t c = 0; c < corners.size(); ++c) {
    a.corners.push_back(static_cast<int>(c));
    a.corner_directions.row(c) = corners[c].normalized();
  }
  a.arcs = arcs;
  return a;
}

// The cube's corners and edges (corners differing in one coordinate).
KnotFeatureArcs CubeArcs() {
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 8; ++k) {
    corners.emplace_back(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
  }
  std::vector<std::array<int, 2>> arcs;
  for (int a = 0; a < 8; ++a) {
    for (int b = a + 1; b < 8; ++b) {
      const int d = a ^ b;
      if (d == 1 || d == 2 || d == 4) arcs.push_back({a, b});
    }
  }
  return Arcs(corners, arcs);
}

// The octahedron's corners (the axes) and edges (every pair not opposite).
KnotFeatureArcs OctahedronArcs() {
  std::vector<Eigen::Vector3d> corners;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      c[axis] = sign;
      corners.push_back(c);
    }
  }
  std::vector<std::array<int, 2>> arcs;
  for (int a = 0; a < 6; ++a) {
    for (int b = a + 1; b < 6; ++b) {
      if (a / 2 != b / 2) arcs.push_back({a, b});
    }
  }
  return Arcs(corners, arcs);
}

// A square pyramid seen from its centre: four triangles and a quad.
KnotFeatureArcs PyramidArcs() {
  const std::vector<Eigen::Vector3d> corners = {
      {1, 1, -0.5}, {-1, 1, -0.5}, {-1, -1, -0.5}, {1, -1, -0.5}, {0, 0, 1.5}};
  return Arcs(corners,
              {{0, 1}, {1, 2}, {2, 3}, {0, 3}, {0, 4}, {1, 4}, {2, 4}, {3, 4}});
}

// (u, v) of side k (0: v = -1, 1: u = 1, 2: v = 1, 3: u = -1) at t.
Eigen::Vector2d SidePoint(int k, double t) {
  switch (k) {
    case 0:
      return {t, -1.0};
    case 1:
      return {1.0, t};
    case 2:
      return {t, 1.0};
    default:
      return {-1.0, t};
  }
}

// The one other face and side whose point at the same t is the same sphere
// point (brute force); false when there is not exactly one.
bool Neighbour(int f, int k, double t, int* g, int* side) {
  const Eigen::Vector2d a = SidePoint(k, t);
  const Eigen::Vector3d p = CubeSpherePoint(f, a.x(), a.y());
  int found = 0;
  for (int h = 0; h < 6; ++h) {
    if (h == f) continue;
    for (int s = 0; s < 4; ++s) {
      const Eigen::Vector2d b = SidePoint(s, t);
      if ((CubeSpherePoint(h, b.x(), b.y()) - p).norm() < 1e-12) {
        *g = h;
        *side = s;
        ++found;
      }
    }
  }
  return found == 1;
}

TEST(CubeSphereTest, DerivativesOrientationAndSharedSides) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-0.999, 0.999);
  for (int f = 0; f < 6; ++f) {
    for (int k = 0; k < 50; ++k) {
      const double u = d(rng), v = d(rng), h = 1e-6;
      Eigen::Vector3d du, dv;
      const Eigen::Vector3d p = CubeSpherePoint(f, u, v, &du, &dv);
      EXPECT_NEAR(p.norm(), 1.0, 1e-15);
      EXPECT_GT(du.cross(dv).dot(p), 0.0);  // counter-clockwise from outside
      const Eigen::Vector3d fu =
          (CubeSpherePoint(f, u + h, v) - CubeSpherePoint(f, u - h, v)) /
          (2 * h);
      const Eigen::Vector3d fv =
          (CubeSpherePoint(f, u, v + h) - CubeSpherePoint(f, u, v - h)) /
          (2 * h);
      EXPECT_LT((du - fu).norm(), 1e-8);
      EXPECT_LT((dv - fv).norm(), 1e-8);
    }
    for (int side = 0; side < 4; ++side) {
      for (const double t : {-1.0, -0.6, 0.1, 0.77, 1.0}) {
        int g = -1, s = -1;
        if (std::abs(t) == 1.0) continue;  // corners: three faces
        EXPECT_TRUE(Neighbour(f, side, t, &g, &s)) << f << " " << side;
      }
    }
  }
  // The faces tile the sphere: the equiangular map's inverse of a random
  // direction lands in exactly one face's open square.
  std::normal_distribution<double> n;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d p =
        Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    int inside = 0;
    for (int f = 0; f < 6; ++f) {
      // Newton on (u, v) from the centre.
      Eigen::Vector2d x(0, 0);
      for (int it = 0; it < 50; ++it) {
        Eigen::Vector3d du, dv;
        const Eigen::Vector3d q = CubeSpherePoint(f, x[0], x[1], &du, &dv);
        if (q.dot(p) <= 0) break;
        Eigen::Matrix<double, 3, 2> j;
        j << du, dv;
        x -= (j.transpose() * j).ldlt().solve(j.transpose() * (q - p));
        if (x.cwiseAbs().maxCoeff() > 3) break;
      }
      if (x.cwiseAbs().maxCoeff() < 1 &&
          (CubeSpherePoint(f, x[0], x[1]) - p).norm() < 1e-12) {
        ++inside;
      }
    }
    EXPECT_EQ(inside, 1);
  }
}

void CheckLayout(const CadQuadLayout& layout, const KnotFeatureArcs& arcs,
                 int quads, bool split) {
  ASSERT_EQ(layout.num_quads(), quads);
  EXPECT_EQ(layout.kind, CadQuadLayout::Kind::kFeatureFaces);
  EXPECT_TRUE(layout.has_creases());
  // Area and orientation by 16-point Gauss-Legendre in each direction.
  const GaussLegendre<16> rule;
  double area = 0.0;
  for (int q = 0; q < quads; ++q) {
    for (int j = 0; j < 16; ++j) {
      for (int i = 0; i < 16; ++i) {
        const double u = -1.0 + 2.0 * rule.x[i], v = -1.0 + 2.0 * rule.x[j];
        Eigen::Vector3d du, dv;
        const Eigen::Vector3d p = layout.Point(q, u, v, &du, &dv);
        const double jacobian = du.cross(dv).dot(p);
        EXPECT_GT(jacobian, 0.0) << q;
        area += 4.0 * rule.w[i] * rule.w[j] * jacobian;
        // The derivatives against central differences.
        const double h = 1e-6;
        const Eigen::Vector3d fu =
            (layout.Point(q, u + h, v) - layout.Point(q, u - h, v)) / (2 * h);
        const Eigen::Vector3d fv =
            (layout.Point(q, u, v + h) - layout.Point(q, u, v - h)) / (2 * h);
        EXPECT_LT((fu - du).norm(), 1e-7);
        EXPECT_LT((fv - dv).norm(), 1e-7);
      }
    }
  }
  EXPECT_NEAR(area, 4.0 * kPi, 1e-6);

  // Every side point: exactly one other quad side with the same sphere
  // point at the same parameter, and a crease side lies on an arc.
  int crease_sides = 0;
  for (int q = 0; q < quads; ++q) {
    for (int k = 0; k < 4; ++k) {
      crease_sides += layout.crease[q][k];
      for (int n = 1; n < 16; ++n) {
        const double t = -1.0 + 2.0 * n / 16;
        const Eigen::Vector2d a = SidePoint(k, t);
        const Eigen::Vector3d p = layout.Point(q, a.x(), a.y());
        EXPECT_NEAR(p.norm(), 1.0, 1e-14);
        int found = 0;
        for (int g = 0; g < quads; ++g) {
          for (int s = 0; s < 4; ++s) {
            if (g == q && s == k) continue;
            const Eigen::Vector2d b = SidePoint(s, t);
            if (layout.Point(g, b.x(), b.y()) == p) {
              ++found;
              EXPECT_EQ(layout.crease[g][s], layout.crease[q][k]);
            }
          }
        }
        EXPECT_EQ(found, 1) << "quad " << q << " side " << k << " t " << t;
        if (!layout.crease[q][k]) continue;
        // On an arc: on its great circle, between its ends.
        bool on_arc = false;
        for (const auto& arc : arcs.arcs) {
          const Eigen::Vector3d x = arcs.corner_directions.row(arc[0]);
          const Eigen::Vector3d y = arcs.corner_directions.row(arc[1]);
          const double cosine = x.dot(y) - 1e-12;
          on_arc |= std::abs(x.cross(y).normalized().dot(p)) < 1e-14 &&
                    p.dot(x) >= cosine && p.dot(y) >= cosine;
        }
        EXPECT_TRUE(on_arc) << "quad " << q << " side " << k << " t " << t;
      }
    }
  }
  // Every arc is two crease sides (split: four, its halves).
  EXPECT_EQ(crease_sides, static_cast<int>(arcs.arcs.size()) * (split ? 4 : 2));
}

TEST(CadLayoutTest, CubeArcsGiveTheSixFacesAsQuads) {
  const KnotFeatureArcs arcs = CubeArcs();
  const std::optional<CadQuadLayout> layout = FeatureQuadLayout(arcs);
  ASSERT_TRUE(layout.has_value());
  CheckLayout(*layout, arcs, 6, false);
  // The cube's corners make the cube-sphere's equiangular map: every quad
  // point is a cube-sphere point at the same parameters, up to the quad's
  // rotation (the tangent of pi u / 4 projects to the cube's face).
  for (int q = 0; q < 6; ++q) {
    const Eigen::Vector3d p = layout->Point(q, 0.3, -0.6);
    bool matched = false;
    for (int c = 0; c < 6 && !matched; ++c) {
      for (const auto& uv :
           {Eigen::Vector2d(0.3, -0.6), Eigen::Vector2d(0.6, 0.3),
            Eigen::Vector2d(-0.3, 0.6), Eigen::Vector2d(-0.6, -0.3)}) {
        if ((CubeSpherePoint(c, uv.x(), uv.y()) - p).norm() < 1e-14) {
          matched = true;
        }
      }
    }
    EXPECT_TRUE(matched) << q;
  }
}

// The same cube with its corners numbered in other orders: the faces'
// cycles start elsewhere, and the quads' corners must be reordered.
TEST(CadLayoutTest, CubeQuadsAreOrderedWhateverTheCornerNumbering) {
  const KnotFeatureArcs cube = CubeArcs();
  for (const std::array<int, 8>& order :
       {std::array<int, 8>{7, 6, 5, 4, 3, 2, 1, 0},
        std::array<int, 8>{3, 5, 0, 6, 1, 7, 2, 4},
        std::array<int, 8>{6, 0, 3, 5, 7, 1, 4, 2}}) {
    std::vector<Eigen::Vector3d> corners(8);
    for (int c = 0; c < 8; ++c) {
      corners[order[c]] = cube.corner_directions.row(c);
    }
    std::vector<std::array<int, 2>> arcs;
    for (const auto& arc : cube.arcs) {
      arcs.push_back({order[arc[0]], order[arc[1]]});
    }
    const KnotFeatureArcs renumbered = Arcs(corners, arcs);
    const std::optional<CadQuadLayout> layout = FeatureQuadLayout(renumbered);
    ASSERT_TRUE(layout.has_value());
    CheckLayout(*layout, renumbered, 6, false);
  }
}

TEST(CadLayoutTest, TriangleFacesAreCutIntoThreeQuadsEach) {
  const KnotFeatureArcs arcs = OctahedronArcs();
  const std::optional<CadQuadLayout> layout = FeatureQuadLayout(arcs);
  ASSERT_TRUE(layout.has_value());
  CheckLayout(*layout, arcs, 24, true);
}

TEST(CadLayoutTest, MixedFacesAreAllCut) {
  const KnotFeatureArcs arcs = PyramidArcs();
  const std::optional<CadQuadLayout> layout = FeatureQuadLayout(arcs);
  ASSERT_TRUE(layout.has_value());
  CheckLayout(*layout, arcs, 4 * 3 + 4, true);
}

TEST(CadLayoutTest, NoArcsOrArcsThatBoundNoFacesGiveNoLayout) {
  EXPECT_FALSE(FeatureQuadLayout(KnotFeatureArcs()).has_value());
  // A corner on a single arc: no faces.
  KnotFeatureArcs dangling = CubeArcs();
  dangling.arcs.pop_back();
  EXPECT_FALSE(FeatureQuadLayout(dangling).has_value());
}

TEST(CadLayoutTest, CubeSphereHasNoCreases) {
  const CadQuadLayout layout = CubeSphereLayout(4);
  EXPECT_EQ(layout.num_quads(), 6);
  EXPECT_EQ(layout.grid, 4);
  EXPECT_FALSE(layout.has_creases());
  for (int c = 0; c < 6; ++c) {
    EXPECT_EQ(layout.Point(c, 0.25, -0.5), CubeSpherePoint(c, 0.25, -0.5));
  }
}

}  // namespace
}  // namespace sdcb
