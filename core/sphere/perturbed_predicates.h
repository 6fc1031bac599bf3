// Exact predicates on knots under one fixed symbolic perturbation, so that
// every combinatorial question about knots ("is knot q inside the cap of knots
// a, b, c?") has a strict yes/no answer, even for co-circular knots, knots on
// a common great circle or near-duplicates. All stages that decide "inside"
// (configurations, the DCB basis, tests) must use these functions so that
// they agree with each other. See docs/CONFIGURATIONS.md.
//
// The perturbation (Simulation of Simplicity, Edelsbrunner & Muecke 1990):
// coordinate j (0 = x, 1 = y, 2 = z) of knot i is moved by eps^(2^(3 i + j))
// for an infinitesimal eps > 0; the origin (the sphere's centre) is never
// moved. A sign that is zero for the unperturbed knots is replaced by the
// sign of the lowest-order non-vanishing term of the determinant as a
// polynomial in eps, evaluated exactly. Non-zero signs are never changed.
#ifndef SDCB_CORE_SPHERE_PERTURBED_PREDICATES_H_
#define SDCB_CORE_SPHERE_PERTURBED_PREDICATES_H_

#include <Eigen/Core>
#include <array>

namespace sdcb {

// Stands for the centre of the sphere wherever a knot index is expected.
inline constexpr int kOriginIndex = -1;

// Sign (+1 or -1, never 0) of orient3d(p_i, p_j, p_k, p_l) = sign of
// det[p_j - p_i, p_k - p_i, p_l - p_i] under the perturbation, where p_x is
// row x of `knots` (#knots by 3) or the origin for kOriginIndex. The four
// indices must be distinct; at most one may be kOriginIndex.
int PerturbedOrient3dSign(const Eigen::MatrixX3d& knots, int i, int j, int k,
                          int l);

// Position of knot q relative to the smaller cap of knots (a, b, c) (the
// side of their plane without the origin, paper Definition 3) under the
// perturbation: +1 strictly inside, -1 strictly outside; never 0. a, b, c, q
// must be distinct knot indices.
int PerturbedCapSide(const Eigen::MatrixX3d& knots, int a, int b, int c, int q);

// The plane through three knots, for testing many knots against it (loads
// the corners once). Same answers as PerturbedOrient3dSign(a, b, c, q).
class PerturbedPlane {
 public:
  // `knots` must outlive the object; a, b, c distinct knot indices.
  PerturbedPlane(const Eigen::MatrixX3d& knots, int a, int b, int c);
  // +1 or -1: the side of knot q (not a, b or c), i.e. the perturbed
  // orient3d(a, b, c, q).
  int Side(int q) const;
  // The side of the origin.
  int OriginSide() const;

 private:
  const Eigen::MatrixX3d& knots_;
  std::array<int, 3> corners_;
  std::array<Eigen::Vector3d, 3> points_;  // the corners' coordinates
};

// The cap of three knots, for testing many knots against one cap: computes
// the origin's side once. Same answers as PerturbedCapSide.
class PerturbedCap {
 public:
  // `knots` must outlive the object; a, b, c distinct knot indices.
  PerturbedCap(const Eigen::MatrixX3d& knots, int a, int b, int c);
  // True iff knot q (not a, b or c) is strictly inside the cap.
  bool Contains(int q) const { return plane_.Side(q) != origin_side_; }

 private:
  PerturbedPlane plane_;
  int origin_side_;
};

namespace internal {
// The perturbed sign computed from the symbolic expansion alone (used by
// PerturbedOrient3dSign when the exact sign is zero); exposed for tests.
int SymbolicOrient3dSign(const Eigen::MatrixX3d& knots,
                         const std::array<int, 4>& rows);
}  // namespace internal

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_PERTURBED_PREDICATES_H_
