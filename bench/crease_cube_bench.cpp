// Can a spherical DCB-spline keep a cube's edges sharp through its knots
// alone? The cube [-1, 1]^3 parameterized radially (each edge an arc of the
// great circle through it and its opposite edge), knots laid out as below,
// control points fitted by least squares to a 60 x 60 grid of every face
// (tests/testing/cube_creases.h), then measured against the closed-form cube:
// control points, the largest and rms distance between the spline and the
// cube point of the same parameter on a finer grid (percent of the diagonal;
// it bounds the Hausdorff distance both ways), and the angle between the
// spline's normal and the face's at 1 % of the diagonal from every edge.
//
//   crease_cube_bench [EDGE_SEGMENTS] [FACE_GRID] [CORNER_KNOTS] [CORNER_GAP]
//                     [CORNER_RATIO] [DEGREE]
//
// Knots: the 8 corners; EDGE_SEGMENTS - 1 evenly spaced knots inside every
// edge; FACE_GRID^2 inside every face; CORNER_KNOTS knots on every edge near
// each corner, CORNER_GAP, CORNER_GAP * CORNER_RATIO, ... from it (cube
// units). Defaults 1 0 1 1e-6 0.25 3: the corners and one knot 1e-6 from
// each along each of its three edges (32 knots).
#include <cstdio>
#include <cstdlib>

#include "testing/cube_creases.h"

int main(int argc, char** argv) {
  sdcb::testing::CubeKnotLayout layout;
  if (argc > 1) layout.edge_segments = std::atoi(argv[1]);
  if (argc > 2) layout.face_grid = std::atoi(argv[2]);
  if (argc > 3) layout.corner_knots = std::atoi(argv[3]);
  if (argc > 4) layout.corner_gap = std::atof(argv[4]);
  if (argc > 5) layout.corner_ratio = std::atof(argv[5]);
  const int degree = argc > 6 ? std::atoi(argv[6]) : 3;
  const Eigen::MatrixX3d knots = sdcb::testing::CubeKnots(layout);
  auto spline = sdcb::testing::FitCubeSpline(knots, degree);
  if (!spline.ok()) {
    std::fprintf(stderr, "%s\n", spline.status().message().c_str());
    return 1;
  }
  const sdcb::testing::CubeMeasures m = sdcb::testing::MeasureCube(*spline);
  const Eigen::Vector3d gaps = Eigen::Vector3d::Ones() - m.worst.cwiseAbs();
  // The worst point lies on a face (one gap 0): its distance to the nearest
  // edge is the smaller of the other two.
  double edge = 2.0, corner = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (gaps[i] > 1e-12) edge = std::min(edge, gaps[i]);
  }
  corner = gaps.norm();
  std::printf(
      "degree %d, knots %d, control points %d: max %.4f %%, rms %.4f %% of "
      "the diagonal; normal at 1 %% from the edges %.3f deg (middle third "
      "%.3f); worst %.3f from an edge, %.3f from a corner\n",
      degree, static_cast<int>(knots.rows()), spline->basis().size(),
      m.max_percent, m.rms_percent, m.max_normal_degrees,
      m.middle_normal_degrees, edge, corner);
  return 0;
}
