#include "sdcb/core/tessellate/feature_pattern.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "sdcb/core/common/constants.h"

namespace sdcb {
namespace {

// A right-handed tangent basis (e1, e2) at unit vector n: e1 x e2 = n.
void Basis(const Eigen::Vector3d& n, Eigen::Vector3d* e1, Eigen::Vector3d* e2) {
  const Eigen::Vector3d helper = std::abs(n[0]) < 0.9
                                     ? Eigen::Vector3d::UnitX()
                                     : Eigen::Vector3d::UnitY();
  *e1 = helper.cross(n).normalized();
  *e2 = n.cross(*e1);
}

// The spherical excess of triangle (a, b, c) (its area on the unit sphere).
double SphericalArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& c) {
  const double det = a.dot(b.cross(c));
  return 2.0 * std::atan2(std::abs(det), 1.0 + a.dot(b) + b.dot(c) + c.dot(a));
}

// Ear clipping of the counter-clockwise polygon `points` (2D); appends the
// triangles (indices into `points`). False if it is not simple.
bool EarClip(const std::vector<Eigen::Vector2d>& points,
             std::vector<std::array<int, 3>>* triangles) {
  std::vector<int> left(points.size());
  for (size_t i = 0; i < left.size(); ++i) left[i] = static_cast<int>(i);
  const auto cross = [&](int a, int b, int c) {
    const Eigen::Vector2d u = points[b] - points[a], v = points[c] - points[a];
    return u[0] * v[1] - u[1] * v[0];
  };
  while (left.size() > 3) {
    const int n = static_cast<int>(left.size());
    bool clipped = false;
    for (int i = 0; i < n && !clipped; ++i) {
      const int a = left[(i + n - 1) % n], b = left[i], c = left[(i + 1) % n];
      if (!(cross(a, b, c) > 0.0)) continue;  // reflex or flat
      bool empty = true;
      for (int q : left) {
        if (q == a || q == b || q == c) continue;
        if (cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 &&
            cross(c, a, q) >= 0.0) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      triangles->push_back({a, b, c});
      left.erase(left.begin() + i);
      clipped = true;
    }
    if (!clipped) return false;
  }
  if (!(cross(left[0], left[1], left[2]) > 0.0)) return false;
  triangles->push_back({left[0], left[1], left[2]});
  return true;
}

// The centre of a face's gnomonic chart: the cycle's Newell normal (for
// three corners the normal of their plane, equally far from each), or zero
// if some corner is not well inside its hemisphere.
Eigen::Vector3d ChartCentre(const Eigen::MatrixX3d& corners,
                            const std::vector<int>& cycle) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < cycle.size(); ++i) {
    const Eigen::Vector3d x = corners.row(cycle[i]);
    const Eigen::Vector3d y = corners.row(cycle[(i + 1) % cycle.size()]);
    m += x.cross(y);
  }
  if (!(m.norm() > 1e-9)) return Eigen::Vector3d::Zero();
  m.normalize();
  for (int c : cycle) {
    if (!(corners.row(c).dot(m) > 0.05)) return Eigen::Vector3d::Zero();
  }
  return m;
}

}  // namespace

StatusOr<std::vector<std::vector<int>>> FeatureFaces(
    const Eigen::MatrixX3d& corners,
    const std::vector<std::array<int, 2>>& arcs) {
  const int n = static_cast<int>(corners.rows());
  // Each corner's arcs in counter-clockwise order seen from outside.
  std::vector<std::vector<std::pair<double, int>>> around(n);
  for (const auto& arc : arcs) {
    const int a = arc[0], b = arc[1];
    if (a < 0 || a >= n || b < 0 || b >= n || a == b) {
      return InvalidArgumentError("a feature arc has a bad corner");
    }
    for (const auto& [from, to] : {std::pair{a, b}, std::pair{b, a}}) {
      const Eigen::Vector3d c = corners.row(from), x = corners.row(to);
      if (!(c.dot(x) > -1.0 + 1e-9)) {
        return InvalidArgumentError("a feature arc spans half a circle");
      }
      Eigen::Vector3d e1, e2;
      Basis(c, &e1, &e2);
      const Eigen::Vector3d t = x - x.dot(c) * c;
      around[from].push_back({std::atan2(t.dot(e2), t.dot(e1)), to});
    }
  }
  for (int c = 0; c < n; ++c) {
    if (around[c].size() < 2) {
      return InvalidArgumentError("feature corner " + std::to_string(c) +
                                  " ends fewer than two arcs");
    }
    std::sort(around[c].begin(), around[c].end());
  }
  // Faces: each directed arc once, the face on its left, turning at each
  // corner to the arc just clockwise of the one it came along.
  const auto position = [&](int at, int to) {
    for (size_t i = 0; i < around[at].size(); ++i) {
      if (around[at][i].second == to) return static_cast<int>(i);
    }
    return -1;
  };
  std::vector<std::vector<char>> used(n);
  for (int c = 0; c < n; ++c) used[c].assign(around[c].size(), 0);
  std::vector<std::vector<int>> faces;
  for (int start = 0; start < n; ++start) {
    for (size_t k = 0; k < around[start].size(); ++k) {
      if (used[start][k]) continue;
      std::vector<int> cycle;
      int from = start, slot = static_cast<int>(k);
      while (!used[from][slot] && cycle.size() <= arcs.size() * 2) {
        used[from][slot] = 1;
        cycle.push_back(from);
        const int to = around[from][slot].second;
        const int back = position(to, from);
        const int deg = static_cast<int>(around[to].size());
        slot = (back + deg - 1) % deg;
        from = to;
      }
      if (from != start) {
        return InvalidArgumentError("the feature arcs do not bound faces");
      }
      std::vector<int> sorted = cycle;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
        return InvalidArgumentError("a face of the feature arcs is not simple");
      }
      if (ChartCentre(corners, cycle).isZero(0.0)) {
        return InvalidArgumentError("a face of the feature arcs is too wide");
      }
      faces.push_back(std::move(cycle));
    }
  }
  return faces;
}

