#include "sdcb/core/sphere/sphere_triangle_locator.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

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

// The column (or row) of gnomonic coordinate `u` in a grid of n by n cells
// over [-1, 1]^2, clamped.
int GridCell(double u, int n) {
  return std::clamp(static_cast<int>(std::floor((u + 1) / 2 * n)), 0, n - 1);
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
  n_ = std::clamp(static_cast<int>(std::ceil(std::sqrt(nf / 12.0))), 1, 512);
  const int cells = 6 * n_ * n_;
  // Two passes over the triangles' cells: count, then fill.
  std::vector<int> count(cells + 1, 0);
  cell_faces_.clear();
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> at;
    if (pass == 1) {
      cell_begin_.assign(cells + 1, 0);
      for (int c = 0; c < cells; ++c)
        cell_begin_[c + 1] = cell_begin_[c] + count[c];
      cell_faces_.resize(cell_begin_[cells]);
      at.assign(cell_begin_.begin(), cell_begin_.end() - 1);
    }
    for (Eigen::Index f = 0; f < nf; ++f) {
      if (flat[f]) continue;
      const std::array<Eigen::Vector3d, 3> t = {
          points_.row(faces_(f, 0)).transpose(),
          points_.row(faces_(f, 1)).transpose(),
          points_.row(faces_(f, 2)).transpose()};
      for (int face = 0; face < 6; ++face) {
        Eigen::Vector2d lo, hi;
        if (!FaceBox(t, face, &lo, &hi)) continue;
        for (int x = GridCell(lo[0], n_); x <= GridCell(hi[0], n_); ++x) {
          for (int y = GridCell(lo[1], n_); y <= GridCell(hi[1], n_); ++y) {
            const int c = (face * n_ + x) * n_ + y;
            if (pass == 0) {
              ++count[c];
            } else {
              cell_faces_[at[c]++] = static_cast<int>(f);
            }
          }
        }
      }
    }
  }
}

int SphereTriangleLocator::CellOf(int face, const Eigen::Vector2d& ab) const {
  return (face * n_ + GridCell(ab[0], n_)) * n_ + GridCell(ab[1], n_);
}

bool SphereTriangleLocator::Holds(int face, const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = points_.row(faces_(face, 0)).transpose();
  const Eigen::Vector3d b = points_.row(faces_(face, 1)).transpose();
  const Eigen::Vector3d c = points_.row(faces_(face, 2)).transpose();
  return Det3Sign(a, b, p) >= 0 && Det3Sign(b, c, p) >= 0 &&
         Det3Sign(c, a, p) >= 0 && Det3Sign(a, b, c) != 0;
}

SphereTriangleLocator::Location SphereTriangleLocator::Locate(
    const Eigen::Vector3d& direction) const {
  Location out;
  if (faces_.rows() == 0) return out;
  const int face = CubeFaceOf(direction);
  const int c = CellOf(face, GnomonicOnFace(direction, face));
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
