#include "sdcb/core/mesh/mesh_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace sdcb {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using Traits = CGAL::AABB_traits<Kernel, Primitive>;
using AabbTree = CGAL::AABB_tree<Traits>;

Point ToPoint(const Eigen::Vector3d& v) { return Point(v.x(), v.y(), v.z()); }

// Longest-edge bisection of (a, b, c) until no edge is longer than `limit`:
// calls emit(a, b, c) per piece, returns the number of pieces (at most
// 2^depth).
template <typename Emit>
int64_t Split(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
              const Eigen::Vector3d& c, double limit, int depth, Emit emit) {
  const double ab = (b - a).squaredNorm(), bc = (c - b).squaredNorm(),
               ca = (a - c).squaredNorm();
  const double longest = std::max({ab, bc, ca});
  if (depth == 0 || longest <= limit * limit) {
    emit(a, b, c);
    return 1;
  }
  // Rotate so that (a, b) is the longest edge, then cut it at its middle.
  if (ab != longest) {
    return bc == longest ? Split(b, c, a, limit, depth, emit)
                         : Split(c, a, b, limit, depth, emit);
  }
  const Eigen::Vector3d m = 0.5 * (a + b);
  return Split(a, m, c, limit, depth - 1, emit) +
         Split(m, b, c, limit, depth - 1, emit);
}

// The closest point of the tree's triangles to `query` (the search started
// from `hint`), reported with the mesh face `faces` holds for that triangle.
MeshDistance::Closest ClosestFrom(
    const AabbTree& tree, const std::vector<Triangle>& triangles,
    const std::vector<int>& faces, const Eigen::Vector3d& query,
    const AabbTree::Point_and_primitive_id& hint) {
  const auto hit = tree.closest_point_and_primitive(ToPoint(query), hint);
  MeshDistance::Closest out;
  out.point = Eigen::Vector3d(hit.first.x(), hit.first.y(), hit.first.z());
  out.face = faces[hit.second - triangles.cbegin()];
  out.distance = (out.point - query).norm();
  return out;
}

// Pieces at most 2^kMaxSplitDepth per triangle, and kMaxPiecesPerFace per
// face over the mesh.
constexpr int kMaxSplitDepth = 12;
constexpr int64_t kMaxPiecesPerFace = 8;

}  // namespace

struct MeshDistance::Tree {
  std::vector<Triangle> triangles;
  std::vector<int> faces;                // mesh face of each triangle
  std::vector<int> first_piece;          // per mesh face, -1 if none
  std::vector<Eigen::Vector3d> normals;  // per mesh face
  Eigen::MatrixX3i corners;              // per mesh face
  Eigen::MatrixX3d vertices;
  // CSR: the faces around each vertex.
  std::vector<int> vertex_face_start, vertex_faces;
  AabbTree tree;
};

