#include "sdcb/core/sphere/sphere_triangle_locator.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <queue>
#include <utility>

#include "sdcb/core/sphere/cube_atlas.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/sphere/spherical_barycentric.h"

namespace sdcb {
namespace {

// Gnomonic coordinates are trusted to within kPad (rounding makes errors
// below 1e-14 for the coordinates in [-1, 1] that matter): every box is
// widened by it, and the cube face's pyramid is widened by it before a
// triangle is clipped to it.
constexpr double kPad = 1e-9;

// The box, widened by kPad, of the gnomonic coordinates on cube face `face`
// of the points of the spherical triangle `t` (counter-clockwise, within an
// open hemisphere) whose cube face is `face` (core/sphere/cube_atlas.h: the
// pyramid |x_k| <= s x_axis, s the face's sign, k the two other axes);
// false when it has none. The triangle's cone is clipped to the pyramid
// widened by kPad (Sutherland-Hodgman on the corner vectors: the planes go
// through the origin) and the clipped corners are projected. A clipped
// corner may slide along its edge by rounding only where the edge runs
// within ~1e-15 of a widened plane, outside the pyramid itself, so the box
// still covers every point of the triangle in the pyramid.
bool FaceBox(const std::array<Eigen::Vector3d, 3>& t, int face,
             Eigen::Vector2d* lo, Eigen::Vector2d* hi) {
  const int axis = face / 2;
  const double sign = face % 2 == 0 ? 1.0 : -1.0;
  int positive = 0;
  for (const Eigen::Vector3d& c : t) positive += sign * c[axis] > 0.0;
  // A triangle in the closed opposite hemisphere misses the face.
  if (positive == 0) return false;
  const Eigen::Vector2d whole(1 + kPad, 1 + kPad);
  // The flat triangle's distance from the origin bounds every clipped
  // corner's length from below; a triangle spanning nearly a hemisphere
  // (distance < 1/4) may reach any cell of the face.
  const Eigen::Vector3d normal = (t[1] - t[0]).cross(t[2] - t[0]);
  if (!(t[0].dot(normal) >= 0.25 * normal.norm())) {
    *lo = -whole;
    *hi = whole;
    return true;
  }
  std::array<Eigen::Vector3d, 8> poly, next;
  int m = 3;
  std::copy(t.begin(), t.end(), poly.begin());
  for (int plane = 0; plane < 4 && m > 0; ++plane) {
    const int k = (axis + 1 + plane / 2) % 3;
    const double side = plane % 2 == 0 ? 1.0 : -1.0;
    auto h = [&](const Eigen::Vector3d& x) {
      return (1 + kPad) * sign * x[axis] - side * x[k];
    };
    int out = 0;
    for (int i = 0; i < m; ++i) {
      const Eigen::Vector3d& a = poly[i];
      const Eigen::Vector3d& b = poly[(i + 1) % m];
      const double ha = h(a), hb = h(b);
      if (ha >= 0) next[out++] = a;
      if ((ha >= 0) != (hb >= 0)) {
        next[out++] = a + ha / (ha - hb) * (b - a);
      }
    }
    m = out;
    std::swap(poly, next);
  }
  if (m == 0) return false;
  *lo = whole;
  *hi = -whole;
  for (int i = 0; i < m; ++i) {
    // Clipped corners are at least 1/4 long and in the widened pyramid, so
    // s x_axis >= 1/8; anything else is rounding gone wrong: the whole face.
    if (!(sign * poly[i][axis] >= 0.125)) {
      *lo = -whole;
      *hi = whole;
      return true;
    }
    const Eigen::Vector2d ab = GnomonicOnFace(poly[i], face);
    *lo = lo->cwiseMin(ab);
    *hi = hi->cwiseMax(ab);
  }
  *lo = (lo->array() - kPad).cwiseMax(-whole.array());
  *hi = (hi->array() + kPad).cwiseMin(whole.array());
  return true;
}

// Det3Sign(a, b, c), the same answer, with a floating-point filter first
// that spares most calls into CGAL's predicate (Holds runs for every listed
// triangle a query meets). Evaluated as below, det[a b c] is within
// 5 u P + O(u^2) of the exact value in round-to-nearest (u = 2^-53; P is
// the same sum with every product's absolute value: 2u from each 2 x 2
// minor, u from its product with a_i, 2u from the two additions; fused
// multiply-adds only drop roundings), and within 10 u P in any rounding
// mode, so beyond 1e-14 P its sign is exact. Otherwise, and where that
// bound is below 1e-290 (products may underflow, and their absolute errors
// would matter) or not finite (overflow), Det3Sign decides.
int FilteredDet3Sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& c) {
  const double p0 = b[1] * c[2], q0 = b[2] * c[1];
  const double p1 = b[2] * c[0], q1 = b[0] * c[2];
  const double p2 = b[0] * c[1], q2 = b[1] * c[0];
  const double det = a[0] * (p0 - q0) + a[1] * (p1 - q1) + a[2] * (p2 - q2);
  const double permanent = std::abs(a[0]) * (std::abs(p0) + std::abs(q0)) +
                           std::abs(a[1]) * (std::abs(p1) + std::abs(q1)) +
                           std::abs(a[2]) * (std::abs(p2) + std::abs(q2));
  const double bound = 1e-14 * permanent;
  if (bound > 1e-290) {
    if (det > bound) return 1;
    if (det < -bound) return -1;
  }
  return Det3Sign(a, b, c);
}

// The column (or row) of gnomonic coordinate `u` in a grid of n by n cells
// over [-1, 1]^2, clamped.
int GridCell(double u, int n) {
  return std::clamp(static_cast<int>(std::floor((u + 1) / 2 * n)), 0, n - 1);
}

// A cell splits into four while it lists more than kLeafTriangles, at most
// kMaxDepth times below a grid cell (1/1024 of its side), unless its
// quarters would list more than 5/2 times its triangles together, and while
// the leaves list at most kEntriesPerTriangle times the triangles (or what
// the grid alone lists, if more: its cells are about as large as the
// triangles on average, so it lists a triangle a few times).
constexpr int kLeafTriangles = 8;
constexpr int kMaxDepth = 10;
constexpr int kEntriesPerTriangle = 8;

// A triangle on one cube face: its box (FaceBox) and its edges' lines. On
// the face's plane x = s e_k + u e_k1 + v e_k2 (k the face's axis, s its
// sign, k1, k2 the next axes), det[t_i t_i+1 x] = L_i(u, v) = line[i] .
// (s, u, v), with (line[i][0], line[i][1], line[i][2]) = the k, k1, k2
// components of t_i x t_i+1; the triangle (counter-clockwise) is where all
// three are >= 0, in front of the face's plane or not.
struct TriangleBox {
  int triangle = 0;
  int face = 0;
  Eigen::Vector2d lo, hi;
  std::array<Eigen::Vector3d, 3> line;
};

// A cell: the closed square [lo, hi] of gnomonic coordinates on its face.
struct Square {
  Eigen::Vector2d lo, hi;
};

Square GridSquare(int x, int y, int n) {
  return {Eigen::Vector2d(-1.0 + 2.0 * x / n, -1.0 + 2.0 * y / n),
          Eigen::Vector2d(-1.0 + 2.0 * (x + 1) / n, -1.0 + 2.0 * (y + 1) / n)};
}

Eigen::Vector2d Middle(const Square& s) { return 0.5 * (s.lo + s.hi); }

// The quarter of `s` that holds `ab` (a point of `s`): 2 * (a in the upper
// half) + (b in the upper half); a point on a middle line goes up.
int QuarterOf(const Square& s, const Eigen::Vector2d& ab) {
  const Eigen::Vector2d m = Middle(s);
  return 2 * (ab[0] >= m[0]) + (ab[1] >= m[1]);
}

Square Quarter(const Square& s, int q) {
  const Eigen::Vector2d m = Middle(s);
  Square out = s;
  (q / 2 == 1 ? out.lo : out.hi)[0] = m[0];
  (q % 2 == 1 ? out.lo : out.hi)[1] = m[1];
  return out;
}

// Whether the triangle of `b` may meet the closed square `s`: their boxes
// meet and no edge's line has all four corners clearly outside. The lines'
// values carry rounding errors below 3e-15 (unit corners, |u|, |v| <= 1),
// and a query's coordinates may be off by 1e-14 (|grad L_i| <= |line[i]|),
// so "clearly" is below -(1e-12 + 1e-9 |line[i]|_1).
bool Meets(const TriangleBox& b, const Square& s) {
  if (b.lo[0] > s.hi[0] || b.hi[0] < s.lo[0] || b.lo[1] > s.hi[1] ||
      b.hi[1] < s.lo[1]) {
    return false;
  }
  const double sign = b.face % 2 == 0 ? 1.0 : -1.0;
  for (const Eigen::Vector3d& l : b.line) {
    const double tol = 1e-12 + 1e-9 * l.lpNorm<1>();
    const double at = sign * l[0];
    if (at + l[1] * s.lo[0] + l[2] * s.lo[1] < -tol &&
        at + l[1] * s.hi[0] + l[2] * s.lo[1] < -tol &&
        at + l[1] * s.lo[0] + l[2] * s.hi[1] < -tol &&
        at + l[1] * s.hi[0] + l[2] * s.hi[1] < -tol) {
      return false;
    }
  }
  return true;
}

// The cells of the grid of n by n cells per cube face for `boxes` (of
// `triangles` triangles), split as above.
struct Cells {
  // As SphereTriangleLocator's cell_child_, cell_begin_, cell_faces_.
  std::vector<int> child, begin, faces;
};
Cells BuildCells(int n, const std::vector<TriangleBox>& boxes,
                 Eigen::Index triangles) {
  // Cells: the grid's 6 n^2 (cell (face, x, y) is (face n + x) n + y), then
  // quarters four at a time. While building, each lists its triangles' boxes
  // (indices into `boxes`, ascending) at [begin, begin + count) of `listed`,
  // where a split cell's list stays unused.
  Cells out;
  const int grid_cells = 6 * n * n;
  std::vector<Square> square(grid_cells);
  std::vector<int> depth(grid_cells, 0), begin(grid_cells + 1, 0),
      count(grid_cells, 0);
  out.child.assign(grid_cells, -1);
  for (int c = 0; c < grid_cells; ++c) {
    square[c] = GridSquare(c / n % n, c % n, n);
  }
  // Two passes over the boxes' grid cells: count, then fill.
  std::vector<int> listed;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      for (int c = 0; c < grid_cells; ++c) begin[c + 1] = begin[c] + count[c];
      listed.resize(begin[grid_cells]);
      std::fill(count.begin(), count.end(), 0);
    }
    for (size_t i = 0; i < boxes.size(); ++i) {
      const TriangleBox& b = boxes[i];
      for (int x = GridCell(b.lo[0], n); x <= GridCell(b.hi[0], n); ++x) {
        for (int y = GridCell(b.lo[1], n); y <= GridCell(b.hi[1], n); ++y) {
          const int c = (b.face * n + x) * n + y;
          if (!Meets(b, square[c])) continue;
          if (pass == 1) listed[begin[c] + count[c]] = static_cast<int>(i);
          ++count[c];
        }
      }
    }
  }
  begin.pop_back();
  // Split the fullest cell first (ties: the lowest), so a cut budget is
  // spent where the lists are longest.
  const size_t budget = std::max(
      listed.size(), static_cast<size_t>(kEntriesPerTriangle * triangles));
  size_t live = listed.size();
  std::priority_queue<std::pair<int, int>> fullest;  // (count, -cell)
  for (int c = 0; c < grid_cells; ++c) {
    if (count[c] > kLeafTriangles) fullest.emplace(count[c], -c);
  }
  while (!fullest.empty()) {
    const int c = -fullest.top().second;
    fullest.pop();
    const size_t start = listed.size();
    std::array<int, 4> quarter_count{};
    for (int q = 0; q < 4; ++q) {
      const Square s = Quarter(square[c], q);
      for (int i = begin[c]; i < begin[c] + count[c]; ++i) {
        const int box = listed[i];
        if (!Meets(boxes[box], s)) continue;
        listed.push_back(box);
        ++quarter_count[q];
      }
    }
    const size_t added = listed.size() - start;
    // Quarters listing on average more than 5/8 of the cell's triangles:
    // they are large against the cell (or slivers, whose boxes are), and
    // splitting would mostly copy them.
    if (2 * added > 5 * static_cast<size_t>(count[c])) {
      listed.resize(start);
      continue;
    }
    if (live + added - count[c] > budget) {
      listed.resize(start);
      break;
    }
    live += added - count[c];
    const int first = static_cast<int>(square.size());
    out.child[c] = first;
    int at = static_cast<int>(start);
    for (int q = 0; q < 4; ++q) {
      square.push_back(Quarter(square[c], q));
      depth.push_back(depth[c] + 1);
      begin.push_back(at);
      count.push_back(quarter_count[q]);
      out.child.push_back(-1);
      at += quarter_count[q];
      if (quarter_count[q] > kLeafTriangles && depth[c] + 1 < kMaxDepth) {
        fullest.emplace(quarter_count[q], -(first + q));
      }
    }
  }
  // The leaves' lists, in cell order, as triangle indices.
  const int cells = static_cast<int>(square.size());
  out.begin.assign(cells + 1, 0);
  out.faces.clear();
  out.faces.reserve(live);
  for (int c = 0; c < cells; ++c) {
    if (out.child[c] < 0) {
      for (int i = begin[c]; i < begin[c] + count[c]; ++i) {
        out.faces.push_back(boxes[listed[i]].triangle);
      }
    }
    out.begin[c + 1] = static_cast<int>(out.faces.size());
  }
  return out;
}

}  // namespace

