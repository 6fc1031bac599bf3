// The surface of a spherical spline as a network of bicubic B-spline faces,
// tangent-continuous across their edges, for CAD (docs/CAD.md).
//
// - Layout: quads of the sphere (converters/cad/cad_layout.h), each cut into
//   G x G faces: the cube-sphere's six (each cube face projected by the
//   equiangular map, G = face_grid), or, for a spline whose knots hold
//   feature arcs, quads whose sides are the arcs (G = 1), so that the faces'
//   borders lie on the creases. A face's parameters (u, v) are its quad's
//   over the face's box, and the spline's surface over it is
//   S(sigma_q(u, v)). Along every side two faces use the same parameter.
// - Knots: every face has its own knot vectors (uniform at first, halved
//   where the face is too far from the spline). Every side shared by two
//   faces is one cubic B-spline curve whose knots are those the two faces
//   have in common along it; each face's boundary is that curve with the
//   face's other knots inserted (a linear map of the curve's poles), so the
//   faces meet exactly (C0 by construction) without a knot of one face
//   forcing a line of knots through the other. Inside a face the surface is
//   C2.
// - Fit: every free pole (corners, the sides' inner poles, the faces' inner
//   poles) in one linear least-squares problem: the faces against the
//   spline at 4 x 4 Gauss-Legendre points of every knot cell (weighted by
//   the cell's parameter area), and, along every side, the tangent-plane
//   condition at 4 Gauss-Legendre points of every span and at its ends: the
//   derivative out of one face lies in the plane of the derivative out of
//   the other and the side's tangent, with the coefficients the sphere map
//   gives (the spline satisfies them exactly); each such row is divided by
//   the spline's derivative there, so its residual is an angle. Not across
//   a crease: there the spline itself turns. One sparse
//   Cholesky factorization, three right-hand sides (x, y, z).
// - Measurement: |X_f(u, v) - S(sigma(u, v))| (the parametric distance,
//   which bounds the distance both ways since the faces' regions tile the
//   sphere) and the angle between the two normals, sampled on a lattice of
//   every knot cell (not bounded between its points); the normal jump
//   across every side but creases at 8 points of every span (of both
//   faces' knots). On a crease the spline's normal is taken a hair inside
//   the face.
// - Refinement: a knot cell over 95 % of the tolerance gets its face's spans
//   through it halved, along the directions in which the residual changes (a
//   cell at a side also along the side, and the neighbour's span there, so
//   that the shared curve gets the knot); once the distance holds but the
//   jump is over `smoothness_degrees`, the tangent rows weigh ten times
//   more. Until both hold, a budget stops it, or the distance grows over two
//   refinements in a row (where the spline folds or is singular the tangent
//   rows cannot hold).
#ifndef SDCB_CONVERTERS_CAD_CAD_NETWORK_H_
#define SDCB_CONVERTERS_CAD_CAD_NETWORK_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdcb/converters/cad/bspline_face.h"
#include "sdcb/converters/cad/cad_layout.h"
#include "sdcb/core/common/progress.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

struct CadNetworkOptions {
  // The largest allowed distance between faces and spline, percent of
  // `length_unit`.
  double tolerance_percent = 0.05;
  // The largest allowed angle between the two faces' normals across a
  // side, degrees; 180 fits the distance alone (no tangent rows).
  double smoothness_degrees = 0.5;
  // The length that is 100 % (1 in a model's normalized frame).
  double length_unit = 1.0;
  // Each cube face of the cube-sphere is cut into face_grid x face_grid
  // faces (a power of 2).
  int face_grid = 8;
  // Whether a spline whose knots hold feature arcs gets the layout of their
  // faces (FeatureQuadLayout) instead of the cube-sphere.
  bool follow_creases = true;
  // Budgets: faces (all of the layout's must fit) and free poles.
  int max_faces = 1000;
  int max_control_points = 200000;
  // The weight of the tangent rows (residuals in radians) against the
  // distance rows (in the frame's length), at the first round.
  double tangent_weight = 0.01;
  // Spans of every face's first knot vectors; rounds of refinement.
  int initial_spans = 2;
  int max_rounds = 20;
  // Each knot cell is measured on an (n + 1) x (n + 1) lattice.
  int measure_per_cell = 6;
  // Called after every round with a stage name and an estimate of the
  // finished fraction in [0, 1], from the calling thread.
  ProgressCallback progress;
};

// A side shared by two faces: one cubic B-spline curve from vertex `start`
// (parameter breaks.front()) to `end` (breaks.back()).
struct CadEdge {
  KnotBreaks breaks;
  std::vector<Eigen::Vector3d> poles;
  int start = 0, end = 0;
};

struct CadNetwork {
  // The faces, counter-clockwise seen from outside (dX/du x dX/dv points
  // out), in the spline's frame, each over its parameter box (its knots'
  // ends). Side k of a face runs along u at v = v_0 (k = 0), along v at u =
  // u_1 (1), along u at v = v_1 (2), along v at u = u_0 (3); face_edges[f][k]
  // is its edge, traversed by increasing parameter on sides 0 and 1 and by
  // decreasing parameter on sides 2 and 3. Each face's boundary is its edge
  // curves with the face's knots inserted: the same points.
  std::vector<BSplineFace> faces;
  CadQuadLayout layout;
  std::vector<int> face_quad;  // the layout's quad of every face
  std::vector<std::array<int, 4>> face_edges;
  std::vector<CadEdge> edges;
  int num_vertices = 0;
  int control_points = 0;  // free poles
  // Sampled on the knot cells' lattices: the largest parametric distance
  // (bounds both directions), percent, per face and in all; the
  // area-weighted rms; the points behind them.
  std::vector<double> face_max_distance_percent;
  double max_distance_percent = 0.0;
  double rms_distance_percent = 0.0;
  int64_t measured_points = 0;
  // The largest angle between a face's normal and the spline's at the same
  // sphere point, and how many measured points are above 90 degrees.
  double max_normal_angle_degrees = 0.0;
  int64_t folded_points = 0;
  // The largest angle between the two faces' normals along the sides that
  // are not creases, and the points measured; the edges on creases.
  double max_normal_jump_degrees = 0.0;
  int jump_points = 0;
  int crease_edges = 0;
  int rounds = 0;
  bool within_tolerance = false;  // distance and smoothness both met
  std::string stop_reason;
  double fit_seconds = 0.0, measure_seconds = 0.0;
  // The figures of every round.
  struct Round {
    int knot_cells = 0;
    int control_points = 0;
    double tangent_weight = 0.0;
    double max_distance_percent = 0.0, rms_distance_percent = 0.0;
    double max_normal_jump_degrees = 0.0, max_normal_angle_degrees = 0.0;
    int64_t folded_points = 0;
    double seconds = 0.0;
  };
  std::vector<Round> history;
};

// The network for `spline`, refined until the distance and the smoothness
// hold or a budget stops it (not an error: see within_tolerance).
// kInvalidArgument for bad options or a face budget below the layout's.
StatusOr<CadNetwork> FitCadNetwork(const SphericalSpline& spline,
                                   const CadNetworkOptions& options = {});

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_CAD_NETWORK_H_
