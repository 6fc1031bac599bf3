#include "sdcb/core/sphere/trim_region.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "sdcb/core/common/constants.h"

namespace sdcb {
namespace {

// The angle between unit vectors a and b, accurate at 0 and pi.
double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// The angle from unit vector p to the shorter great arc a -> b with
// n = a x b != 0: to the foot of p on the arc's great circle when that foot
// lies on the arc, else to the nearer end.
double ArcDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                   const Eigen::Vector3d& b, const Eigen::Vector3d& n) {
  if (a.cross(p).dot(n) >= 0 && p.cross(b).dot(n) >= 0) {
    const double nn = n.squaredNorm();
    const double h = p.dot(n);
    const Eigen::Vector3d foot = p - (h / nn) * n;
    return std::atan2(std::abs(h) / std::sqrt(nn), foot.norm());
  }
  return std::min(Angle(p, a), Angle(p, b));
}

// Whether the great arc p -> q (shorter than pi) crosses the side a -> b
// with n = a x b. A loop vertex on the great circle of p, q counts as on
// its positive side (for both of its sides), so that crossings of a closed
// loop have the right parity when the arc passes through a vertex.
bool Crosses(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
             const Eigen::Vector3d& m, const Eigen::Vector3d& a,
             const Eigen::Vector3d& b, const Eigen::Vector3d& n) {
  if ((m.dot(a) >= 0) == (m.dot(b) >= 0)) return false;
  if ((n.dot(p) >= 0) == (n.dot(q) >= 0)) return false;
  // The two great circles meet at +-x; each arc holds the one on the side
  // of its midpoint.
  const Eigen::Vector3d x = m.cross(n);
  return (x.dot(p + q) > 0) == (x.dot(a + b) > 0);
}

// A fixed generic rotation for the grid, so that its cells' centres and
// edges do not line up with symmetric inputs (icosphere vertices, axes).
Eigen::Matrix3d GridFrame() {
  return (Eigen::AngleAxisd(0.5123, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(0.3217, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(0.7071, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// Cube face f = 2 k + (x_k < 0) of a point x (rotated frame), gnomonic
// coordinates (x_{k+1}, x_{k+2}) / |x_k| in [-1, 1]^2.
void Gnomonic(const Eigen::Vector3d& x, int* face, double* u, double* v) {
  int k = 0;
  if (std::abs(x[1]) > std::abs(x[k])) k = 1;
  if (std::abs(x[2]) > std::abs(x[k])) k = 2;
  const double w = std::abs(x[k]);
  *face = 2 * k + (x[k] < 0);
  *u = x[(k + 1) % 3] / w;
  *v = x[(k + 2) % 3] / w;
}

// The unit vector (rotated frame) at gnomonic (u, v) of face f.
Eigen::Vector3d FromGnomonic(int face, double u, double v) {
  const int k = face / 2;
  Eigen::Vector3d x;
  x[k] = face % 2 == 0 ? 1.0 : -1.0;
  x[(k + 1) % 3] = u;
  x[(k + 2) % 3] = v;
  return x.normalized();
}

// Whether every point of `cap` is farther than `best` (cosine, sine) from
// unit p: the angle from p to its centre exceeds best + its radius.
template <typename Cap>
bool Beyond(const Eigen::Vector3d& p, const Cap& cap, double best,
            double cos_best, double sin_best) {
  return best + cap.radius < kPi &&
         p.dot(cap.center) <
             cos_best * cap.cos_radius - sin_best * cap.sin_radius;
}

int GridCoordinate(double u, int n) {
  const int i = static_cast<int>(std::floor((u + 1) * 0.5 * n));
  return std::clamp(i, 0, n - 1);
}

}  // namespace

Status ValidateTrimLoop(const TrimLoop& loop) {
  // Points counted from 1, as parts and loops are in every message.
  const Eigen::Index n = loop.points.rows();
  const auto str = [](Eigen::Index i) { return std::to_string(i); };
  if (n < 3) {
    return InvalidArgumentError("it has " + str(n) +
                                " points; a loop needs at least 3");
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = loop.points.row(i);
    if (!p.allFinite() || !(std::abs(p.norm() - 1) <= 1e-9)) {
      return InvalidArgumentError("point " + str(i + 1) +
                                  " is not a finite unit vector");
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d a = loop.points.row(i);
    const Eigen::Vector3d b = loop.points.row((i + 1) % n);
    if (a.cross(b).norm() == 0) {
      return InvalidArgumentError("points " + str(i + 1) + " and " +
                                  str((i + 1) % n + 1) +
                                  " are equal or antipodal");
    }
  }
  return Status::Ok();
}

StatusOr<TrimRegion> TrimRegion::Create(std::vector<TrimLoop> loops) {
  TrimRegion region;
  std::vector<std::pair<int, int>> loop_sides;  // [begin, end) per loop
  for (size_t l = 0; l < loops.size(); ++l) {
    const Status valid = ValidateTrimLoop(loops[l]);
    if (!valid.ok()) {
      return valid.WithPrefix("trim loop " + std::to_string(l));
    }
    const Eigen::MatrixX3d& pts = loops[l].points;
    const int begin = static_cast<int>(region.sides_.size());
    for (Eigen::Index i = 0; i < pts.rows(); ++i) {
      Side s;
      s.a = pts.row(i);
      s.b = pts.row((i + 1) % pts.rows());
      s.n = s.a.cross(s.b);
      s.cap = MakeCap((s.a + s.b).normalized(), Angle(s.a, s.b) / 2);
      region.sides_.push_back(s);
    }
    loop_sides.emplace_back(begin, static_cast<int>(region.sides_.size()));
  }
  region.loops_ = std::move(loops);
  if (region.sides_.empty()) return region;
  region.IndexDistances();
  region.GridSides();
  region.ClassifyCenters(loop_sides);
  return region;
}

TrimRegion::Cap TrimRegion::MakeCap(const Eigen::Vector3d& center,
                                    double radius) {
  Cap cap;
  cap.center = center;
  cap.radius = radius;
  cap.cos_radius = std::cos(radius);
  cap.sin_radius = std::sin(radius);
  return cap;
}

void TrimRegion::IndexDistances() {
  Eigen::MatrixX3d midpoints(sides_.size(), 3);
  for (size_t i = 0; i < sides_.size(); ++i) {
    midpoints.row(i) = sides_[i].cap.center.transpose();
  }
  midpoints_ = std::make_shared<const PointKdTree>(midpoints);
  for (size_t begin = 0; begin < sides_.size(); begin += kChunk) {
    const size_t end = std::min(sides_.size(), begin + kChunk);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t i = begin; i < end; ++i) sum += sides_[i].a;
    Cap cap;  // no bound unless a cap under a hemisphere holds the sides
    if (sum.norm() > 1e-6) {
      const Eigen::Vector3d center = sum.normalized();
      double radius = 0;
      for (size_t i = begin; i < end; ++i) {
        radius = std::max(
            {radius, Angle(center, sides_[i].a), Angle(center, sides_[i].b)});
      }
      // A cap smaller than a hemisphere is convex: it holds the arcs
      // between the ends it holds.
      if (radius < kPi / 2 - 1e-9) cap = MakeCap(center, radius + 1e-12);
    }
    chunks_.push_back(cap);
  }
}

int TrimRegion::PathParity(const Eigen::Vector3d& r, const Eigen::Vector3d& q,
                           int begin, int end) const {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> arcs;
  if (r.dot(q) > -0.5) {
    arcs.emplace_back(r, q);
  } else {
    Eigen::Index k;
    r.cwiseAbs().minCoeff(&k);
    const Eigen::Vector3d w = r.cross(Eigen::Vector3d::Unit(k)).normalized();
    arcs.emplace_back(r, w);
    arcs.emplace_back(w, q);
  }
  int parity = 0;
  for (const auto& [p0, p1] : arcs) {
    const Eigen::Vector3d m = p0.cross(p1);
    for (int j = begin; j < end; ++j) {
      const Side& s = sides_[j];
      parity ^= Crosses(p0, p1, m, s.a, s.b, s.n);
    }
  }
  return parity;
}

void TrimRegion::GridSides() {
  // The grid: about six cells per trim point, 4 to 128 cells a face side.
  const int n = std::clamp(
      static_cast<int>(std::ceil(std::sqrt(double(sides_.size())))), 4, 128);
  grid_n_ = n;
  frame_ = GridFrame();
  const int cells = 6 * n * n;
  std::vector<std::vector<int>> lists(cells);
  // Each side, cut into pieces of at most 30 degrees, is drawn on every
  // face whose hemisphere holds both ends of a piece (a piece that reaches
  // a face's region, where |x_k| >= 1/sqrt(3), ends within 84.8 degrees of
  // the face's axis): there the piece is the straight segment between its
  // ends' gnomonic images, and every cell that segment comes within
  // `margin` of gets the side.
  const double margin = 1e-9;
  const double max_piece = 30 * kPi / 180;
  for (int si = 0; si < static_cast<int>(sides_.size()); ++si) {
    const Side& s = sides_[si];
    const Eigen::Vector3d a = frame_ * s.a;
    const Eigen::Vector3d b = frame_ * s.b;
    const double angle = Angle(a, b);
    const int pieces =
        std::max(1, static_cast<int>(std::ceil(angle / max_piece)));
    const Eigen::Vector3d e = (b - a.dot(b) * a).normalized();
    for (int piece = 0; piece < pieces; ++piece) {
      const double t0 = angle * piece / pieces;
      const double t1 = angle * (piece + 1) / pieces;
      const Eigen::Vector3d p =
          piece == 0 ? a : (std::cos(t0) * a + std::sin(t0) * e).normalized();
      const Eigen::Vector3d q =
          piece + 1 == pieces
              ? b
              : (std::cos(t1) * a + std::sin(t1) * e).normalized();
      for (int face = 0; face < 6; ++face) {
        const int k = face / 2;
        const double sign = face % 2 == 0 ? 1.0 : -1.0;
        if (sign * p[k] <= 0.05 || sign * q[k] <= 0.05) continue;
        const Eigen::Vector2d gp(p[(k + 1) % 3] / (sign * p[k]),
                                 p[(k + 2) % 3] / (sign * p[k]));
        const Eigen::Vector2d gq(q[(k + 1) % 3] / (sign * q[k]),
                                 q[(k + 2) % 3] / (sign * q[k]));
        const Eigen::Vector2d lo = gp.cwiseMin(gq).array() - margin;
        const Eigen::Vector2d hi = gp.cwiseMax(gq).array() + margin;
        if (lo.x() > 1 || lo.y() > 1 || hi.x() < -1 || hi.y() < -1) continue;
        const int i0 = GridCoordinate(lo.x(), n),
                  i1 = GridCoordinate(hi.x(), n);
        const int j0 = GridCoordinate(lo.y(), n),
                  j1 = GridCoordinate(hi.y(), n);
        const Eigen::Vector2d d = gq - gp;
        const double tolerance = margin * (d.norm() + 1e-300);
        for (int i = i0; i <= i1; ++i) {
          for (int j = j0; j <= j1; ++j) {
            // The segment's line misses the cell when all four corners lie
            // strictly on one side of it.
            int above = 0, below = 0;
            for (int c = 0; c < 4; ++c) {
              const Eigen::Vector2d corner(-1 + 2.0 * (i + (c & 1)) / n,
                                           -1 + 2.0 * (j + (c >> 1)) / n);
              const Eigen::Vector2d r = corner - gp;
              const double side = d.x() * r.y() - d.y() * r.x();
              above += side > tolerance;
              below += side < -tolerance;
            }
            if (above == 4 || below == 4) continue;
            std::vector<int>& list = lists[(face * n + i) * n + j];
            if (list.empty() || list.back() != si) list.push_back(si);
          }
        }
      }
    }
  }
  cell_begin_.assign(cells + 1, 0);
  for (int c = 0; c < cells; ++c) {
    cell_begin_[c + 1] = cell_begin_[c] + static_cast<int>(lists[c].size());
  }
  cell_sides_.reserve(cell_begin_[cells]);
  for (const std::vector<int>& list : lists) {
    cell_sides_.insert(cell_sides_.end(), list.begin(), list.end());
  }
  cell_centers_.resize(cells);
  for (int face = 0; face < 6; ++face) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        cell_centers_[(face * n + i) * n + j] =
            frame_.transpose() *
            FromGnomonic(face, -1 + (2.0 * i + 1) / n, -1 + (2.0 * j + 1) / n);
      }
    }
  }
}

void TrimRegion::ClassifyCenters(
    const std::vector<std::pair<int, int>>& loop_sides) {
  // Per loop a point r kept with respect to that loop alone: just left of
  // the middle of its first side, nearer to it than to any other side.
  std::vector<Eigen::Vector3d> reference;
  for (const auto& [begin, end] : loop_sides) {
    const Side& s0 = sides_[begin];
    const Eigen::Vector3d& mid = s0.cap.center;
    double room = s0.cap.radius;
    for (int j = begin + 1; j < end; ++j) {
      const Side& s = sides_[j];
      room = std::min(room, ArcDistance(mid, s.a, s.b, s.n));
    }
    const double step = 0.5 * std::min(room, 0.01);
    reference.push_back(
        (mid + std::tan(step) * s0.n.normalized()).normalized());
  }
  // Whether each cell's centre is kept: on each face the first cell from
  // the loops' reference points (a point is in at most one hole), the others
  // walking row by row in a serpentine, crossing from each centre to the
  // next through the two cells' sides (the arc stays in the two cells).
  const int n = grid_n_;
  center_kept_.assign(6 * n * n, 1);
  for (int face = 0; face < 6; ++face) {
    int previous = -1;
    bool kept = true;
    for (int i = 0; i < n; ++i) {
      for (int jj = 0; jj < n; ++jj) {
        const int j = i % 2 == 0 ? jj : n - 1 - jj;
        const int cell = (face * n + i) * n + j;
        const Eigen::Vector3d& q = cell_centers_[cell];
        if (previous < 0) {
          kept = true;
          for (size_t l = 0; l < loop_sides.size(); ++l) {
            if (PathParity(reference[l], q, loop_sides[l].first,
                           loop_sides[l].second)) {
              kept = false;
            }
          }
        } else {
          const Eigen::Vector3d& p = cell_centers_[previous];
          const Eigen::Vector3d m = p.cross(q);
          // The union of the two cells' ascending side lists.
          std::vector<int> both;
          std::set_union(cell_sides_.begin() + cell_begin_[previous],
                         cell_sides_.begin() + cell_begin_[previous + 1],
                         cell_sides_.begin() + cell_begin_[cell],
                         cell_sides_.begin() + cell_begin_[cell + 1],
                         std::back_inserter(both));
          for (int si : both) {
            const Side& s = sides_[si];
            kept ^= Crosses(p, q, m, s.a, s.b, s.n);
          }
        }
        center_kept_[cell] = kept;
        previous = cell;
      }
    }
  }
}

int TrimRegion::CellOf(const Eigen::Vector3d& p) const {
  int face;
  double u, v;
  Gnomonic(frame_ * p, &face, &u, &v);
  return (face * grid_n_ + GridCoordinate(u, grid_n_)) * grid_n_ +
         GridCoordinate(v, grid_n_);
}

bool TrimRegion::Contains(const Eigen::Vector3d& p) const {
  if (sides_.empty()) return true;
  const int cell = CellOf(p);
  const Eigen::Vector3d& q = cell_centers_[cell];
  const Eigen::Vector3d m = p.cross(q);
  bool kept = center_kept_[cell];
  for (int k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k) {
    const Side& s = sides_[cell_sides_[k]];
    kept ^= Crosses(p, q, m, s.a, s.b, s.n);
  }
  return kept;
}

double TrimRegion::DistanceToTrim(const Eigen::Vector3d& p,
                                  double limit) const {
  if (sides_.empty()) return limit;
  // The side with the nearest midpoint bounds the answer from above; the
  // scan then skips most chunks of sides with one dot product.
  const Side& nearest = sides_[midpoints_->Nearest(p).index];
  double best =
      std::min(limit, ArcDistance(p, nearest.a, nearest.b, nearest.n));
  double cos_best = std::cos(best), sin_best = std::sin(best);
  for (size_t c = 0; c < chunks_.size(); ++c) {
    if (Beyond(p, chunks_[c], best, cos_best, sin_best)) continue;
    const size_t end = std::min(sides_.size(), (c + 1) * kChunk);
    for (size_t i = c * kChunk; i < end; ++i) {
      const Side& s = sides_[i];
      if (Beyond(p, s.cap, best, cos_best, sin_best)) continue;
      const double d = ArcDistance(p, s.a, s.b, s.n);
      if (d < best) {
        best = d;
        cos_best = std::cos(best);
        sin_best = std::sin(best);
      }
    }
  }
  return best;
}

}  // namespace sdcb
