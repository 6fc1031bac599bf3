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
//   and spline -> patch) from above. It is sampled on an (n + 1) by (n + 1)
//   lattice of every face, and on one three times as fine on the faces whose
//   coarse maximum (distance or normal angle) is above `fine_share` of its
//   limit: elsewhere a maximum between the coarse points would have to be
//   several times the one at them (docs/CAD.md has the measured ratios).
//   Faces whose sampled distance or angle exceeds the limits are refined,
//   until every face is within them or the patch budget stops the
//   refinement.
// A face's patch depends only on its corners' sphere points, so a face that
// a round keeps is neither fitted nor measured again.
#ifndef SDCB_CONVERTERS_CAD_PATCHES_H_
#define SDCB_CONVERTERS_CAD_PATCHES_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdcb/converters/bicubic_patch.h"
#include "sdcb/core/cage/sphere_cage_topology.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

struct CadPatchOptions {
  // The largest allowed distance between patches and spline, percent of
  // `length_unit`.
  double tolerance_percent = 0.05;
  // The largest allowed angle between a patch's normal and the spline's at
  // the same sphere point, degrees (bounds the normal jump across patch
  // borders by twice as much).
  double angle_degrees = 10.0;
  // The length that is 100 % (1 in a model's normalized frame).
  double length_unit = 1.0;
  // The layout never has more faces (patches).
  int max_faces = 50000;
  // Uniform refinements of the cube before the first round.
  int initial_levels = 2;
  int max_rounds = 30;
  // Fit samples per face: k by k grid centres; per edge: k inner points.
  int fit_samples_per_side = 8;
  // The coarse lattice of every face has order n: at least this, and large
  // enough for `measure_samples` points over all faces. The fine lattice
  // (order 3 n) measures the faces whose coarse maximum is above
  // `fine_share` of the tolerance or of the angle.
  int check_samples_per_side = 10;
  int measure_samples = 100000;
  double fine_share = 0.5;
  // Called after every round with a stage name ("round 3, 1584 patches")
  // and an estimate of the finished fraction in [0, 1], from the calling
  // thread.
  std::function<void(const std::string& stage, double fraction)> progress;
};

struct CadPatchSet {
  // One patch per layout face, in the spline's frame; counter-clockwise
  // seen from outside (dB/du x dB/dv points out).
  std::vector<BicubicPatch> patches;
  SphereCage layout;
  // Per face: the largest parametric distance to the spline on its
  // lattices (coarse, and fine where measured), percent, and the largest
  // angle between the patch's normal and the spline's there, degrees
  // (points where the spline is singular are skipped).
  std::vector<double> face_max_distance_percent;
  std::vector<double> face_max_normal_angle_degrees;
  double max_normal_angle_degrees = 0.0;
  double max_distance_percent = 0.0;
  // Area-weighted over the patches, on the coarse lattices.
  double rms_distance_percent = 0.0;
  // Lattice points behind the figures above (coarse and fine), and the
  // faces measured on the fine lattice.
  int64_t measured_points = 0;
  int fine_faces = 0;
  // The largest angle between the two patches' normals along shared edges
  // (33 points per edge).
  double max_normal_jump_degrees = 0.0;
  int rounds = 0;
  bool within_tolerance = false;
  std::string stop_reason;
  // Seconds spent fitting and measuring patches, over all rounds.
  double fit_seconds = 0.0, measure_seconds = 0.0;
};

// Patches for `spline` (normalized frame or any other; distances in percent
// of options.length_unit), refined until every patch is within the distance
// tolerance and the normal angle. Not reaching them is not an error: see
// within_tolerance. kInvalidArgument for bad options.
StatusOr<CadPatchSet> FitCadPatches(const SphericalSpline& spline,
                                    const CadPatchOptions& options = {});

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_PATCHES_H_