SphereTriangleLocator::SphereTriangleLocator(const Eigen::MatrixX3d& points,
                                             const Eigen::MatrixX3i& faces)
    : points_(points), faces_(faces) {
  const Eigen::Index nf = faces_.rows();
  flipped_.assign(nf, 0);
  std::vector<char> flat(nf, 0);  // det = 0: holds no direction
  for (Eigen::Index f = 0; f < nf; ++f) {
    const int det =
        Det3Sign(points_.row(faces_(f, 0)), points_.row(faces_(f, 1)),
                 points_.row(faces_(f, 2)));
    if (det < 0) {
      std::swap(faces_(f, 1), faces_(f, 2));
      flipped_[f] = 1;
    }
    flat[f] = det == 0;
  }
  std::vector<TriangleBox> boxes;
  for (Eigen::Index f = 0; f < nf; ++f) {
    if (flat[f]) continue;
    const std::array<Eigen::Vector3d, 3> t = {
        points_.row(faces_(f, 0)).transpose(),
        points_.row(faces_(f, 1)).transpose(),
        points_.row(faces_(f, 2)).transpose()};
    for (int face = 0; face < 6; ++face) {
      TriangleBox b;
      if (!FaceBox(t, face, &b.lo, &b.hi)) continue;
      const int k = face / 2;
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d normal = t[i].cross(t[(i + 1) % 3]);
        b.line[i] = Eigen::Vector3d(normal[k], normal[(k + 1) % 3],
                                    normal[(k + 2) % 3]);
      }
      b.triangle = static_cast<int>(f);
      b.face = face;
      boxes.push_back(b);
    }
  }
  n_ = std::clamp(static_cast<int>(std::ceil(std::sqrt(nf / 12.0))), 1, 512);
  Cells cells = BuildCells(n_, boxes, nf);
  cell_child_ = std::move(cells.child);
  cell_begin_ = std::move(cells.begin);
  cell_faces_ = std::move(cells.faces);
}

