#include "sdcb/core/sphere/cube_atlas.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sdcb {

int CubeFaceOf(const Eigen::Vector3d& d) {
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(d[k]) > std::abs(d[axis])) axis = k;
  }
  return 2 * axis + (d[axis] < 0 ? 1 : 0);
}

Eigen::Vector2d GnomonicOnFace(const Eigen::Vector3d& d, int face) {
  const int axis = face / 2;
  const double w = face % 2 == 0 ? d[axis] : -d[axis];
  return Eigen::Vector2d(d[(axis + 1) % 3], d[(axis + 2) % 3]) / w;
}

Eigen::Vector3d DirectionOnFace(int face, const Eigen::Vector2d& ab) {
  const int axis = face / 2;
  Eigen::Vector3d p;
  p[axis] = face % 2 == 0 ? 1.0 : -1.0;
  p[(axis + 1) % 3] = ab[0];
  p[(axis + 2) % 3] = ab[1];
  return p.normalized();
}

Eigen::Vector2d CubeAtlasUv(const CubeAtlasLayout& layout, int part, int face,
                            const Eigen::Vector2d& ab) {
  const double t = layout.tile;
  const double x = (face % 3 + 0.5 * (ab[0] / layout.extent + 1.0)) * t;
  const double y =
      (2 * part + face / 3 + 0.5 * (ab[1] / layout.extent + 1.0)) * t;
  return Eigen::Vector2d(x / layout.width(), y / layout.height());
}

CubeAtlasTexel CubeAtlasTexelAt(const CubeAtlasLayout& layout, int x, int y) {
  const int t = layout.tile;
  CubeAtlasTexel texel;
  const int row = y / t;
  texel.part = row / 2;
  texel.face = 3 * (row % 2) + x / t;
  const double e = layout.extent;
  const Eigen::Vector2d ab(e * (2.0 * (x % t + 0.5) / t - 1.0),
                           e * (2.0 * (y % t + 0.5) / t - 1.0));
  texel.direction = DirectionOnFace(texel.face, ab);
  return texel;
}

CubeAtlasMesh CubeAtlasTexcoords(const CubeAtlasLayout& layout, int part,
                                 const Eigen::MatrixX3d& directions,
                                 const Eigen::MatrixX3i& faces) {
  const Eigen::Index nv = directions.rows(), nf = faces.rows();
  CubeAtlasMesh out;
  out.faces.resize(nf, 3);
  std::vector<std::array<int, 6>> copy(nv);
  for (auto& c : copy) c.fill(-1);
  std::vector<Eigen::Vector2d> uv;
  const double e = layout.extent;
  for (Eigen::Index f = 0; f < nf; ++f) {
    std::array<Eigen::Vector3d, 3> d;
    for (int c = 0; c < 3; ++c) d[c] = directions.row(faces(f, c)).transpose();
    // The face that keeps the corners' largest coordinate smallest.
    int best = -1;
    double best_cost = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 3; ++c) {
      const int face = CubeFaceOf(d[c]);
      const int axis = face / 2;
      const double sign = face % 2 == 0 ? 1.0 : -1.0;
      double cost = 0.0;
      for (int k = 0; k < 3 && cost < best_cost; ++k) {
        if (sign * d[k][axis] <= 0.0) {
          cost = std::numeric_limits<double>::infinity();
          break;
        }
        cost = std::max(cost, GnomonicOnFace(d[k], face).cwiseAbs().maxCoeff());
      }
      if (cost < best_cost || (cost == best_cost && face < best)) {
        best = face;
        best_cost = cost;
      }
    }
    if (best < 0) {
      // A triangle wider than a face's hemisphere: its centre's face.
      best = CubeFaceOf(d[0] + d[1] + d[2]);
    }
    const int axis = best / 2;
    const double sign = best % 2 == 0 ? 1.0 : -1.0;
    for (int c = 0; c < 3; ++c) {
      const int v = faces(f, c);
      int& to = copy[v][best];
      if (to < 0) {
        Eigen::Vector2d ab = GnomonicOnFace(d[c], best);
        if (!(sign * d[c][axis] > 0.0) || !(ab.cwiseAbs().maxCoeff() <= e)) {
          ++out.corners_beyond_extent;
          if (!(sign * d[c][axis] > 0.0)) ab = -ab;  // towards the edge seen
          ab = ab.cwiseMax(-e).cwiseMin(e);
          if (!ab.allFinite()) ab.setZero();
        }
        to = static_cast<int>(uv.size());
        uv.push_back(CubeAtlasUv(layout, part, best, ab));
        out.vertex.push_back(v);
      }
      out.faces(f, c) = to;
    }
  }
  out.texcoords.resize(static_cast<Eigen::Index>(uv.size()), 2);
  for (size_t i = 0; i < uv.size(); ++i) out.texcoords.row(i) = uv[i];
  return out;
}

}  // namespace sdcb