StatusOr<MeshDistance> MeshDistance::Create(const TriangleMesh& mesh) {
  if (!mesh.vertices.allFinite()) {
    return InvalidInputError("the mesh has a non-finite vertex coordinate");
  }
  auto t = std::make_unique<Tree>();
  t->normals.resize(mesh.num_faces(), Eigen::Vector3d::Zero());
  std::vector<int> kept;
  double area = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Triangle triangle(ToPoint(a), ToPoint(b), ToPoint(c));
    if (triangle.is_degenerate()) continue;  // exact collinearity test
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() > 0) t->normals[f] = n.normalized();
    area += 0.5 * n.norm();
    kept.push_back(f);
  }
  // Long needles (a CAD fan's: every one reaches from the hub to the rim)
  // have boxes that overlap everything, and a query then tests most of them:
  // the tree holds pieces of them instead (longest-edge bisection, the same
  // face), no longer than 8 times the side of a mean-area square, longer
  // while they would exceed kMaxPiecesPerFace pieces per face. The pieces
  // tile their triangle, so the closest point is the triangle's. Ordinary
  // meshes have no such triangle and keep one piece per face.
  const auto corner = [&](int f, int k) -> Eigen::Vector3d {
    return mesh.vertices.row(mesh.faces(f, k)).transpose();
  };
  const auto ignore = [](const Eigen::Vector3d&, const Eigen::Vector3d&,
                         const Eigen::Vector3d&) {};
  double limit = kept.empty()
                     ? 0.0
                     : 8.0 * std::sqrt(area / static_cast<double>(kept.size()));
  int64_t pieces = static_cast<int64_t>(kept.size());
  for (int attempt = 0; attempt < 64 && limit > 0; ++attempt, limit *= 2) {
    pieces = 0;
    for (int f : kept) {
      pieces += Split(corner(f, 0), corner(f, 1), corner(f, 2), limit,
                      kMaxSplitDepth, ignore);
    }
    if (pieces <= kMaxPiecesPerFace * static_cast<int64_t>(kept.size())) break;
  }
  t->triangles.reserve(static_cast<size_t>(pieces));
  t->faces.reserve(static_cast<size_t>(pieces));
  for (int f : kept) {
    const int64_t face_pieces =
        Split(corner(f, 0), corner(f, 1), corner(f, 2), limit, kMaxSplitDepth,
              [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c) {
                t->triangles.emplace_back(ToPoint(a), ToPoint(b), ToPoint(c));
                t->faces.push_back(f);
              });
    // A face kept whole was tested above; a piece rounded flat is dropped
    // (its neighbours cover it).
    if (face_pieces == 1) continue;
    for (int64_t k = 0; k < face_pieces; ++k) {
      const size_t i = t->triangles.size() - face_pieces + k;
      if (t->triangles[i].is_degenerate()) t->faces[i] = -1;
    }
  }
  {
    size_t kept_pieces = 0;
    for (size_t i = 0; i < t->triangles.size(); ++i) {
      if (t->faces[i] < 0) continue;
      t->triangles[kept_pieces] = t->triangles[i];
      t->faces[kept_pieces++] = t->faces[i];
    }
    t->triangles.resize(kept_pieces);
    t->faces.resize(kept_pieces);
  }
  if (t->triangles.empty()) {
    return InvalidInputError("the mesh has no non-degenerate triangle");
  }
  t->first_piece.assign(mesh.faces.rows(), -1);
  for (size_t i = t->triangles.size(); i-- > 0;) {
    t->first_piece[t->faces[i]] = static_cast<int>(i);
  }
  t->corners = mesh.faces;
  t->vertices = mesh.vertices;
  const Eigen::Index nv = mesh.vertices.rows();
  t->vertex_face_start.assign(nv + 1, 0);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) ++t->vertex_face_start[mesh.faces(f, k) + 1];
  }
  for (Eigen::Index v = 0; v < nv; ++v) {
    t->vertex_face_start[v + 1] += t->vertex_face_start[v];
  }
  t->vertex_faces.resize(t->vertex_face_start[nv]);
  std::vector<int> fill(t->vertex_face_start.begin(),
                        t->vertex_face_start.end() - 1);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      t->vertex_faces[fill[mesh.faces(f, k)]++] = static_cast<int>(f);
    }
  }
  t->tree.insert(t->triangles.begin(), t->triangles.end());
  t->tree.build();
  // The hints of the queries (CGAL's k-d tree of reference points): each
  // mesh vertex once, with a piece holding it, instead of a corner of every
  // piece (about twice as many points on a closed mesh, the same places).
  std::vector<AabbTree::Point_and_primitive_id> hints;
  hints.reserve(static_cast<size_t>(nv));
  std::vector<char> hinted(static_cast<size_t>(nv), 0);
  for (size_t i = 0; i < t->triangles.size(); ++i) {
    const int f = t->faces[i];
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      if (hinted[v]) continue;
      const Point p = ToPoint(mesh.vertices.row(v).transpose());
      const Triangle& piece = t->triangles[i];
      if (piece.vertex(0) == p || piece.vertex(1) == p ||
          piece.vertex(2) == p) {
        hinted[v] = 1;
        hints.emplace_back(p, t->triangles.cbegin() + i);
      }
    }
  }
  if (hints.empty()) {  // every corner in a piece rounded flat
    t->tree.accelerate_distance_queries();
  } else {
    t->tree.accelerate_distance_queries(hints.begin(), hints.end());
  }
  return MeshDistance(std::move(t));
}