int SphereTriangleLocator::LeafOf(int face, const Eigen::Vector2d& ab) const {
  const int x = GridCell(ab[0], n_), y = GridCell(ab[1], n_);
  int c = (face * n_ + x) * n_ + y;
  if (cell_child_[c] < 0) return c;
  Square s = GridSquare(x, y, n_);
  do {
    const int q = QuarterOf(s, ab);
    s = Quarter(s, q);
    c = cell_child_[c] + q;
  } while (cell_child_[c] >= 0);
  return c;
}

bool SphereTriangleLocator::Holds(int face, const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = points_.row(faces_(face, 0)).transpose();
  const Eigen::Vector3d b = points_.row(faces_(face, 1)).transpose();
  const Eigen::Vector3d c = points_.row(faces_(face, 2)).transpose();
  return FilteredDet3Sign(a, b, p) >= 0 && FilteredDet3Sign(b, c, p) >= 0 &&
         FilteredDet3Sign(c, a, p) >= 0 && FilteredDet3Sign(a, b, c) != 0;
}

SphereTriangleLocator::CellStats SphereTriangleLocator::Stats() const {
  CellStats out;
  for (size_t c = 0; c < cell_child_.size(); ++c) {
    if (cell_child_[c] >= 0) continue;
    ++out.leaves;
    out.longest = std::max(out.longest, cell_begin_[c + 1] - cell_begin_[c]);
  }
  out.entries = static_cast<int64_t>(cell_faces_.size());
  return out;
}

SphereTriangleLocator::Location SphereTriangleLocator::Locate(
    const Eigen::Vector3d& direction) const {
  Location out;
  if (faces_.rows() == 0) return out;
  const int face = CubeFaceOf(direction);
  const int c = LeafOf(face, GnomonicOnFace(direction, face));
  for (int i = cell_begin_[c]; i < cell_begin_[c + 1]; ++i) {
    const int f = cell_faces_[i];
    if (!Holds(f, direction)) continue;
    Eigen::Vector3d b =
        SphericalBarycentric(direction, points_.row(faces_(f, 0)).transpose(),
                             points_.row(faces_(f, 1)).transpose(),
                             points_.row(faces_(f, 2)).transpose());
    b /= b.sum();
    // Weights in the corner order the caller gave.
    if (flipped_[f]) std::swap(b[1], b[2]);
    out.face = f;
    out.barycentric = b;
    return out;
  }
  return out;
}

}  // namespace sdcb
