#include "sdcb/core/measure/triangle_distance.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace sdcb {
namespace {

Eigen::Vector3d ClosestOnSegment(const Eigen::Vector3d& p,
                                 const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 == 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

// The barycentric coordinates (u, v, w) of q's projection: the weights (v, w)
// of b and c in q - a = v (b - a) + w (c - a) by the normal equations, with
// `clamp` v into [0, 1] and then w into [0, 1 - v]; the centroid's where the
// edges' Gram determinant is not > 0.
Eigen::Vector3d Coordinates(const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                            const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                            bool clamp) {
  const Eigen::Vector3d e0 = b - a, e1 = c - a, d = q - a;
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const double d20 = d.dot(e0), d21 = d.dot(e1);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0)) return Eigen::Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3);
  double v = (d11 * d20 - d01 * d21) / det;
  double w = (d00 * d21 - d01 * d20) / det;
  if (clamp) {
    v = std::clamp(v, 0.0, 1.0);
    w = std::clamp(w, 0.0, 1.0 - v);
  }
  return Eigen::Vector3d(1.0 - v - w, v, w);
}

}  // namespace

Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p,
                                       const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a;
  const Eigen::Vector3d n = ab.cross(ac);
  const double n2 = n.squaredNorm();
  const double scale =
      std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});
  if (!(n2 > 1e-24 * scale * scale)) {
    // Degenerate: the closest of the three edges.
    const Eigen::Vector3d q[3] = {ClosestOnSegment(p, a, b),
                                  ClosestOnSegment(p, b, c),
                                  ClosestOnSegment(p, c, a)};
    int best = 0;
    for (int i = 1; i < 3; ++i) {
      if ((p - q[i]).squaredNorm() < (p - q[best]).squaredNorm()) best = i;
    }
    return q[best];
  }
  // Barycentric coordinates of the projection onto the plane.
  const Eigen::Vector3d ap = p - a;
  const double v = ap.cross(ac).dot(n) / n2;  // weight of b
  const double w = ab.cross(ap).dot(n) / n2;  // weight of c
  const double u = 1.0 - v - w;
  if (u >= 0 && v >= 0 && w >= 0) return a + v * ab + w * ac;
  // Outside: the closest point lies on an edge opposite a negative weight.
  Eigen::Vector3d best = ClosestOnSegment(p, a, b);
  double best_d = (p - best).squaredNorm();
  for (const Eigen::Vector3d& q :
       {ClosestOnSegment(p, b, c), ClosestOnSegment(p, c, a)}) {
    const double d = (p - q).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = q;
    }
  }
  return best;
}

Eigen::Vector3d TriangleCoordinates(const Eigen::Vector3d& q,
                                    const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  return Coordinates(q, a, b, c, false);
}

Eigen::Vector3d ClampedTriangleCoordinates(const Eigen::Vector3d& q,
                                           const Eigen::Vector3d& a,
                                           const Eigen::Vector3d& b,
                                           const Eigen::Vector3d& c) {
  return Coordinates(q, a, b, c, true);
}

}  // namespace sdcb
