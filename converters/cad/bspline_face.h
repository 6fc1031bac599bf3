// A bicubic B-spline surface over a box with clamped knot vectors: the
// faces of the CAD export's network (converters/cad/cad_network.h). Evaluation
// follows the Cox-de Boor recursion (Piegl and Tiller, "The NURBS Book",
// algorithms A2.1-A2.3) written here.
#ifndef SDCB_CONVERTERS_CAD_BSPLINE_FACE_H_
#define SDCB_CONVERTERS_CAD_BSPLINE_FACE_H_

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "sdcb/converters/cad/bicubic_patch.h"

namespace sdcb {

// The distinct knots of a clamped cubic knot vector: b_0 < b_1 < ... < b_m
// (m spans); b_0 and b_m have multiplicity 4, the others 1, so the spline
// has m + 3 poles and is C2 inside.
using KnotBreaks = std::vector<double>;

// The span s of `breaks` holding x (b_s <= x < b_{s+1}; x = b_m is in the
// last span; x outside [b_0, b_m] in the first or last span).
int KnotSpan(const KnotBreaks& breaks, double x);

// The four cubic B-splines that are not zero in span s at x (the basis
// functions of poles s .. s + 3), and their derivatives when `d` is not
// null.
void CubicBSplineBasis(const KnotBreaks& breaks, int s, double x, double n[4],
                       double d[4]);

// The matrix (fine poles by coarse poles) that gives the poles of a spline
// on `coarse` in the knots of `fine` (which must hold every knot of
// `coarse`, between the same ends): the same curve, knots inserted.
Eigen::MatrixXd KnotInsertionMatrix(const KnotBreaks& coarse,
                                    const KnotBreaks& fine);

// The Greville abscissa of pole i (the mean of its three inner knots): b_0
// for the first pole, b_m for the last.
double GrevilleAbscissa(const KnotBreaks& breaks, int i);

struct BSplineFace {
  KnotBreaks u_breaks, v_breaks;
  // poles[j * num_u() + i]: pole i along u, j along v.
  std::vector<Eigen::Vector3d> poles;

  int num_u() const { return static_cast<int>(u_breaks.size()) + 2; }
  int num_v() const { return static_cast<int>(v_breaks.size()) + 2; }
  // The point at (u, v) in the knots' box, with its derivatives when not
  // null.
  Eigen::Vector3d Evaluate(double u, double v, Eigen::Vector3d* du = nullptr,
                           Eigen::Vector3d* dv = nullptr) const;
  // The face as bicubic Bezier patches, one per knot cell (u fastest), each
  // over its cell mapped to [0, 1]^2 (Boehm's knot insertion).
  std::vector<BicubicPatch> BezierPatches() const;
};

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_BSPLINE_FACE_H_
