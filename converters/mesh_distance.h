// Exact Euclidean distances from points to a triangle mesh (CGAL's AABB
// tree): the error colors of `sdcb export --colors error` and the
// spline-to-mesh half of the export's measured distance.
#ifndef SDCB_CONVERTERS_MESH_DISTANCE_H_
#define SDCB_CONVERTERS_MESH_DISTANCE_H_

#include <Eigen/Core>
#include <memory>

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

class MeshDistance {
 public:
  // `mesh` needs valid face indices; it is copied.
  explicit MeshDistance(const TriangleMesh& mesh);
  ~MeshDistance();
  MeshDistance(const MeshDistance&) = delete;
  MeshDistance& operator=(const MeshDistance&) = delete;

  // Distance from each row of `points` (#P by 3) to the closest point of the
  // mesh; #P values. Parallel (TBB), deterministic.
  Eigen::VectorXd Distances(const Eigen::MatrixX3d& points) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

// Per-vertex colors: `values` mapped linearly from [lo, hi] onto a blue -
// white - red ramp (diverging, white at the middle) or a white - red ramp
// (sequential); values outside are clamped, NaN is grey.
Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3> ColorRamp(
    const Eigen::VectorXd& values, double lo, double hi, bool diverging);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_MESH_DISTANCE_H_
