// Small folds of a fitted spline removed by the least change of its fit.
//
// A least-squares spline can turn over where the mesh creases sharply (a
// narrow groove, the gap between two fingers): a few surface samples whose
// normal points away from the mesh's, 0.0002-0.01 % of the area on CGAL's
// meshes. RepairFolds moves the control points near them so that, at every
// constrained sample u (the folded ones and their lattice neighbours),
//
//   g(u) = (F_u x F_v) . n  >=  normal_floor |F_u| |F_v|,
//
// with F_u, F_v the chart derivatives (core/spline/spherical_spline.h) and n
// the mesh's normal at the point closest to F(u) (MeshDistance::Normal: on
// an edge or a vertex, that of the triangles sharing it): the spline's normal
// within acos(normal_floor) of the mesh's. Each iteration linearizes g in the
// control points (g is bilinear in them: dg = dF_u . (F_v x n) + dF_v . (n x
// F_u)) and tries the step d that minimizes
//
//   d^T (N (x) I_3) d + sum_s w_s (g_s + J_s d - t_s)^2
//
// over the control points whose supports meet the constrained samples and
// their neighbours in N, the others fixed. N is the fit's regularized
// normal matrix, so d^T N d is exactly what the step adds to the fit's
// least-squares objective; t_s the floor where g_s is below it, else g_s
// (a satisfied sample is held, not pulled down). The weights damp each
// constraint by the damping times its own scale (w_s = 1 / (damping D_s),
// D_s = sum_j |J_sj|^2 / N_jj), so a step corrects about 1 / (1 + damping)
// of each violation. After every step the lattice is measured again where
// the step can move the surface (RemeasureSurfaceToMesh of
// core/measure/surface_deviation.h: surface -> mesh and the fold test); the
// step is taken if it leaves less folded area (or as much with less
// shortfall below the floor) and the lattice's surface -> mesh distance
// within the larger of max_distance_percent and the given spline's, and the
// damping falls by 4 (down to `damping`); else it is dropped and the damping
// grows by 4. Samples a step folded join the constrained set either way.
// Stops when nothing folds and every constrained sample meets the floor, or
// after max_iterations steps tried. The result is kept when it has at most
// half the folds of the given control points, else they stay as they are;
// folds above max_folded_percent are not tried (those of thin parts, which
// are not small: there the map, not the control points, is wrong).
#ifndef SDCB_CORE_FIT_FOLD_REPAIR_H_
#define SDCB_CORE_FIT_FOLD_REPAIR_H_

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "sdcb/core/common/status.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/dcb_basis.h"

namespace sdcb {

struct FoldRepairOptions {
  int max_iterations = 12;
  // The required cosine-like margin of g (above): 0.2 asks for the normal
  // within about 78 degrees of the mesh's.
  double normal_floor = 0.2;
  double damping = 0.1;
  // Folded area (percent of the surface's) above which no repair is tried.
  double max_folded_percent = 0.1;
  // A step may leave the lattice's surface -> mesh distance up to the larger
  // of this and the given spline's (percent of the length unit).
  double max_distance_percent = 0;
};

struct FoldRepairResult {
  // Whether the control points were replaced: when the steps taken leave at
  // most half the folds of the given ones.
  bool changed = false;
  int iterations = 0;            // steps tried (taken or dropped)
  int constrained_samples = 0;   // lattice samples constrained at the end
  int moved_control_points = 0;  // most control points one step moved
  // Folded area (percent of the surface's) at the lattice, before and after
  // (after = before unless changed).
  double folded_before_percent = 0;
  double folded_after_percent = 0;
};

// `normal_lower`: the lower triangle of the fit's regularized normal matrix
// (RegularizedNormalMatrixLower of core/fit/least_squares.h), whose
// solution `control_points` is; replaced as above.
// `lattice`: the measurement that finds the folds (its surface -> mesh half
// and fold test are used). kInternal if a factorization fails.
StatusOr<FoldRepairResult> RepairFolds(
    const DcbBasis& basis, BasisForm form,
    const Eigen::SparseMatrix<double>& normal_lower, const TriangleMesh& mesh,
    const MeshDistance& mesh_distance, const DeviationOptions& lattice,
    const FoldRepairOptions& options, Eigen::MatrixX3d* control_points);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FOLD_REPAIR_H_
