// A bicubic Bezier patch (the faces of the CAD export, docs/CAD.md): its
// points and derivatives, the parameters of its sides, and the volume and
// area a closed set of patches encloses.
#ifndef SDCB_CONVERTERS_CAD_BICUBIC_PATCH_H_
#define SDCB_CONVERTERS_CAD_BICUBIC_PATCH_H_

#include <Eigen/Core>
#include <array>
#include <vector>

namespace sdcb {

// The cubic Bernstein polynomials at t, and their derivatives when `d` is
// not null.
void CubicBernstein(double t, double b[4], double d[4]);

// A bicubic Bezier patch over [0, 1]^2: poles[4 * j + i] is the pole i
// along u, j along v. Corner (0, 0) is poles[0], (1, 0) poles[3], (1, 1)
// poles[15], (0, 1) poles[12].
struct BicubicPatch {
  std::array<Eigen::Vector3d, 16> poles;

  // The point at (u, v), with its parameter derivatives when not null.
  Eigen::Vector3d Evaluate(double u, double v, Eigen::Vector3d* du = nullptr,
                           Eigen::Vector3d* dv = nullptr) const;
};

// The volume a closed set of patches encloses (counter-clockwise seen from
// outside; negative if they face inward) and their area, in their units:
// the volume is a third of the flux of x through them, integrated exactly
// (Gauss-Legendre with 5 points per direction: the integrand is a
// polynomial of degree 8 in u and in v), the area by Gauss-Legendre with 8
// points per direction. Parallel; deterministic.
struct PatchSetMeasures {
  double volume = 0.0;
  double area = 0.0;
};
PatchSetMeasures MeasurePatchSet(const std::vector<BicubicPatch>& patches);

// (u, v) of face-local edge k (from corner k to corner k + 1, the corners at
// (0, 0), (1, 0), (1, 1), (0, 1)) at edge parameter t in [0, 1].
Eigen::Vector2d QuadEdgeParameter(int k, double t);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_BICUBIC_PATCH_H_
