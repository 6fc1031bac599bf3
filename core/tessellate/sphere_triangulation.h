// The pattern of a tessellation: a triangulation of the unit sphere (the
// spline's domain) by directions and faces, with the adjacency of a corner
// table (each face's three half-edges know their twins). Every operation
// (edge split, edge flip, half-edge collapse, vertex move) replaces faces by
// faces covering the same part of S^2 with the same boundary, so the
// triangulation stays closed, manifold, genus 0 and without T-junctions.
//
// It holds directions and faces only; the surface is evaluated elsewhere
// (core/measure/surface_sampler.h), as OpenSubdiv keeps Bfr::Tessellation
// apart from Bfr::Surface.
//
// Half-edge h = 3 f + e runs from face(f)[e] to face(f)[(e + 1) % 3].
// Faces are counter-clockwise seen from outside. Face slots are reused: a
// split keeps its two faces' slots and appends two, a collapse keeps the
// slots of the faces it changes and kills two.
#ifndef SDCB_CORE_TESSELLATE_SPHERE_TRIANGULATION_H_
#define SDCB_CORE_TESSELLATE_SPHERE_TRIANGULATION_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "sdcb/core/common/status.h"

namespace sdcb {

class SphereTriangulation {
 public:
  using Face = std::array<int, 3>;

  // The icosahedron with every face split into four `subdivisions` times
  // (core/mesh/icosphere.h); `subdivisions` in [0, 9].
  static SphereTriangulation Icosphere(int subdivisions);
  // A triangulation from unit `directions` (#V by 3) and `faces` (#F by 3,
  // counter-clockwise seen from outside). kInvalidArgument unless every
  // directed edge is used once and its reverse once (closed, manifold,
  // consistently oriented) and every vertex is used, or, with
  // `allow_unused`, vertices in no face are kept as removed ones.
  static StatusOr<SphereTriangulation> FromFaces(
      const Eigen::MatrixX3d& directions, const Eigen::MatrixX3i& faces,
      bool allow_unused = false);

  int num_vertices() const { return static_cast<int>(vertices_.size()); }
  // Face slots, including dead ones (see alive()).
  int num_face_slots() const { return static_cast<int>(faces_.size()); }
  int num_faces() const { return num_alive_; }
  const Eigen::Vector3d& vertex(int v) const { return vertices_[v]; }
  const Face& face(int f) const { return faces_[f]; }
  bool alive(int f) const { return alive_[f] != 0; }
  bool vertex_alive(int v) const { return vertex_face_[v] >= 0; }

  // Half-edges: origin, target, twin (the same edge in the other face).
  int Origin(int h) const { return faces_[h / 3][h % 3]; }
  int Target(int h) const { return faces_[h / 3][(h % 3 + 1) % 3]; }
  int Twin(int h) const { return twin_[h]; }
  // The corner of h's face opposite h.
  int Apex(int h) const { return faces_[h / 3][(h % 3 + 2) % 3]; }
  // The half-edge a -> b, or -1 if there is no such edge.
  int HalfEdge(int a, int b) const;

  // The faces around vertex v, counter-clockwise seen from outside, and the
  // neighbours: faces[i] = (v, ring[i], ring[i + 1]) up to rotation.
  void Star(int v, std::vector<int>* faces, std::vector<int>* ring) const;

  // Splits the edge of half-edge h at the unit vector `direction` (a point
  // of the edge's arc: the caller's choice, usually the normalized
  // midpoint), and both its faces with it. Returns the new vertex. The two
  // faces keep their slots (each keeps the part at h's origin) and two
  // faces are appended.
  int SplitEdge(int h, const Eigen::Vector3d& direction);
  // The faces that would replace v's faces if v were collapsed into its
  // neighbour w (v's faces with w for v, without the two faces of edge
  // (v, w)), in the order of Star(v) and with the slots they would keep.
  // False if the collapse would not keep a triangulation of the sphere:
  // the link condition (v and w share exactly two neighbours) or a new face
  // not positively oriented.
  bool PreviewCollapse(int v, int w, std::vector<Face>* faces,
                       std::vector<int>* slots) const;
  void Collapse(int v, int w);

