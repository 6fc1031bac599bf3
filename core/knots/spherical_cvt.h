// Knot placement by a centroidal Voronoi tessellation (CVT) on the unit
// sphere (paper Sec. 4.4). Given a density rho on S^2 and the knots of the
// previous rounds (fixed), K new knots minimize the CVT energy
//
//   E = sum_k  integral over the Voronoi cell of knot t_k of
//              rho(t) |t - t_k|^2 dsigma(t)
//
// over the new knots only (|.| is the chord length in R^3). Lloyd's method:
// assign the density to the nearest knot, move every free knot to the
// density-weighted centroid of its cell projected onto S^2 (the minimizer of
// its cell's energy over the sphere), repeat. E never increases.
//
// Integration: every spherical triangle of the density's mesh is split into
// m^2 sub-triangles (barycentric grid of the flat triangle, corners pushed
// onto S^2); one sample at each sub-triangle's centroid carries the exact
// spherical area of the sub-triangle times the density there. The samples
// are a fixed quadrature whose discrete energy Lloyd lowers monotonically. With
// few knots, samples are merged into bins (CvtOptions::bins_per_knot).
#ifndef SDCB_CORE_KNOTS_SPHERICAL_CVT_H_
#define SDCB_CORE_KNOTS_SPHERICAL_CVT_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sdcb/core/common/status.h"

namespace sdcb {

// A density on S^2, piecewise linear over a spherical triangle mesh: the
// parameterized input mesh (same connectivity; vertices are the sphere
// parameters). At a point p of triangle (a, b, c) the density is
// l_a rho_a + l_b rho_b + l_c rho_c, with (l_a, l_b, l_c) the barycentric
// coordinates of the central projection of p onto the flat triangle abc.
struct SphericalDensity {
  // #V by 3 unit vectors (|v| = 1 within kUnitVectorTolerance).
  Eigen::MatrixX3d sphere_vertices;
  // #F by 3 vertex indices; the triangles must cover S^2 once (a valid
  // spherical parameterization), their orientation does not matter.
  Eigen::MatrixX3i faces;
  // #V finite values >= 0, not all 0 (only ratios matter).
  Eigen::VectorXd values;
};

// Density values for a knot-placement round: (v / max v)^alpha for values
// v >= 0, i.e. the values normalized to [0, 1] to the power alpha (paper
// Sec. 4.4, alpha = 4). Round 0 passes the curvedness kappa (rho = kappa^alpha
// up to a constant factor, which does not change the CVT); later rounds pass
// the fitting error per vertex. `values` must be finite, >= 0 and not all 0
// (kInvalidArgument otherwise); alpha > 0.
StatusOr<Eigen::VectorXd> DensityFromValues(const Eigen::VectorXd& values,
                                            double alpha = 4.0);

// Density values that spread knots as `values` asks per unit of the mesh's
// area instead of the sphere's: values x ratio^2, normalized to a largest
// value of 1, `area_ratio` the parameterization's area ratio at each vertex
// (VertexAreaRatio, core/param/parameterization_distortion.h). A CVT on a
// 2-D domain places its points at a density proportional to the square
// root of its density function (Gersho), so these knots have
// sqrt(values) x ratio per unit of sphere area: sqrt(values) per unit of
// mesh area, wherever the map compresses or stretches the surface. Sizes
// must match, values as for DensityFromValues, ratios finite and > 0
// (kInvalidArgument otherwise).
StatusOr<Eigen::VectorXd> PullBackDensity(const Eigen::VectorXd& values,
                                          const Eigen::VectorXd& area_ratio);

struct CvtOptions {
  // Lloyd iterations at most.
  int max_iterations = 100;
  // Stop when an iteration lowers E by less than this fraction of E.
  double relative_energy_tolerance = 1e-6;
  // No two knots (fixed or new) are ever closer than this angle, in radians
  // on S^2 (1e-4 rad: ~1/500 of the spacing of 5000 uniform knots). The
  // Delaunay configurations and the simplex splines need distinct knots;
  // near-duplicates give tiny determinants. A Lloyd move that would break
  // it is not taken (the knot keeps its previous position).
  double min_separation = 1e-4;
  // Quadrature resolution: the subdivision m of every triangle is the
  // smallest with #F * m^2 >= samples_per_knot * (total knots), at most
  // max_subdivision.
  int samples_per_knot = 16;
  int max_subdivision = 8;
  // With few knots on a fine mesh, samples far outnumber what the cells
  // need: when there are more than 2 * bins_per_knot * (total knots)
  // samples, they are merged into bins, each holding at most
  // 1 / (bins_per_knot * total knots) of the integral of rho^(1/2) (CVT
  // cells hold equal shares of it asymptotically), split along their widest
  // axis. A bin is its samples' weighted mean and total weight, which keeps
  // E and the centroids exact except in bins cut by a Voronoi edge.
  // 0 never merges.
  int bins_per_knot = 64;
  // Lloyd iterations skip points that provably still belong to their fixed
  // knot (see docs/KNOTS.md). The result is the same either way; false
  // searches every point every iteration (for tests and measurements).
  bool skip_settled_points = true;
  // Seed of the deterministic initialization of the new knots.
  std::uint64_t seed = 0x5dcb;
};

struct KnotPlacement {
  // (#fixed + new_knots) by 3 unit vectors: the fixed knots first, unchanged
  // and in their order, then the new knots.
  Eigen::MatrixX3d knots;
  int num_fixed = 0;
  // CVT energy E of the quadrature (units: density * steradian * chord^2)
  // for the initial knots and at the end.
  double initial_energy = 0;
  double final_energy = 0;
  // E at the start of every Lloyd iteration, then the final E: size
  // iterations + 1, non-increasing.
  std::vector<double> energy_history;
  int iterations = 0;
  bool converged = false;  // relative_energy_tolerance reached
  // Smallest angle between two knots (radians); +inf for fewer than 2.
  double min_separation = 0;
  int quadrature_samples = 0;  // points after merging into bins
};

// Places `new_knots` (>= 0) knots minimizing the CVT energy with
// `fixed_knots` (#fixed by 3 unit vectors, pairwise at least
// options.min_separation apart) fixed. New knots start at quadrature
// samples drawn with probability proportional to density times the squared
// distance to the nearest knot chosen so far (k-means++ seeding: dense
// regions, away from existing knots), from options.seed. Errors:
// kInvalidArgument for bad density/knots/options, kInvalidInput when the
// density's integral is 0, kUnsupported when the knots cannot be placed
// min_separation apart. Parallel (TBB) with fixed-size blocks and ordered
// reductions: the result is the same for any number of threads.
StatusOr<KnotPlacement> PlaceKnots(const SphericalDensity& density,
                                   const Eigen::MatrixX3d& fixed_knots,
                                   int new_knots,
                                   const CvtOptions& options = {});

struct KnotSeparation {
  double angle = 0;             // radians; +inf for fewer than 2 knots
  int first = -1, second = -1;  // rows of a closest pair, first < second
};

// The smallest angle between two rows of `knots` (#K by 3 unit vectors),
// via a k-d tree: O(K log K).
KnotSeparation MinimumKnotSeparation(const Eigen::MatrixX3d& knots);

}  // namespace sdcb

#endif  // SDCB_CORE_KNOTS_SPHERICAL_CVT_H_
