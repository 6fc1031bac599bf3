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

  // Splits edge (a, b) at its normalized midpoint, and both its faces with
  // it (no T-junction; the four new faces stay positively oriented).
  // `on_vertex(v)` is called for the new vertex before any length involving
  // it is asked for. Bisect splits longest edges only; the remesher any.
  void SplitEdge(int a, int b, const EdgeLength& length,
                 const std::function<void(int)>& on_vertex);

  // The other face across edge (a, b), or -1.
  int Opposite(int f, int a, int b) const;
  // The face that has the directed edge a -> b (in its orientation), or -1.
  int FaceOf(int a, int b) const;
  bool HasEdge(int a, int b) const { return edges_.count(Key(a, b)) > 0; }
  bool vertex_alive(int v) const { return vertex_face_[v] >= 0; }

  // The neighbours of vertex v in counter-clockwise order (seen from
  // outside); ring[i], ring[i + 1] and v span one face.
  std::vector<int> Ring(int v) const;

  // Half-edge collapse of v into its neighbour w: the two faces of edge
  // (v, w) disappear, v's other faces get w instead of v. Fills `faces`
  // with the faces that would replace v's faces and returns true if the
  // collapse keeps a valid triangulation of the sphere: the link condition
  // (v and w share exactly two neighbours, so the result stays manifold)
  // and every new face positively oriented on the sphere.
  bool PreviewCollapse(int v, int w, std::vector<Face>* faces) const;
  void Collapse(int v, int w, const EdgeLength& length);
  // Flips edge (a, b) of faces (a, b, c), (b, a, d) to (a, d, c), (d, b, c).
  // Returns false (and does nothing) if edge (c, d) exists already or a new
  // face would not be positively oriented. `faces` gets the new faces.
  bool PreviewFlip(int a, int b, std::vector<Face>* faces) const;
  void Flip(int a, int b, const EdgeLength& length);
  // Moves vertex v to the unit vector `direction` (the caller checks the
  // faces stay positive with IsPositive) and re-measures its edges.
  void MoveVertex(int v, const Eigen::Vector3d& direction,
                  const EdgeLength& length);
  // Whether (a, b, c) is a positively oriented spherical triangle (with a
  // small relative margin against rounding).
  bool IsPositive(int a, int b, int c) const { return Positive(a, b, c); }
  // The same test for three unit vectors.
  static bool IsPositive(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                         const Eigen::Vector3d& z);
  // The faces around vertex v in counter-clockwise order: Star(v)[i] is the
  // face of Ring(v)[i] and Ring(v)[i + 1].
  std::vector<int> Star(int v) const;
  // All edges as (a, b), a < b, in increasing order of (a, b).
  std::vector<std::array<int, 2>> Edges() const;

  // The alive vertices in increasing order, and the alive faces with their
  // corners renumbered accordingly (#F by 3).
  std::vector<int> AliveVertices() const;
  Eigen::MatrixX3i Faces() const;

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
  // Whether (a, b, c) is a positively oriented spherical triangle.
  bool Positive(int a, int b, int c) const;
  // The longest edge of face f as (a, b), in the face's orientation.
  std::array<int, 2> LongestEdge(int f) const;
  int AddFace(const Face& face, const EdgeLength& length);
  void DetachFace(int f);

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Face> faces_;
  std::vector<char> alive_;
  std::vector<int> vertex_face_;  // an alive face of each vertex, -1: removed
  int num_alive_ = 0;
  std::unordered_map<std::uint64_t, Edge> edges_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_SPHERE_TRIANGULATION_H_
