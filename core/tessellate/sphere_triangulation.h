// The pattern of an adaptive tessellation: a conforming triangulation of the
// unit sphere (the spline's domain), refined by longest-edge bisection
// (Rivara's LEPP algorithm: before an edge is split, every face along the
// path of increasing longest edges is split first, so both faces of a split
// edge are split together). It starts from the icosahedron and is always a
// closed, manifold, genus-0 triangulation without T-junctions: every
// operation (bisection, edge flip, edge collapse) replaces faces by faces
// that cover the same part of S^2 with the same boundary.
//
// It holds directions on S^2 and faces only; the surface is evaluated
// elsewhere (core/tessellate/surface_sampler.h), and the caller supplies the
// edge lengths that order the bisections (e.g. chord lengths on the
// surface).
#ifndef SDCB_CORE_TESSELLATE_SPHERE_TRIANGULATION_H_
#define SDCB_CORE_TESSELLATE_SPHERE_TRIANGULATION_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

namespace sdcb {

class SphereTriangulation {
 public:
  using Face = std::array<int, 3>;
  // The length that orders bisections of the edge between vertices a and b
  // (symmetric; called once per edge when the edge appears). Longest edges
  // are split first; ties are broken by vertex indices, so the order is
  // strict and LEPP terminates whatever the lengths are.
  using EdgeLength = std::function<double(int a, int b)>;

  // The regular icosahedron (12 vertices, 20 faces), faces counter-clockwise
  // seen from outside. `length` orders its edges.
  static SphereTriangulation Icosahedron(const EdgeLength& length);

  int num_vertices() const { return static_cast<int>(vertices_.size()); }
  // Face slots, including dead ones (see alive()).
  int num_face_slots() const { return static_cast<int>(faces_.size()); }
  int num_faces() const { return num_alive_; }
  const Eigen::Vector3d& vertex(int v) const { return vertices_[v]; }
  const Face& face(int f) const { return faces_[f]; }
  bool alive(int f) const { return alive_[f] != 0; }

  // Splits face f at the midpoint of its longest edge, after splitting the
  // faces its longest-edge path needs (LEPP), so the result is conforming.
  // `on_vertex(v)` is called for each new vertex (the normalized midpoint of
  // the split edge) before any length involving it is asked for. New faces
  // are appended to the face slots; the split faces become dead.
  void Bisect(int f, const EdgeLength& length,
              const std::function<void(int)>& on_vertex);

  // The other face across edge (a, b), or -1.
  int Opposite(int f, int a, int b) const;

  // Alive faces as a #F by 3 index matrix and a compact numbering of the
  // vertices they use (all of them: nothing is ever removed).
  Eigen::MatrixX3i Faces() const;
  // #V by 3 vertex directions.
  Eigen::MatrixX3d Vertices() const;

 private:
  struct Edge {
    int face[2] = {-1, -1};
    double length = 0.0;
  };
  static std::uint64_t Key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) |
           static_cast<std::uint32_t>(b);
  }
  // Whether edge (a, b) is longer than (c, d) in the strict order.
  bool Longer(int a, int b, int c, int d) const;
  // The longest edge of face f as (a, b), in the face's orientation.
  std::array<int, 2> LongestEdge(int f) const;
  int AddFace(const Face& face, const EdgeLength& length);
  void DetachFace(int f);
  // Splits edge (a, b), which must be the longest edge of both its faces.
  void SplitEdge(int a, int b, const EdgeLength& length,
                 const std::function<void(int)>& on_vertex);

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Face> faces_;
  std::vector<char> alive_;
  int num_alive_ = 0;
  std::unordered_map<std::uint64_t, Edge> edges_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_SPHERE_TRIANGULATION_H_
