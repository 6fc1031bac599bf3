// The surface of a spherical spline as bicubic B-spline patches for CAD
// (docs/CAD.md): one patch per face of a quad layout on the sphere (the
// cube-sphere of core/cage/sphere_cage_topology.h, refined where a patch is
// too far from the spline), each patch a bicubic Bezier (a B-spline patch
// with no interior knots) over the face's region of the sphere.
//
// - Every layout edge is one cubic curve: its ends are the spline at the
//   edge's two sphere points, its two inner poles fitted (least squares) to
//   the spline along the edge. Both faces of an edge use that curve, pole for
//   pole, so neighbouring patches meet exactly (a closed, sewable shell);
//   the tangent planes across an edge agree only approximately (the jump of
//   the normal is measured).
// - The four inner poles of a patch are fitted to the spline at a grid of
//   the face's parameters, the boundary poles held fixed.
// - A patch is compared with the spline point of the same sphere point,
//   |B(u, v) - S(sphere(f, u, v))|: since the faces' regions tile the sphere,
//   this parametric distance bounds the distance both ways (patch -> spline
//   and spline -> patch) from above. Faces whose distance exceeds the
//   tolerance are refined, until every face is within it or the patch budget
//   stops the refinement.
#ifndef SDCB_CONVERTERS_CAD_PATCHES_H_
#define SDCB_CONVERTERS_CAD_PATCHES_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdcb/core/cage/sphere_cage_topology.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

// A bicubic Bezier patch over [0, 1]^2: poles[4 * j + i] is the pole i
// along u, j along v. Corner (0, 0) is poles[0], (1, 0) poles[3], (1, 1)
// poles[15], (0, 1) poles[12].
struct BicubicPatch {
  std::array<Eigen::Vector3d, 16> poles;

  // The point at (u, v), with its parameter derivatives when not null.
  Eigen::Vector3d Evaluate(double u, double v, Eigen::Vector3d* du = nullptr,
                           Eigen::Vector3d* dv = nullptr) const;
};

struct CadPatchOptions {
  // The largest allowed distance between patches and spline, percent of
  // `length_unit`.
  double tolerance_percent = 0.05;
  // The largest allowed angle between a patch's normal and the spline's at
  // the same sphere point, degrees (bounds the normal jump across patch
  // borders by twice as much).
  double max_normal_degrees = 10.0;
  // The length that is 100 % (1 in a model's normalized frame).
  double length_unit = 1.0;
  // The layout never has more faces (patches).
  int max_patches = 50000;
  // Uniform refinements of the cube before the first round.
  int initial_levels = 2;
  int max_rounds = 30;
  // Fit samples per face: k by k grid centres; per edge: k inner points.
  int fit_samples_per_side = 8;
  // Each round checks every face on an (n + 1) by (n + 1) lattice, n at
  // least k and large enough for `measure_samples` points in all; once every
  // face is within, on one with 3 n: that measurement is the one returned
  // (and may send faces back for refinement).
  int check_samples_per_side = 10;
  int measure_samples = 100000;
  // Called after every round: round, patches, the round's largest distance.
  std::function<void(int, int, double)> on_round;
};

struct CadPatchSet {
  // One patch per layout face, in the spline's frame; counter-clockwise
  // seen from outside (dB/du x dB/dv points out).
  std::vector<BicubicPatch> patches;
  SphereCage layout;
  // Parametric distance to the spline on the final (fine) lattice, percent.
  std::vector<double> patch_max_percent;
  // Angle between the patch's normal and the spline's on that lattice,
  // degrees (points where the spline is singular are skipped).
  std::vector<double> patch_max_normal_degrees;
  double max_normal_deviation_degrees = 0.0;
  double max_deviation_percent = 0.0;
  double rms_deviation_percent = 0.0;  // area-weighted over the patches
  int64_t measured_points = 0;
  // The largest angle between the two patches' normals along shared edges.
  double max_normal_jump_degrees = 0.0;
  int rounds = 0;
  bool within_tolerance = false;
  std::string stop_reason;
};

// Patches for `spline` (normalized frame or any other; distances in percent
// of options.length_unit), refined until every patch is within the distance
// tolerance and the normal angle. Not reaching them is not an error: see
// within_tolerance. kInvalidArgument for bad options.
StatusOr<CadPatchSet> FitCadPatches(const SphericalSpline& spline,
                                    const CadPatchOptions& options = {});

// (u, v) of face-local edge k (from corner k to corner k + 1, the corners at
// (0, 0), (1, 0), (1, 1), (0, 1)) at edge parameter t in [0, 1].
Eigen::Vector2d QuadEdgeParameter(int k, double t);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_PATCHES_H_
