// Trim loops on the unit sphere and the region they keep (core/spline/
// model.h: an open part's spline is kept where its mesh was).
#ifndef SDCB_CORE_SPHERE_TRIM_REGION_H_
#define SDCB_CORE_SPHERE_TRIM_REGION_H_

#include <Eigen/Core>
#include <vector>

#include "sdcb/core/common/status.h"

namespace sdcb {

// One trim loop: a closed polygon on the unit sphere whose sides are the
// shorter great-circle arcs between consecutive rows (the last row joins the
// first). The kept region lies to the LEFT of every side seen from outside:
// beside the side a -> b, the points p with dot(p, a x b) > 0. The loops of a
// part are disjoint simple polygons; the kept region is the sphere minus the
// holes they bound (each loop bounds one hole, on its right).
struct TrimLoop {
  Eigen::MatrixX3d points;  // #points by 3 unit vectors, >= 3 rows
};

// Ok, or kInvalidArgument naming the problem: fewer than 3 rows, a row that
// is not a finite unit vector (|norm - 1| <= 1e-9), consecutive rows equal
// or antipodal.
Status ValidateTrimLoop(const TrimLoop& loop);

// Which sphere points a set of trim loops keeps. Immutable after Create;
// Contains and DistanceToTrim are thread-safe.
class TrimRegion {
 public:
  // No loops: the whole sphere is kept.
  TrimRegion() = default;
  // kInvalidArgument when a loop fails ValidateTrimLoop.
  static StatusOr<TrimRegion> Create(std::vector<TrimLoop> loops);

  bool empty() const { return loops_.empty(); }
  const std::vector<TrimLoop>& loops() const { return loops_; }

  // Whether unit vector `p` lies in the kept region (points on a trim side
  // count as kept). Exact up to the rounding of the orientation tests.
  bool Contains(const Eigen::Vector3d& p) const;
  // The angle, radians, from unit vector `p` to the nearest point of any
  // trim side; +inf without loops.
  double DistanceToTrim(const Eigen::Vector3d& p) const;

 private:
  std::vector<TrimLoop> loops_;
  // Per loop: a bounding cap (unit centre, cosine of its angular radius)
  // and whether its hole lies inside the cap; cap_cos = -2 means no cap.
  struct LoopBound {
    Eigen::Vector3d center = Eigen::Vector3d::UnitZ();
    double cap_cos = -2.0;
    bool hole_inside_cap = true;
    Eigen::Vector3d outside_point = Eigen::Vector3d::UnitZ();  // not in hole
  };
  std::vector<LoopBound> bounds_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_TRIM_REGION_H_
