#include "sdcb/core/mesh/mesh_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>
#include <cmath>
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

}  // namespace

struct MeshDistance::Tree {
  std::vector<Triangle> triangles;
  std::vector<int> faces;  // mesh face of each triangle
  std::vector<Eigen::Vector3d> normals;  // per mesh face
  AabbTree tree;
};

StatusOr<MeshDistance> MeshDistance::Create(const TriangleMesh& mesh) {
  if (!mesh.vertices.allFinite()) {
    return InvalidInputError("the mesh has a non-finite vertex coordinate");
  }
  auto t = std::make_unique<Tree>();
  t->normals.resize(mesh.num_faces(), Eigen::Vector3d::Zero());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Triangle triangle(ToPoint(a), ToPoint(b), ToPoint(c));
    if (triangle.is_degenerate()) continue;  // exact collinearity test
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() > 0) t->normals[f] = n.normalized();
    t->triangles.push_back(triangle);
    t->faces.push_back(f);
  }
  if (t->triangles.empty()) {
    return InvalidInputError("the mesh has no non-degenerate triangle");
  }
  t->tree.insert(t->triangles.begin(), t->triangles.end());
  t->tree.build();
  t->tree.accelerate_distance_queries();
  return MeshDistance(std::move(t));
}

MeshDistance::MeshDistance(std::unique_ptr<Tree> tree)
    : tree_(std::move(tree)) {}
MeshDistance::MeshDistance(MeshDistance&&) noexcept = default;
MeshDistance& MeshDistance::operator=(MeshDistance&&) noexcept = default;
MeshDistance::~MeshDistance() = default;

MeshDistance::Closest MeshDistance::Find(const Eigen::Vector3d& query) const {
  const auto hit = tree_->tree.closest_point_and_primitive(ToPoint(query));
  Closest out;
  out.point = Eigen::Vector3d(hit.first.x(), hit.first.y(), hit.first.z());
  out.face = tree_->faces[hit.second - tree_->triangles.begin()];
  out.distance = (out.point - query).norm();
  return out;
}

Eigen::Vector3d MeshDistance::FaceNormal(int face) const {
  return tree_->normals[face];
}

}  // namespace sdcb