  // Flips the edge of half-edge h: faces (a, b, c) and (b, a, d) become
  // (a, d, c) and (d, b, c) in the same two slots. False (and nothing
  // changes) if edge (c, d) exists or a new face would not be positive.
  bool PreviewFlip(int h, std::array<Face, 2>* faces) const;
  void Flip(int h);

  // Moves vertex v to the unit vector `direction`; the caller checks that
  // its faces stay positive.
  void MoveVertex(int v, const Eigen::Vector3d& direction) {
    vertices_[v] = direction;
  }

  // Feature arcs: great-circle arcs between corner vertices, each a chain
  // of edges that the operations keep. `arc_ends[i]`: the two corner
  // vertices of arc i; `vertex_arc[v]`: the arc v lies inside,
  // kCornerVertex for an arc's end, kFreeVertex otherwise (#V entries).
  // From then on PreviewFlip refuses to flip an arc's edge, PreviewCollapse
  // to move a corner or an arc's vertex off its arc, and SplitEdge puts the
  // vertex of an arc's edge on that arc.
  static constexpr int kFreeVertex = -1;
  static constexpr int kCornerVertex = -2;
  void SetFeatures(std::vector<std::array<int, 2>> arc_ends,
                   std::vector<int> vertex_arc);
  bool has_features() const { return !arc_ends_.empty(); }
  const std::vector<std::array<int, 2>>& arc_ends() const { return arc_ends_; }
  int vertex_arc(int v) const {
    return has_features() ? vertex_arc_[v] : kFreeVertex;
  }
  bool IsFeatureVertex(int v) const { return vertex_arc(v) != kFreeVertex; }
  // Whether edge (a, b) lies on an arc (both ends on the same arc).
  bool IsFeatureEdge(int a, int b) const { return CommonArc(a, b) >= 0; }
  // The arc edge (a, b) lies on (both ends on it), or -1.
  int EdgeArc(int a, int b) const { return CommonArc(a, b); }

  // Whether (x, y, z) is a positively oriented spherical triangle, with a
  // small relative margin against rounding.
  static bool IsPositive(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                         const Eigen::Vector3d& z);
  bool IsPositive(const Face& t) const {
    return IsPositive(vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]);
  }

  // The alive vertices in increasing order, and the alive faces with their
  // corners renumbered accordingly (#F by 3).
  std::vector<int> AliveVertices() const;
  Eigen::MatrixX3i Faces() const;

 private:
  // The two faces of half-edge h = (a, b): f = (a, b, c) and its twin's
  // g = (b, a, d), and the twins of their four outer edges.
  struct Quad {
    int f, g, a, b, c, d;
    int out_bc, out_ca, out_ad, out_db;
  };
  Quad QuadOf(int h) const;
  void Link(int h, int g) {
    twin_[h] = g;
    if (g >= 0) twin_[g] = h;
  }
  void SetFace(int f, int a, int b, int c) { faces_[f] = {a, b, c}; }
  int AppendFace();
  // SplitEdge at the vertex m, already added, in no face yet.
  void SplitEdgeAt(int h, int m);

  // The arc both a and b lie on (inside or at an end), or -1.
  int CommonArc(int a, int b) const;
  bool OnArc(int v, int arc) const {
    return vertex_arc_[v] == arc ||
           (vertex_arc_[v] == kCornerVertex &&
            (arc_ends_[arc][0] == v || arc_ends_[arc][1] == v));
  }

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Face> faces_;
  std::vector<int> twin_;  // 3 per face slot
  std::vector<char> alive_;
  std::vector<int> vertex_face_;  // a face of each vertex; -1: removed
  int num_alive_ = 0;
  std::vector<std::array<int, 2>> arc_ends_;
  std::vector<int> vertex_arc_;  // per vertex, when there are arcs
  // (min corner << 32 | max corner, arc), sorted: the arc between two
  // corners without a scan of all arcs (a trim has thousands).
  std::vector<std::pair<uint64_t, int>> corner_pairs_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_SPHERE_TRIANGULATION_H_