StatusOr<SphereTriangulation> FeatureAlignedPattern(
    const Eigen::MatrixX3d& corners,
    const std::vector<std::array<int, 2>>& arcs) {
  SDCB_ASSIGN_OR_RETURN(const std::vector<std::vector<int>> cycles,
                        FeatureFaces(corners, arcs));
  std::vector<std::array<int, 3>> faces;
  double area = 0.0;
  for (const std::vector<int>& cycle : cycles) {
    const Eigen::Vector3d m = ChartCentre(corners, cycle);
    Eigen::Vector3d e1, e2;
    Basis(m, &e1, &e2);
    std::vector<Eigen::Vector2d> chart;
    for (int c : cycle) {
      const Eigen::Vector3d x = corners.row(c);
      const Eigen::Vector3d y = x / x.dot(m);
      chart.emplace_back(y.dot(e1), y.dot(e2));
    }
    std::vector<std::array<int, 3>> pieces;
    if (!EarClip(chart, &pieces)) {
      return InvalidArgumentError(
          "a face of the feature arcs does not triangulate");
    }
    for (const auto& t : pieces) {
      const std::array<int, 3> f = {cycle[t[0]], cycle[t[1]], cycle[t[2]]};
      area += SphericalArea(corners.row(f[0]), corners.row(f[1]),
                            corners.row(f[2]));
      faces.push_back(f);
    }
  }
  // Faces that overlap (arcs that cross) cover more than the sphere.
  if (std::abs(area - 4.0 * kPi) > 1e-9) {
    return InvalidArgumentError("the feature arcs cross");
  }
  const int n = static_cast<int>(corners.rows());
  Eigen::MatrixX3i face_matrix(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) {
    face_matrix.row(f) << faces[f][0], faces[f][1], faces[f][2];
  }
  SDCB_ASSIGN_OR_RETURN(SphereTriangulation pattern,
                        SphereTriangulation::FromFaces(corners, face_matrix));
  pattern.SetFeatures(arcs,
                      std::vector<int>(n, SphereTriangulation::kCornerVertex));
  return pattern;
}

StatusOr<FeatureQuadMesh> FeatureQuads(
    const Eigen::MatrixX3d& corners,
    const std::vector<std::array<int, 2>>& arcs, bool split) {
  SDCB_ASSIGN_OR_RETURN(const std::vector<std::vector<int>> cycles,
                        FeatureFaces(corners, arcs));
  FeatureQuadMesh out;
  out.split = split || !std::all_of(cycles.begin(), cycles.end(),
                                    [](const std::vector<int>& c) {
                                      return c.size() == 4;
                                    });
  const auto sorted = [](int a, int b) {
    return std::array<int, 2>{std::min(a, b), std::max(a, b)};
  };
  if (!out.split) {
    out.points = corners;
    for (const std::vector<int>& c : cycles) {
      out.quads.push_back({c[0], c[1], c[2], c[3]});
    }
    for (const auto& arc : arcs) out.creases.push_back(sorted(arc[0], arc[1]));
    std::sort(out.creases.begin(), out.creases.end());
    return out;
  }
  const int n = static_cast<int>(corners.rows());
  const int m = static_cast<int>(arcs.size());
  out.points.resize(n + m + static_cast<Eigen::Index>(cycles.size()), 3);
  out.points.topRows(n) = corners;
  std::map<std::array<int, 2>, int> midpoint;
  for (int a = 0; a < m; ++a) {
    const std::array<int, 2> key = sorted(arcs[a][0], arcs[a][1]);
    midpoint[key] = n + a;
    out.points.row(n + a) =
        (corners.row(key[0]) + corners.row(key[1])).normalized();
  }
  for (size_t f = 0; f < cycles.size(); ++f) {
    const std::vector<int>& cycle = cycles[f];
    const int centre = n + m + static_cast<int>(f);
    out.points.row(centre) = ChartCentre(corners, cycle).transpose();
    const int k = static_cast<int>(cycle.size());
    for (int i = 0; i < k; ++i) {
      const int c = cycle[i];
      const int next = midpoint.at(sorted(c, cycle[(i + 1) % k]));
      const int previous = midpoint.at(sorted(cycle[(i + k - 1) % k], c));
      out.quads.push_back({c, next, centre, previous});
      out.creases.push_back(sorted(c, next));
    }
  }
  std::sort(out.creases.begin(), out.creases.end());
  return out;
}

}  // namespace sdcb
