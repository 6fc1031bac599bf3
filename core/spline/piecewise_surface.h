// A fast evaluator of a SphericalSpline: its pieces as polynomials.
//
// The surface F = N / I (eq. 6 with eq. 5; N / |x|^k for the raw basis of
// eq. 4) is a ratio of piecewise homogeneous polynomials of degree k whose
// pieces are the cells of the arrangement of the knot segments [t_a, t_b] of
// every configuration set. The sphere is covered by a cube map: each face a G x
// G grid of cells in gnomonic coordinates (great circles are straight lines
// there), each cell split into quadrants while more than 40 segments cross it.
// A leaf cell keeps the knot segments that cross it and the basis functions
// whose support meets it; a point's exact, perturbed signs against those
// segments' great circles (the predicate SimplexSpline uses) name its region,
// and each region gets, the first time a point falls in it, the bivariate
// polynomials of N and I in the cell's local gnomonic coordinates
// (PiecewiseRegionBuilder). Evaluating is a few sign tests, a lock-free hash
// probe and two polynomial evaluations; positions agree with
// SphericalSpline::Evaluate to rounding (~1e-13 relative), and so do
// normals and curvatures, from the polynomials' first and second
// derivatives, to the rounding of those. Cells still crossed by more than 64
// segments after 8 splits, and cells whose sums would cancel (terms above
// 1e6: the thin triangles beside co-circular knots that keep a crease), fall
// back to SphericalSpline. Thread-safe (regions
// are added under a per-cell lock and published atomically); results do not
// depend on the evaluation order or thread count.
#ifndef SDCB_CORE_SPLINE_PIECEWISE_SURFACE_H_
#define SDCB_CORE_SPLINE_PIECEWISE_SURFACE_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "sdcb/core/spline/block_arena.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/core/spline/surface_shape.h"

namespace sdcb {

class PiecewiseSurface {
 public:
  // `spline` must outlive this object. `grid` = G (cells per cube-face
  // side); 0 chooses it from the total length of the knot segments (about
  // ten segments per cell).
  explicit PiecewiseSurface(const SphericalSpline& spline, int grid = 0);
  ~PiecewiseSurface();
  PiecewiseSurface(const PiecewiseSurface&) = delete;
  PiecewiseSurface& operator=(const PiecewiseSurface&) = delete;

  int grid() const { return grid_; }
  // Number of regions whose polynomials have been built so far.
  int64_t num_regions() const;

  // F(p), p a nonzero vector (its direction is used).
  Eigen::Vector3d Evaluate(const Eigen::Vector3d& p) const;
  // F(p) and the unit normal of SphericalSpline::EvaluateDifferential (zero
  // where the surface is singular).
  void EvaluateWithNormal(const Eigen::Vector3d& p, Eigen::Vector3d* position,
                          Eigen::Vector3d* normal) const;
  // Rows of `directions` (#P by 3) in parallel; `normals` may be null.
  void EvaluateMany(const Eigen::MatrixX3d& directions,
                    Eigen::MatrixX3d* positions,
                    Eigen::MatrixX3d* normals) const;

  // The surface's shape at the direction of p: position, normal,
  // fundamental forms and curvatures in the chart of
  // SphericalSpline::EvaluateShape (the tangent frame of p / |p|), from the
  // first and second derivatives of the region's polynomials.
  SurfaceShape EvaluateShape(const Eigen::Vector3d& p) const;
  // EvaluateShape at each row of `directions` (#P by 3), in parallel.
  void EvaluateShapeMany(const Eigen::MatrixX3d& directions,
                         std::vector<SurfaceShape>* shapes) const;
  // Only the Gaussian and mean curvatures of EvaluateShapeMany (#P each).
  void EvaluateCurvatureMany(const Eigen::MatrixX3d& directions,
                             Eigen::VectorXd* gaussian,
                             Eigen::VectorXd* mean) const;

 private:
  struct Node;
  struct Leaf;
  struct Table;
  struct Scratch;
  class CellBuilder;  // the constructor's quadtrees
  // Fills segments_, set_segment_start_ and set_segments_ from the basis.
  void CollectSegments();
  // The leaf cell of p and p's local coordinates (s, t) in it, in [-1, 1]^2.
  int Locate(const Eigen::Vector3d& p, double* s, double* t) const;
  // The coefficients of p's region in `leaf` (monomial m, component d =
  // N_x, N_y, N_z, I at index 4 m + d), built on first use; null in a cell
  // whose sums are ill-conditioned (PiecewiseRegionBuilder::Build).
  const double* Region(const Leaf& leaf, const Eigen::Vector3d& p) const;
  const double* BuildRegion(const Leaf& leaf, const Eigen::Vector3d& p,
                            uint64_t key) const;
  void Eval(const Eigen::Vector3d& p, Eigen::Vector3d* position,
            Eigen::Vector3d* normal) const;
  template <int K>
  void EvalDegree(const Eigen::Vector3d& p, Eigen::Vector3d* position,
                  Eigen::Vector3d* normal) const;
  template <int K>
  SurfaceShape ShapeDegree(const Eigen::Vector3d& p) const;
  // store(r, shape) for each row r of `directions`, by ByLeaf.
  template <typename Store>
  void ShapesByLeaf(const Eigen::MatrixX3d& directions,
                    const Store& store) const;
  // Calls evaluate(o, r, p, out) for each row r of `directions` (p: the
  // row), leaf by leaf, in parallel, with o < kChunk its place in its chunk
  // and `width` doubles at `out` for its result; then finish(n, rows,
  // results) once per chunk of n rows, rows[o] and results + width * o for
  // o < n.
  template <typename EvaluateRow, typename FinishChunk>
  void ByLeaf(const Eigen::MatrixX3d& directions, int width,
              const EvaluateRow& evaluate, const FinishChunk& finish) const;

  const SphericalSpline& spline_;
  int grid_ = 0;
  int size_ = 0;                               // PolynomialSize(degree)
  std::vector<Node> nodes_;                    // 6 * grid^2 roots first
  std::vector<std::unique_ptr<Leaf>> leaves_;  // depth-first per root
  std::vector<std::array<int, 2>> segments_;   // knot pairs a < b
  // CSR: the segments (indices into segments_) of basis function i are
  // set_segments_[set_segment_start_[i] .. set_segment_start_[i + 1]).
  std::vector<int> set_segment_start_, set_segments_;
  // The regions' coefficients and their tables.
  mutable BlockArena arena_;
  // The batch evaluations' buffers, kept for the next call.
  mutable std::mutex scratch_mutex_;
  mutable std::vector<std::unique_ptr<Scratch>> scratch_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_PIECEWISE_SURFACE_H_
