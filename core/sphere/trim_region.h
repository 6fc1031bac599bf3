// Trim loops on the unit sphere and the region they keep (core/spline/
// model.h: an open part's spline is kept where its mesh was).
#ifndef SDCB_CORE_SPHERE_TRIM_REGION_H_
#define SDCB_CORE_SPHERE_TRIM_REGION_H_

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/sphere/point_kd_tree.h"

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

// Ok, or kInvalidArgument naming the problem (rows counted from 1): fewer
// than 3 rows, a row that is not a finite unit vector (|norm - 1| <= 1e-9),
// consecutive rows parallel (equal or antipodal).
Status ValidateTrimLoop(const TrimLoop& loop);

// Which sphere points a set of trim loops keeps. Immutable after Create;
// Contains and DistanceToTrim are thread-safe.
class TrimRegion {
 public:
  // No loops: the whole sphere is kept.
  TrimRegion() = default;
  // kInvalidArgument when a loop fails ValidateTrimLoop. Time and memory
  // linear in the loops' points (about six grid cells per point; a 5,000-
  // point loop builds in a few milliseconds). The loops are trusted to be
  // disjoint and simple; crossing loops give a region by crossing parity.
  static StatusOr<TrimRegion> Create(std::vector<TrimLoop> loops);

  bool empty() const { return loops_.empty(); }
  const std::vector<TrimLoop>& loops() const { return loops_; }

  // Whether unit vector `p` lies in the kept region. Exact up to the
  // rounding of the orientation tests (floating-point dot and cross
  // products): a point within about 1e-15 radians of a side may get either
  // answer. Constant time but for the sides in the point's grid cell
  // (1,000,000 queries against a 5,000-point loop: 0.05 s on one core).
  bool Contains(const Eigen::Vector3d& p) const;
  // The angle, radians, from unit vector `p` to the nearest point of any
  // trim side, or `limit` when that is smaller (+inf without loops and a
  // limit of +inf): min(distance, limit). A scan that skips chunks of 32
  // sides by their bounding caps, and most of them when the limit is small
  // (against 5,000 sides: about 2 microseconds near the loop; tens of
  // microseconds for a point far from a round loop without a limit).
  double DistanceToTrim(
      const Eigen::Vector3d& p,
      double limit = std::numeric_limits<double>::infinity()) const;

 private:
  // A cap that holds some trim sides, for DistanceToTrim: unit centre,
  // angular radius (pi: no bound), its cosine and sine.
  struct Cap {
    Eigen::Vector3d center = Eigen::Vector3d::UnitZ();
    double radius = kPi, cos_radius = -1, sin_radius = 0;
  };
  // One trim side a -> b with n = a x b (not normalized) and its cap
  // (centred at its midpoint, radius half its angle).
  struct Side {
    Eigen::Vector3d a, b, n;
    Cap cap;
  };
  // Sides per DistanceToTrim chunk (consecutive sides sharing a cap).
  static constexpr int kChunk = 32;
  // Contains: a cube-map grid over the sphere (gnomonic coordinates of a
  // fixed generic rotation of the sphere, N by N cells per face; a cell is
  // a convex spherical quadrilateral, so the great arc between two of its
  // points stays in it). Per cell: the sides that may pass through it and
  // whether its centre is kept. A query counts the crossings of the arc
  // from the point to its cell's centre with the cell's sides.
  int CellOf(const Eigen::Vector3d& p) const;

  // Create's steps, after sides_ is filled: the DistanceToTrim bounds; the
  // grid's side lists and centres; which centres are kept (`loop_sides`:
  // per loop, its range of sides_).
  static Cap MakeCap(const Eigen::Vector3d& center, double radius);
  void IndexDistances();
  void GridSides();
  void ClassifyCenters(const std::vector<std::pair<int, int>>& loop_sides);
  // The parity of the crossings of sides [begin, end) with the path r -> q:
  // one great arc, or two through a point 90 degrees from r when q is near
  // -r (each arc shorter than pi).
  int PathParity(const Eigen::Vector3d& r, const Eigen::Vector3d& q, int begin,
                 int end) const;

  std::vector<TrimLoop> loops_;
  std::vector<Side> sides_;
  Eigen::Matrix3d frame_ = Eigen::Matrix3d::Identity();  // the rotation
  int grid_n_ = 0;
  std::vector<int> cell_begin_;  // 6 N^2 + 1 offsets into cell_sides_
  std::vector<int> cell_sides_;  // side indices, ascending per cell
  std::vector<Eigen::Vector3d> cell_centers_;  // unit, per cell
  std::vector<char> center_kept_;              // per cell
  // DistanceToTrim: the sides' midpoints, for a first (upper) bound, and
  // the caps of sides kChunk * i .. kChunk * (i + 1) - 1.
  std::shared_ptr<const PointKdTree> midpoints_;
  std::vector<Cap> chunks_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_TRIM_REGION_H_
