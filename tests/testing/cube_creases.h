// The cube [-1, 1]^3 as a spherical DCB-spline with creases made by its
// knots: the cube parameterized radially (p = x / |x|, so each edge is an arc
// of the great circle through it and its opposite edge), knots laid out by
// CubeKnotLayout, control points fitted by least squares to a grid of the
// faces, and the closed-form cube as the oracle of the distance and of the
// normals beside the edges. Shared by tests/core/spline/cube_creases_test.cpp
// and bench/crease_cube_bench.cpp.
#ifndef SDCB_TESTS_TESTING_CUBE_CREASES_H_
#define SDCB_TESTS_TESTING_CUBE_CREASES_H_

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/design_matrix.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb::testing {

struct CubeKnotLayout {
  // The 8 corners always; edge_segments - 1 evenly spaced knots inside every
  // edge (on its great circle); face_grid^2 knots inside every face.
  int edge_segments = 1;
  int face_grid = 0;
  // corner_knots knots on every edge near each of its corners, at
  // corner_gap, corner_gap * corner_ratio, ... (cube units) from the corner.
  int corner_knots = 1;
  double corner_gap = 1e-6;
  double corner_ratio = 0.25;
};

// A point (x, y, z) with x[axis] = value_axis and the other two coordinates
// a, b in the cyclic order after `axis`.
inline Eigen::Vector3d CubeCoordinates(int axis, double along, double a,
                                       double b) {
  Eigen::Vector3d x;
  x[axis] = along;
  x[(axis + 1) % 3] = a;
  x[(axis + 2) % 3] = b;
  return x;
}

inline Eigen::MatrixX3d CubeKnots(const CubeKnotLayout& layout) {
  std::vector<Eigen::Vector3d> knots;
  for (int c = 0; c < 8; ++c) {
    knots.push_back(
        Eigen::Vector3d(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1));
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (int a = -1; a <= 1; a += 2) {
      for (int b = -1; b <= 1; b += 2) {
        std::vector<double> along;
        for (int s = 1; s < layout.edge_segments; ++s) {
          along.push_back(-1.0 + 2.0 * s / layout.edge_segments);
        }
        double gap = layout.corner_gap;
        for (int c = 0; c < layout.corner_knots; ++c) {
          along.push_back(-1.0 + gap);
          along.push_back(1.0 - gap);
          gap *= layout.corner_ratio;
        }
        for (const double t : along) {
          knots.push_back(CubeCoordinates(axis, t, a, b));
        }
      }
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      for (int i = 0; i < layout.face_grid; ++i) {
        for (int j = 0; j < layout.face_grid; ++j) {
          knots.push_back(CubeCoordinates(
              axis, sign, -1.0 + (i + 0.5) * 2.0 / layout.face_grid,
              -1.0 + (j + 0.5) * 2.0 / layout.face_grid));
        }
      }
    }
  }
  Eigen::MatrixX3d matrix(knots.size(), 3);
  for (size_t i = 0; i < knots.size(); ++i) {
    matrix.row(i) = knots[i].normalized();
  }
  return matrix;
}

// The cube's point of parameter p (the radial map's inverse).
inline Eigen::Vector3d CubePoint(const Eigen::Vector3d& p) {
  return p / p.cwiseAbs().maxCoeff();
}

// The centres of an n x n grid of cells on every face.
inline std::vector<Eigen::Vector3d> CubeFaceGrid(int n) {
  std::vector<Eigen::Vector3d> points;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          points.push_back(CubeCoordinates(axis, sign,
                                           -1.0 + (i + 0.5) * 2.0 / n,
                                           -1.0 + (j + 0.5) * 2.0 / n));
        }
      }
    }
  }
  return points;
}

// The spline of degree `degree` on `knots` fitted to the cube at the
// 60 x 60 grid of every face.
inline StatusOr<SphericalSpline> FitCubeSpline(const Eigen::MatrixX3d& knots,
                                               int degree) {
  SDCB_ASSIGN_OR_RETURN(DelaunayConfigurations configurations,
                        ComputeDelaunayConfigurations(knots, degree));
  SDCB_ASSIGN_OR_RETURN(DcbBasis basis,
                        DcbBasis::Create(knots, configurations));
  const std::vector<Eigen::Vector3d> grid = CubeFaceGrid(60);
  Eigen::MatrixX3d params(grid.size(), 3), targets(grid.size(), 3);
  for (size_t r = 0; r < grid.size(); ++r) {
    params.row(r) = grid[r].normalized();
    targets.row(r) = grid[r];
  }
  const DesignMatrix design =
      BuildFormDesignMatrix(basis, params, BasisForm::kNormalized);
  const Eigen::MatrixX3d prior =
      GrevillePrior(design, targets, Eigen::MatrixX3d::Zero(basis.size(), 3));
  SDCB_ASSIGN_OR_RETURN(Eigen::MatrixX3d control,
                        SolveRegularizedLeastSquares(design, targets, prior));
  return SphericalSpline::Create(std::move(basis), std::move(control));
}

struct CubeMeasures {
  // |F(p) - cube(p)| at a 97 x 97 grid of every face (not the fitted one),
  // largest and rms, percent of the diagonal 2 sqrt(3); it bounds the
  // Hausdorff distance both ways (every point of each is matched).
  double max_percent = 0.0;
  double rms_percent = 0.0;
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();  // cube point of the max
  // The largest angle between the spline's normal and the face's at 1 % of
  // the diagonal from every edge, on both faces (41 points along each side
  // of each edge), and the same over the middle third of the edges.
  double max_normal_degrees = 0.0;
  double middle_normal_degrees = 0.0;
};

inline CubeMeasures MeasureCube(const SphericalSpline& spline) {
  CubeMeasures m;
  const double diagonal = 2.0 * std::sqrt(3.0);
  double max_distance = 0.0, sum2 = 0.0;
  const std::vector<Eigen::Vector3d> grid = CubeFaceGrid(97);
  for (const Eigen::Vector3d& x : grid) {
    const Eigen::Vector3d p = x.normalized();
    const double d = (spline.Evaluate(p) - CubePoint(p)).norm();
    if (d > max_distance) m.worst = x;
    max_distance = std::max(max_distance, d);
    sum2 += d * d;
  }
  m.max_percent = 100.0 * max_distance / diagonal;
  m.rms_percent = 100.0 * std::sqrt(sum2 / grid.size()) / diagonal;
  const double inset = 1.0 - 0.01 * diagonal;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      const Eigen::Vector3d face_normal = CubeCoordinates(axis, sign, 0, 0);
      for (int side = -1; side <= 1; side += 2) {
        for (int t = 0; t <= 40; ++t) {
          const double along = -inset + 2.0 * inset * t / 40;
          // Beside the edge where the second coordinate is +-1, then
          // beside the one where the third is.
          for (const Eigen::Vector3d& x :
               {CubeCoordinates(axis, sign, side * inset, along),
                CubeCoordinates(axis, sign, along, side * inset)}) {
            const Eigen::Vector3d n =
                spline.EvaluateDifferential(x.normalized(), JetOrder::kGradient)
                    .normal;
            const double angle =
                std::atan2(n.cross(face_normal).norm(), n.dot(face_normal)) *
                180.0 / kPi;
            m.max_normal_degrees = std::max(m.max_normal_degrees, angle);
            if (t >= 14 && t <= 26) {
              m.middle_normal_degrees =
                  std::max(m.middle_normal_degrees, angle);
            }
          }
        }
      }
    }
  }
  return m;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_CUBE_CREASES_H_
