// Closest points on a triangle mesh: CGAL's AABB tree over the mesh's
// triangles, the independent distance oracle for every error sdcb reports
// (surface to mesh and the colors of `export --colors error`).
#ifndef SDCB_CORE_MESH_MESH_DISTANCE_H_
#define SDCB_CORE_MESH_MESH_DISTANCE_H_

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

class MeshDistance {
 public:
  struct Closest {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // on the mesh
    int face = -1;                                    // the triangle holding it
    double distance = 0.0;                            // |query - point|
  };

  // Builds the tree over every triangle of `mesh` that is not exactly
  // degenerate (three collinear corners: such a triangle lies on its own
  // edges, which other triangles share in a closed mesh). Long needles (a
  // CAD fan's) are held as pieces (longest-edge bisection, at most 8 pieces
  // per face over the mesh) so that queries stay local; Find still reports
  // the whole face. kInvalidInput if no triangle is left or a coordinate is
  // not finite.
  static StatusOr<MeshDistance> Create(const TriangleMesh& mesh);

  MeshDistance(MeshDistance&&) noexcept;
  MeshDistance& operator=(MeshDistance&&) noexcept;
  ~MeshDistance();

  // The closest point of the mesh to `query`. Safe to call from many threads
  // at once; deterministic.
  Closest Find(const Eigen::Vector3d& query) const;

  // The same closest point, the search started from `near` (a point of the
  // mesh on triangle near.face, e.g. a neighbouring query's closest point):
  // only the boxes within |query - near.point| are visited, a few when the
  // two are close. Where two triangles are equally close, the face reported
  // may differ from Find's (near.face is kept on a tie). Deterministic.
  Closest FindNear(const Eigen::Vector3d& query, const Closest& near) const;

  // The distance from each row of `points` (#P by 3) to the mesh; #P values.
  // Parallel (TBB), deterministic.
  Eigen::VectorXd Distances(const Eigen::MatrixX3d& points) const;

  // Unit normal of triangle `face` (right-hand rule over its corner order),
  // zero for an exactly degenerate triangle.
  Eigen::Vector3d FaceNormal(int face) const;

  // Whether `direction` points away from the mesh's orientation at the
  // closest point `c`: its dot product with the normal of c.face is
  // negative, and, when c lies on an edge or a vertex of that triangle
  // (within 1e-9 of its size), with the normals of every triangle sharing
  // that edge or vertex too (at a crease the mesh has no single normal).
  bool Opposes(const Closest& c, const Eigen::Vector3d& direction) const;

  // The mesh's unit normal at the closest point `c`: that of c.face inside
  // it; on an edge or a vertex (as for Opposes) the normalized sum of the
  // normals of the triangles sharing it, whichever of them c.face is.
  Eigen::Vector3d Normal(const Closest& c) const;

 private:
  // c.face, or the triangles sharing the edge or vertex c lies on (as for
  // Opposes), ascending.
  std::vector<int> FacesHolding(const Closest& c) const;
  struct Tree;
  explicit MeshDistance(std::unique_ptr<Tree> tree);
  std::unique_ptr<Tree> tree_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_MESH_DISTANCE_H_
