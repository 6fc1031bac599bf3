#include "sdcb/core/sphere/sphere_triangle_locator.h"

#include <algorithm>
#include <cmath>

#include "sdcb/core/sphere/cube_atlas.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/sphere/spherical_barycentric.h"

namespace sdcb {

SphereTriangleLocator::SphereTriangleLocator(const Eigen::MatrixX3d& points,
                                             const Eigen::MatrixX3i& faces)
    : points_(points), faces_(faces) {
  const Eigen::Index nf = faces_.rows();
  flipped_.assign(nf, 0);
  for (Eigen::Index f = 0; f < nf; ++f) {
    if (Det3Sign(points_.row(faces_(f, 0)), points_.row(faces_(f, 1)),
                 points_.row(faces_(f, 2))) < 0) {
      std::swap(faces_(f, 1), faces_(f, 2));
      flipped_[f] = 1;
    }
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
      for (int face = 0; face < 6; ++face) {
        const int axis = face / 2;
        const double sign = face % 2 == 0 ? 1.0 : -1.0;
        int positive = 0;
        Eigen::Vector2d lo(1, 1), hi(-1, -1);
        for (int c = 0; c < 3; ++c) {
          const Eigen::Vector3d d = points_.row(faces_(f, c)).transpose();
          if (sign * d[axis] > 0.0) {
            ++positive;
            const Eigen::Vector2d ab = GnomonicOnFace(d, face);
            lo = lo.cwiseMin(ab);
            hi = hi.cwiseMax(ab);
          }
        }
        // A triangle in the closed opposite hemisphere misses the face; one
        // partly in it may reach any cell of the face (rare: it spans more
        // than 35 degrees).
        if (positive == 0) continue;
        int x0 = 0, x1 = n_ - 1, y0 = 0, y1 = n_ - 1;
        if (positive == 3) {
          if (lo[0] > 1 || lo[1] > 1 || hi[0] < -1 || hi[1] < -1) continue;
          auto cell = [this](double t) {
            return std::clamp(static_cast<int>(std::floor((t + 1) / 2 * n_)), 0,
                              n_ - 1);
          };
          // A corner exactly on a cell line: both cells (rounding).
          x0 = cell(lo[0] - 1e-9);
          x1 = cell(hi[0] + 1e-9);
          y0 = cell(lo[1] - 1e-9);
          y1 = cell(hi[1] + 1e-9);
        }
        for (int x = x0; x <= x1; ++x) {
          for (int y = y0; y <= y1; ++y) {
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
  auto cell = [this](double t) {
    return std::clamp(static_cast<int>(std::floor((t + 1) / 2 * n_)), 0,
                      n_ - 1);
  };
  return (face * n_ + cell(ab[0])) * n_ + cell(ab[1]);
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
