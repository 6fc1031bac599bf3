// Geometry on the unit sphere S^2 used by every stage: determinants, exact
// orientation and the "inside the spherical cap" predicate of the paper's
// Definition 3. Every combinatorial decision goes through the exact
// predicates here; floating point is used only for values.
#ifndef SDCB_CORE_SPHERE_SPHERE_GEOMETRY_H_
#define SDCB_CORE_SPHERE_SPHERE_GEOMETRY_H_

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "sdcb/core/common/constants.h"

namespace sdcb {

// The one tolerance on | |t| - 1 | for every unit vector the library accepts
// (knots, sphere parameters, density vertices): every stage accepts what the
// others accept. Everything the library produces is normalized to ~1e-16.
constexpr double kUnitVectorTolerance = 1e-9;

// Whether every row of `points` (#P by 3) is finite and unit within
// kUnitVectorTolerance.
bool AllUnitRows(const Eigen::MatrixX3d& points);
// The first row that is not finite or not unit within kUnitVectorTolerance,
// or -1.
Eigen::Index FirstNonUnitRow(const Eigen::MatrixX3d& points);

// The chord |a - b| of unit vectors at `angle` radians apart (angles past
// pi count as pi), and back.
inline double ChordFromAngle(double angle) {
  return 2 * std::sin(std::min(angle, kPi) / 2);
}
inline double AngleFromChord(double chord) {
  return 2 * std::asin(std::min(1.0, chord / 2));
}

// det[a b c] = a . (b x c), in floating point (a value, not a decision).
inline double Det3(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c) {
  return a.dot(b.cross(c));
}

// Exact sign of orient3d(a, b, c, d) = sign of det[b-a, c-a, d-a], as CGAL's
// filtered predicate computes it: +1, 0 or -1.
int Orient3dSign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                 const Eigen::Vector3d& c, const Eigen::Vector3d& d);

// Exact sign of det[a b c] = orient3d(origin, a, b, c).
int Det3Sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
             const Eigen::Vector3d& c);

// Position of q relative to the spherical circle through a, b, c (the plane
// through them), without any perturbation: +1 strictly inside the smaller
// cap (the side of the plane without the origin), -1 strictly outside,
// 0 on the circle. Requires a, b, c not collinear and the plane not through
// the origin (a great circle has no smaller cap): then it returns 0 as well.
int CapSide(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
            const Eigen::Vector3d& c, const Eigen::Vector3d& q);

// Whether some plane through the origin has every row of `points` (#P by 3,
// nonzero vectors, pairwise distinct, #P small: the test is O(#P^4)) strictly
// on one side, i.e. the points lie in an open hemisphere. Equivalently the
// origin is not in their convex hull (Caratheodory: not in the closed
// segment, triangle or tetrahedron of any 2, 3 or 4 of them), which is how it
// is decided, with exact signs. The simplex spline M(p | V) is a bounded
// function only for such V (its cone must be pointed).
bool InOpenHemisphere(const Eigen::MatrixX3d& points);

// Orthonormal tangent frame (e_u, e_v) of S^2 at the unit vector p, with
// e_u x e_v = p; deterministic in p.
void TangentFrame(const Eigen::Vector3d& p, Eigen::Vector3d* e_u,
                  Eigen::Vector3d* e_v);

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_SPHERE_GEOMETRY_H_
