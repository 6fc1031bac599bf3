// Spherical parameterization of a closed genus-0 mesh (paper Sec. 4.3): a
// point on the unit sphere for every vertex such that the sphere triangles,
// with the mesh's connectivity, tile S^2 without folds (a bijection), and
// the distortion energy of eq. (12),
//   E = sum_T area(T_M) * E_angle(T) * E_area(T)^lambda,
// is small (see core/param/parameterization_distortion.h for the energies).
//
// Method, coarse to fine over a progressive mesh (core/mesh/mesh_hierarchy.h):
// 1. Collapse edges down to a small base mesh.
// 2. Embed the base mesh: remove one vertex, place the rest by a Tutte
//    (uniform barycentric) embedding of the remaining disk in the plane
//    z = 1 with its boundary on a convex polygon, project centrally onto
//    S^2 (central projection keeps every orientation sign) and put the
//    removed vertex at the south pole. This is a bijection by Tutte's
//    theorem.
// 3. Minimize E by a greedy per-vertex line search along great circles:
//    each vertex moves along the descent direction of its one-ring energy,
//    and a move is taken only if every triangle of the one-ring stays
//    positively oriented (exact sign of det[s0 s1 s2]) and the energy drops.
//    Vertices of one color of a greedy graph coloring never share a
//    triangle and are updated in parallel: the result does not depend on
//    the number of threads.
// 4. Undo collapses level by level (vertex splits). A new vertex is placed
//    inside the kernel of its one-ring on the sphere (checked exactly, the
//    fattest of a few candidates), relaxed by a few descent steps, then
//    step 3 runs on the level.
// 5. For lambda > 1, lambda rises gradually (continuation, see the options).
// A final exact check verifies every triangle's orientation and that the
// triangles cover the sphere once (total spherical area 4*pi).
#ifndef SDCB_CORE_PARAM_SPHERICAL_PARAMETERIZATION_H_
#define SDCB_CORE_PARAM_SPHERICAL_PARAMETERIZATION_H_

#include <Eigen/Core>
#include <functional>
#include <string>

#include "sdcb/core/common/progress.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct SphericalParameterizationOptions {
  // Exponent of the area term in eq. (12), > 0 (the area term is the
  // barrier against folds). Larger values trade angle distortion for area
  // distortion. The paper's Table 1 uses 0.2 and 10; the default 1 balances
  // both.
  double lambda = 1.0;
  // Worker threads; 0 = all cores. The result is the same for any value.
  int threads = 0;
  // Vertices of the coarsest mesh of the hierarchy.
  int base_vertices = 200;
  // Each level has about this many times the vertices of the one before.
  double level_growth = 2.0;
  // Optimization sweeps (every vertex once) on the base mesh, on every finer
  // level and on the finest (input) level; a level stops early when a sweep
  // lowers E by less than the tolerance times E. Small levels (at most
  // `small_level_fraction` of the input's vertices, and at most
  // `small_level_vertices`) are cheap and decide where area goes, so they
  // use the tighter `level_tolerance`; larger ones use `finest_tolerance`.
  // Up to 40,000 input vertices the fraction is the smaller bound; the cap
  // keeps large levels of large inputs off the tight tolerance (CGAL's
  // armadillo refined to 1.66M vertices: a 51K-vertex level takes 8 s at
  // 100 sweeps).
  int base_sweeps = 300;
  int level_sweeps = 100;
  int finest_sweeps = 20;
  double level_tolerance = 1e-5;
  double finest_tolerance = 1e-4;
  double small_level_fraction = 0.1;
  int small_level_vertices = 4000;
  // Levels of more than `large_level_vertices` (the finest included) stop at
  // `large_level_tolerance` and after `large_level_sweeps` sweeps instead:
  // their sweeps move vertices far below any knot spacing the fit can
  // afford, and cost the most. A large level within sqrt(level_growth) of
  // the input's vertex count is not made: the level after the one before it
  // is the input (a level of nearly the input's size costs what the input's
  // does).
  int large_level_vertices = 100000;
  double large_level_tolerance = 3e-4;
  int large_level_sweeps = 10;
  // A vertex is optimized again in the next sweep only if it or a neighbor
  // lowered E by more than `active_fraction` * tolerance * E / vertices in
  // this sweep (0: if it moved at all). The vertices left out could lower E
  // by at most active_fraction times the stopping threshold per sweep.
  // 0.1 halves the moves on the bunny (parameterization 2.7 -> 1.9 CPU s,
  // E +0.002 %), but the fit of bunny_1m that followed then kept a fold
  // its default 0 does not have (docs/SCALE.md), so 0 stays the default.
  double active_fraction = 0.0;
  // Continuation for lambda > 1 (a stiff energy stalls descent from a poor
  // start): the base mesh starts at lambda = 1 and rises to
  // min(lambda, coarse_lambda), used on the following levels except the
  // last `rising_levels` ones, which rise on to `lambda`. A rise multiplies
  // lambda by `lambda_growth` per round of sweeps (`level_sweeps`, or
  // `finest_sweeps` on the finest level).
  double coarse_lambda = 1.0;
  double lambda_growth = 2.0;
  int rising_levels = 1;  // 1: only the finest level
  // Iterations of global L-BFGS on all vertices of the finest level after
  // its sweeps (0: none), stopping early when one lowers E by less than
  // `global_tolerance` times E.
  int global_iterations = 0;
  double global_tolerance = 1e-7;
  // Called with a stage name and the finished fraction in [0, 1].
  ProgressCallback progress;
};

struct SphericalParameterization {
  // #V by 3: unit vectors on S^2, row i for mesh vertex i.
  Eigen::MatrixX3d sphere;
  double energy = 0.0;  // eq. (12) at the result, mesh scaled to area 4*pi
  int levels = 0;       // optimization levels run (base included)
  int base_vertices = 0;
};

// Parameterizes `mesh`, which must pass RequireClosedGenusZero (else its
// kUnsupported status is returned). kInvalidArgument for a lambda that is
// <= 0 or not finite; kInternal if the result fails the bijection check
// (never expected).
StatusOr<SphericalParameterization> ParameterizeOnSphere(
    const TriangleMesh& mesh,
    const SphericalParameterizationOptions& options = {});

// Exact check that `sphere` (#V by 3) is a bijective map of `mesh` onto S^2:
// every row has unit length within 1e-12, every face is positively oriented
// (exact sign of det[s0 s1 s2] > 0) and the faces' spherical areas sum to
// 4*pi (the covering has degree one). The message names the first problem.
Status CheckSphericalBijection(const TriangleMesh& mesh,
                               const Eigen::MatrixX3d& sphere);

}  // namespace sdcb

#endif  // SDCB_CORE_PARAM_SPHERICAL_PARAMETERIZATION_H_
