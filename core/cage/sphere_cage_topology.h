// The topology of a subdivision cage laid out on the unit sphere, refined
// adaptively (docs/CAGE.md):
//
// - quads: the cube's six faces (a cube-sphere) for Catmull-Clark cages;
// - triangles: the icosahedron's twenty faces for Loop cages;
//
// each cell refined 1-to-4 at its edges' midpoints (and its centre for a
// quad), new points pushed onto the sphere. The refined cells form a forest;
// the cage is its leaves made conforming:
//
// - 2:1 balance: a leaf whose neighbour across an edge has been refined
//   twice along that edge is refined too, so at most one point hangs on any
//   leaf edge;
// - triangles: a leaf with hanging points on one or two edges is split into
//   two or three triangles (green closure), on three edges into four;
// - quads: a leaf with hanging points on two opposite edges is split into
//   two quads, on two adjacent edges into three around its centre (corner
//   template), on four edges into four. One or three hanging points cannot
//   be closed with quads alone (a quad-meshed disk has an even number of
//   boundary vertices): odd leaves are paired with the nearest odd leaf of
//   the same size, and the edges of a shortest path between them over equal
//   leaves take a midpoint or lose one (a T-join), which makes every leaf
//   even.
//
// Every cage face keeps its corners' sphere points: its region of the sphere
// is the image of its parameter domain under the normalized bilinear (quad)
// or barycentric (triangle) map of those corners (SphereCage::SpherePoint).
#ifndef SDCB_CORE_CAGE_SPHERE_CAGE_TOPOLOGY_H_
#define SDCB_CORE_CAGE_SPHERE_CAGE_TOPOLOGY_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace sdcb {

enum class CageCellShape { kQuad, kTriangle };

// A conforming cage on the sphere.
struct SphereCage {
  int face_size = 4;  // 4 (quads) or 3 (triangles)
  // #V by 3 unit vectors: the sphere point of every cage vertex.
  Eigen::MatrixX3d sphere_points;
  // Corner vertex indices, counter-clockwise seen from outside; for
  // triangles the fourth entry is -1.
  std::vector<std::array<int, 4>> faces;
  // The leaf cell of SphereCageTopology each face belongs to.
  std::vector<int> face_cell;

  int num_vertices() const { return static_cast<int>(sphere_points.rows()); }
  int num_faces() const { return static_cast<int>(faces.size()); }
  // The sphere point of face `f` at its parameter (u, v), in OpenSubdiv's
  // parameterization: quads corner k at (0,0), (1,0), (1,1), (0,1); triangles
  // at (0,0), (1,0), (0,1) (u, v >= 0, u + v <= 1).
  Eigen::Vector3d SpherePoint(int f, double u, double v) const;
};

class SphereCageTopology {
 public:
  // The cube (quads) or the icosahedron (triangles), every cell refined
  // `levels` times (levels in [0, 8]).
  static SphereCageTopology Create(CageCellShape shape, int levels);

  CageCellShape shape() const { return shape_; }
  // The current conforming cage.
  const SphereCage& cage() const { return cage_; }
  int num_leaves() const { return num_leaves_; }
  // The refinement level of cell `cell` (0 = a face of the base solid).
  int level(int cell) const { return cells_[cell].level; }

  // Refines the given leaf cells (indices as in SphereCage::face_cell;
  // non-leaves are ignored), then whatever the 2:1 balance and the quad
  // closure need, and rebuilds the cage. Leaves 22 levels deep are not
  // refined. Deterministic.
  void Refine(const std::vector<int>& leaf_cells);

 private:
  struct Cell {
    std::array<int, 4> corners{-1, -1, -1, -1};
    int level = 0;
    int first_child = -1;  // -1: a leaf
  };

  int corner_count() const { return shape_ == CageCellShape::kQuad ? 4 : 3; }
  int Midpoint(int a, int b) const;  // -1 if the edge is unrefined
  int GetOrCreateMidpoint(int a, int b);
  void RefineCell(int cell);
  // Refines leaves until every leaf has at most one point on each edge.
  void Balance();
  // Builds cage_ from the leaves; returns the leaves that must be refined
  // first (quads whose parity cannot be fixed), empty on success.
  std::vector<int> BuildCage();
  // Quads: makes every leaf's number of edge points even (odd leaves paired
  // over equal leaves, the paths between them toggled). `mid` holds the
  // point on edge i of leaves[l] at (*mid)[l][i] (-1: none) and takes the
  // points added to `points`; returns the leaves to refine first (an odd
  // leaf without a partner), empty on success.
  std::vector<int> PairQuadParity(const std::vector<int>& leaves,
                                  std::vector<std::array<int, 4>>* mid,
                                  std::vector<Eigen::Vector3d>* points) const;

  CageCellShape shape_ = CageCellShape::kQuad;
  std::vector<Eigen::Vector3d> points_;
  std::vector<Cell> cells_;
  std::unordered_map<uint64_t, int> midpoints_;
  int num_leaves_ = 0;
  SphereCage cage_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_CAGE_SPHERE_CAGE_TOPOLOGY_H_
