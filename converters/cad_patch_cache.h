// The patches of the CAD export's successive layouts (converters/
// cad_patches.h): a face's patch depends only on its corners' sphere points,
// so a face a round keeps is neither fitted nor measured again; the new
// faces and edges of a round are fitted, and faces measured, in batches of
// surface evaluations (PiecewiseSurface::EvaluateMany). Used by
// FitCadPatches.
#ifndef SDCB_CONVERTERS_CAD_PATCH_CACHE_H_
#define SDCB_CONVERTERS_CAD_PATCH_CACHE_H_

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "sdcb/converters/bicubic_patch.h"
#include "sdcb/converters/cad_patches.h"
#include "sdcb/core/cage/sphere_cage_topology.h"
#include "sdcb/core/spline/piecewise_surface.h"

namespace sdcb {

// The exact identity of a sphere point (its coordinates' bits); a face is
// its corners' in order, an edge its two ends, the smaller first.
using PointKey = std::array<uint64_t, 3>;
PointKey KeyOf(const Eigen::Vector3d& p);

template <size_t N>
struct KeyHash {
  size_t operator()(const std::array<PointKey, N>& k) const {
    uint64_t h = 1469598103934665603ull;
    for (const PointKey& p : k) {
      for (uint64_t x : p) h = (h ^ x) * 1099511628211ull + (h >> 29);
    }
    return static_cast<size_t>(h);
  }
};

using FaceKey = std::array<PointKey, 4>;
using EdgeKeyPoints = std::array<PointKey, 2>;
// Local edge c of a face, from corner c to c + 1: its ends, smaller first.
EdgeKeyPoints EdgeKeyOf(const FaceKey& face, int c);

// A face's patch and what its lattices measured (distances in the spline's
// units, angles in degrees).
struct FaceRecord {
  BicubicPatch patch;
  int lattice = 0;  // coarse order n; 0: not measured
  double max_distance = 0.0, max_angle = 0.0;
  double sum_squares = 0.0, sum_area = 0.0;  // trapezoid weights
  bool fine = false;  // measured on the lattice of order 3 n
  double fine_max_distance = 0.0, fine_max_angle = 0.0;
  double Distance() const { return fine ? fine_max_distance : max_distance; }
  double Angle() const { return fine ? fine_max_angle : max_angle; }
};

// The patches of the faces of successive layouts: a face whose corners a
// previous layout had keeps its patch and measurements; new faces and edges
// are fitted in one batch of surface evaluations.
class PatchCache {
 public:
  PatchCache(const PiecewiseSurface& surface, const CadPatchOptions& options);

  // The record of every face of `layout` (fitting the new ones); records of
  // faces the layout no longer has are dropped. Pointers stay valid until
  // the next call.
  std::vector<FaceRecord*> Update(const SphereCage& layout);

  // Measures `faces` of `layout` on their lattice of order n (coarse) or
  // 3 n (fine).
  void Measure(const SphereCage& layout, const std::vector<int>& faces,
               const std::vector<FaceRecord*>& records, int n, bool fine) const;

 private:
  static constexpr int kInner[4] = {5, 6, 9, 10};

  const PiecewiseSurface& surface_;
  const int k_;
  std::vector<std::array<double, 4>> edge_basis_;
  Eigen::Matrix2d edge_inverse_;
  Eigen::MatrixXd full_, design_;
  Eigen::LDLT<Eigen::Matrix4d> solver_;
  std::unordered_map<FaceKey, FaceRecord, KeyHash<4>> faces_;
  std::unordered_map<EdgeKeyPoints, std::array<Eigen::Vector3d, 4>, KeyHash<2>>
      edges_;
};

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_PATCH_CACHE_H_
