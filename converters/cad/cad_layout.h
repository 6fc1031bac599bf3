// The quads of the sphere that the CAD network's faces cut (docs/CAD.md,
// "How the network is made"): the cube-sphere's six, or, for a spline whose
// knots hold feature arcs (a fit that kept its sharp edges,
// core/knots/feature_knots.h), quads whose sides run along the arcs, so that
// the B-rep's face borders lie on the surface's creases.
//
// Each quad q is a map of [-1, 1]^2 onto the sphere. Its sides are numbered
// as a CadNetwork face's: 0 at v = -1, 1 at u = 1, 2 at v = 1, 3 at u = -1.
// Along every side shared by two quads both use the same parameter for the
// same sphere point (the network relies on it): the quads' corners are
// ordered so that every shared side runs the same way in both, from corner
// 0 toward corners 1 and 3 and from those toward corner 2.
#ifndef SDCB_CONVERTERS_CAD_CAD_LAYOUT_H_
#define SDCB_CONVERTERS_CAD_CAD_LAYOUT_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "sdcb/core/knots/feature_knots.h"

namespace sdcb {

struct CadQuadLayout {
  enum class Kind { kCubeSphere, kFeatureFaces };
  Kind kind = Kind::kCubeSphere;
  // Quad q's corners, at (-1, -1), (1, -1), (1, 1), (-1, 1), counter-
  // clockwise seen from outside. The cube-sphere's are the cube's corners
  // (length sqrt(3)); a feature layout's are unit vectors.
  std::vector<std::array<Eigen::Vector3d, 4>> corners;
  // Whether side k of quad q lies on a crease (the surface only continuous
  // across it).
  std::vector<std::array<bool, 4>> crease;
  // The network cuts every quad into grid x grid faces.
  int grid = 1;

  int num_quads() const { return static_cast<int>(corners.size()); }
  bool has_creases() const;
  // "cube-sphere" or "feature faces".
  const char* name() const;
  // The sphere point of quad q at (u, v) in [-1, 1]^2, and its derivatives
  // when not null: the bilinear interpolation of the corners at
  // ((1 + tan(pi u / 4)) / 2, (1 + tan(pi v / 4)) / 2), projected onto the
  // sphere (on the cube-sphere, the cube face's equiangular map). A side is
  // the great-circle arc between its corners.
  Eigen::Vector3d Point(int q, double u, double v,
                        Eigen::Vector3d* du = nullptr,
                        Eigen::Vector3d* dv = nullptr) const;
};

// The sphere point of cube face c (0..5) at (u, v) in [-1, 1]^2 (the
// equiangular map), and its derivatives when not null: quad c of
// CubeSphereLayout.
Eigen::Vector3d CubeSpherePoint(int c, double u, double v,
                                Eigen::Vector3d* du = nullptr,
                                Eigen::Vector3d* dv = nullptr);

// The six faces of the cube, each cut into grid x grid network faces; no
// creases.
CadQuadLayout CubeSphereLayout(int grid);

// The layout of `arcs`' feature faces (FeatureFaces), one network face per
// quad: every feature face that is a quad as it is when the quads' corners
// can be ordered as the header says; otherwise every feature face of n
// corners cut into n quads (corner, its arcs' midpoints, the face's centre),
// which always can. The arcs are the creases. Nothing when there are no
// arcs, they do not cut the sphere into faces, or a quad's map folds.
std::optional<CadQuadLayout> FeatureQuadLayout(const KnotFeatureArcs& arcs);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_CAD_LAYOUT_H_
