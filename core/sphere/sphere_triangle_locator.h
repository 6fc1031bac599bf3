// Point location on a triangulated region of the unit sphere: which
// spherical triangle (great-arc edges) holds a direction, and where in it.
// The map of a mesh part to its sphere (the fit's parameters) is such a
// triangulation; the texture bake (converters/gltf/texture_bake.h) asks it
// for every texel of an atlas.
#ifndef SDCB_CORE_SPHERE_SPHERE_TRIANGLE_LOCATOR_H_
#define SDCB_CORE_SPHERE_SPHERE_TRIANGLE_LOCATOR_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace sdcb {

class SphereTriangleLocator {
 public:
  // `points`: #V by 3 unit vectors; `faces`: #F by 3 rows into them, each
  // triangle within an open hemisphere, in either orientation. Both are
  // copied. Triangles are bucketed on a cube-map grid (cube faces as in
  // core/sphere/cube_atlas.h, about two triangles per cell) whose crowded
  // cells are split into quarters, for a sphere map's triangles may differ
  // in area a hundredfold and more: a cell listing more than 8 triangles is
  // split, fullest first, at most 10 times below a grid cell, while the
  // split helps (its quarters list at most 5/2 times its triangles in all),
  // and while all leaves list at most 8 #F triangles in all (or what the
  // grid lists, if more). The gnomonic projection maps great arcs to
  // segments: a cell lists the triangles that meet it, found by the box of
  // the projected corners of the triangle clipped to the cube face's pyramid
  // and by its edges' lines (with margins for rounding). Triangles with
  // det = 0 hold nothing and are left out.
  SphereTriangleLocator(const Eigen::MatrixX3d& points,
                        const Eigen::MatrixX3i& faces);

  struct Location {
    int face = -1;  // -1: no triangle holds the direction
    // Weights of the corners, summing to 1: those of the point where the
    // ray of the direction meets the flat triangle of the three corners
    // (spherical barycentric coordinates, eq. 2, normalized).
    Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();
  };

  // The lowest-numbered triangle that holds `direction` (any nonzero
  // vector), its boundary included, decided with exact signs (Det3Sign).
  Location Locate(const Eigen::Vector3d& direction) const;

  // Whether triangle `face` holds `direction` (exact, boundary included).
  bool Holds(int face, const Eigen::Vector3d& direction) const;

  // The size of the cells, for tests and benchmarks: leaf cells, the
  // triangles they list together (a triangle is listed in every leaf its
  // box meets) and the longest list.
  struct CellStats {
    int leaves = 0;
    int64_t entries = 0;
    int longest = 0;
  };
  CellStats Stats() const;

 private:
  // The leaf cell of gnomonic coordinates `ab` on cube face `face`.
  int LeafOf(int face, const Eigen::Vector2d& ab) const;

  Eigen::MatrixX3d points_;
  Eigen::MatrixX3i faces_;     // each counter-clockwise seen from outside
  std::vector<char> flipped_;  // per face: corners 1 and 2 swapped
  int n_ = 1;                  // grid cells per cube-face side
  // Per cell (the grid's 6 n^2 first), the first of its four quarters, or -1
  // for a leaf.
  std::vector<int> cell_child_;
  std::vector<int> cell_begin_;  // per cell + 1: offsets into cell_faces_
  std::vector<int> cell_faces_;  // per leaf, ascending
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_SPHERE_TRIANGLE_LOCATOR_H_
