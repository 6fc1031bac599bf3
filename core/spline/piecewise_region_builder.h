// The polynomials of one cell of PiecewiseSurface (piecewise_surface.h) on
// its regions.
//
// A cell is a quadrilateral of a gnomonic cube-face chart p(s, t) = o +
// s e1 + t e2, (s, t) in [-1, 1]^2, crossed by some knot segments (its
// lines, at most 64) and met by the supports of some basis functions (its
// sets). A region is named by its key: bit l is a point's exact, perturbed
// sign against line l's great circle (the predicate SimplexSpline uses). On
// a region, N = sum B_i c_i and I = sum B_i (eqs. 4-6) are bivariate
// polynomials of degree k in (s, t).
//
// Unrolling the recursion (SimplexSpline::LeafPathPolynomials), B_i = w_i
// sum_T P_iT chi_T / |det T| over the triangles T of its knots. A triangle's
// indicator changes in the cell only across its edges that are lines: a
// triangle without such edges is on or off in the whole cell, and one with
// them is on exactly where the signs against those lines (bits of the key)
// take one value and the signs against its other edges, which are constant
// there, take theirs. So on a region
//   N, I = base + sum of the groups whose line signs the key has,
// where base holds the basis functions without lines in the cell and the
// triangles that are on everywhere, and a group holds, for one set of
// required line signs, sum_T sum_i (c_i, 1) w_i P_iT / |det T| over its
// triangles that are on there (found at the first region that has those
// signs). The path polynomials are made once per cell for all its basis
// functions; a region is then a few tests and additions.
//
// The sums over the triangles and groups are made at the cell's first region
// and kept in the arena for the cell's life. Every sum is taken in a fixed
// order, so a region's coefficients depend on its key only: not on which
// point of it came first or on the thread.
#ifndef SDCB_CORE_SPLINE_PIECEWISE_REGION_BUILDER_H_
#define SDCB_CORE_SPLINE_PIECEWISE_REGION_BUILDER_H_

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "sdcb/core/spline/block_arena.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

class PiecewiseRegionBuilder {
 public:
  // `spline` must outlive the builder. (o, e1, e2): the cell's chart.
  // `sets`: the basis functions whose support may meet the cell; for set j
  // and its knots' pair q (in the order (0,1), (0,2), ..., (1,2), ... of
  // its knots), pair_bits[j * P + q] is the pair's line (bit of the key) or
  // -1 if its segment does not cross the cell, P = (k + 3)(k + 2) / 2.
  // `p`: a point of the cell (nonzero). The kept sums are allocated from
  // `arena`, which must outlive the builder.
  PiecewiseRegionBuilder(const SphericalSpline& spline,
                         const Eigen::Vector3d& o, const Eigen::Vector3d& e1,
                         const Eigen::Vector3d& e2,
                         const std::vector<int>& sets,
                         const std::vector<int8_t>& pair_bits,
                         const Eigen::Vector3d& p, BlockArena* arena);
  ~PiecewiseRegionBuilder();

  // Writes the coefficients of the region `key` (p a point of it) to `out`:
  // 4 * PolynomialSize(degree) doubles, monomial m (MonomialIndex) and
  // component d = N_x, N_y, N_z, I at 4 m + d. Not thread-safe. Returns
  // false, and writes nothing, for a cell whose sums would lose the result
  // to rounding: a triangle's term above kMaxTermMagnitude, while N and I
  // are of order 1 (the thin triangles beside co-circular knots, which keep
  // a crease, give terms of 1e6 to 1e16 that cancel; a fitted free-form
  // surface's stay below 1e4). The caller evaluates the spline there.
  bool Build(const Eigen::Vector3d& p, uint64_t key, double* out);

  // Terms above this leave fewer than ~8 exact digits (of ~16) in a sum.
  static constexpr double kMaxTermMagnitude = 1e6;

 private:
  struct Cell;  // the sums as made
  struct Kept;  // and as kept
  // Fills `cell` for this builder (p: a point of the cell).
  void MakeCell(const Eigen::Vector3d& p, Cell* cell) const;

  const SphericalSpline& spline_;
  BlockArena* const arena_;
  Eigen::Vector3d o_, e1_, e2_;
  int size_ = 0;  // PolynomialSize(degree)
  // Until the first Build (MakeCell's input, then freed): 4 * size_, the
  // sets without lines; the sets with lines (ascending) whose B = w M, and
  // their pair bits.
  std::vector<double> fixed_;
  std::vector<int> sets_;
  std::vector<int8_t> pair_bits_;
  // The sets with lines whose B has limit terms (degenerate knots): their
  // pieces are made at every region.
  std::vector<int> other_sets_;
  Kept* kept_ = nullptr;  // made by the first Build
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_PIECEWISE_REGION_BUILDER_H_