MeshDistance::MeshDistance(std::unique_ptr<Tree> tree)
    : tree_(std::move(tree)) {}
MeshDistance::MeshDistance(MeshDistance&&) noexcept = default;
MeshDistance& MeshDistance::operator=(MeshDistance&&) noexcept = default;
MeshDistance::~MeshDistance() = default;

MeshDistance::Closest MeshDistance::Find(const Eigen::Vector3d& query) const {
  const Tree& t = *tree_;
  return ClosestFrom(t.tree, t.triangles, t.faces, query,
                     t.tree.best_hint(ToPoint(query)));
}

MeshDistance::Closest MeshDistance::FindNear(const Eigen::Vector3d& query,
                                             const Closest& near) const {
  const Tree& t = *tree_;
  const int piece =
      near.face >= 0 && near.face < static_cast<int>(t.first_piece.size())
          ? t.first_piece[near.face]
          : -1;
  if (piece < 0) return Find(query);
  return ClosestFrom(t.tree, t.triangles, t.faces, query,
                     AabbTree::Point_and_primitive_id(
                         ToPoint(near.point), t.triangles.cbegin() + piece));
}

Eigen::VectorXd MeshDistance::Distances(const Eigen::MatrixX3d& points) const {
  Eigen::VectorXd out(points.rows());
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, points.rows(), 256),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      for (Eigen::Index i = range.begin(); i < range.end();
                           ++i) {
                        out[i] = Find(points.row(i).transpose()).distance;
                      }
                    });
  return out;
}

Eigen::Vector3d MeshDistance::FaceNormal(int face) const {
  return tree_->normals[face];
}

std::vector<int> MeshDistance::FacesHolding(const Closest& c) const {
  const Tree& t = *tree_;
  // Barycentric coordinates of the closest point in its triangle.
  const int v[3] = {t.corners(c.face, 0), t.corners(c.face, 1),
                    t.corners(c.face, 2)};
  const Eigen::Vector3d a = t.vertices.row(v[0]), b = t.vertices.row(v[1]),
                        cc = t.vertices.row(v[2]);
  const Eigen::Vector3d n = (b - a).cross(cc - a);
  const double twice_area = n.squaredNorm();
  if (!(twice_area > 0)) return {c.face};
  double bary[3];
  bary[0] = n.dot((b - c.point).cross(cc - c.point)) / twice_area;
  bary[1] = n.dot((cc - c.point).cross(a - c.point)) / twice_area;
  bary[2] = 1.0 - bary[0] - bary[1];
  constexpr double kOnBoundary = 1e-9;
  // Corners of the feature holding the point: one vertex (two coordinates
  // ~0), an edge (one ~0), or the interior.
  std::vector<int> feature;
  for (int k = 0; k < 3; ++k) {
    if (bary[k] > kOnBoundary) feature.push_back(v[k]);
  }
  if (feature.size() == 3) return {c.face};
  // Every face holding the whole feature (its vertices), ascending.
  const int pivot = feature.empty() ? v[0] : feature[0];
  std::vector<int> faces;
  for (int j = t.vertex_face_start[pivot]; j < t.vertex_face_start[pivot + 1];
       ++j) {
    const int f = t.vertex_faces[j];
    bool holds = true;
    for (int w : feature) {
      holds = holds && (t.corners(f, 0) == w || t.corners(f, 1) == w ||
                        t.corners(f, 2) == w);
    }
    if (holds) faces.push_back(f);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

bool MeshDistance::Opposes(const Closest& c,
                           const Eigen::Vector3d& direction) const {
  const Tree& t = *tree_;
  if (!(direction.dot(t.normals[c.face]) < 0)) return false;
  for (const int f : FacesHolding(c)) {
    if (!(direction.dot(t.normals[f]) < 0)) return false;
  }
  return true;
}

Eigen::Vector3d MeshDistance::Normal(const Closest& c) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const int f : FacesHolding(c)) sum += tree_->normals[f];
  const double norm = sum.norm();
  return norm > 0 ? Eigen::Vector3d(sum / norm) : tree_->normals[c.face];
}

}  // namespace sdcb
