#include "sdcb/converters/mesh_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace sdcb {

struct MeshDistance::Tree {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Triangles = std::vector<K::Triangle_3>;
  using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
  using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
  Triangles triangles;
  AabbTree tree;
};

MeshDistance::MeshDistance(const TriangleMesh& mesh) : tree_(new Tree) {
  using P = Tree::K::Point_3;
  auto point = [&](int v) {
    return P(mesh.vertices(v, 0), mesh.vertices(v, 1), mesh.vertices(v, 2));
  };
  tree_->triangles.reserve(mesh.faces.rows());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    tree_->triangles.emplace_back(point(mesh.faces(f, 0)),
                                  point(mesh.faces(f, 1)),
                                  point(mesh.faces(f, 2)));
  }
  tree_->tree.insert(tree_->triangles.cbegin(), tree_->triangles.cend());
  tree_->tree.build();
  tree_->tree.accelerate_distance_queries();
}

MeshDistance::~MeshDistance() = default;

Eigen::VectorXd MeshDistance::Distances(const Eigen::MatrixX3d& points) const {
  Eigen::VectorXd out(points.rows());
  if (tree_->triangles.empty()) {
    out.setConstant(std::nan(""));
    return out;
  }
  tbb::parallel_for(Eigen::Index{0}, points.rows(), [&](Eigen::Index i) {
    const Tree::K::Point_3 p(points(i, 0), points(i, 1), points(i, 2));
    out[i] = std::sqrt(tree_->tree.squared_distance(p));
  });
  return out;
}

Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3> ColorRamp(
    const Eigen::VectorXd& values, double lo, double hi, bool diverging) {
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3> out(values.size(), 3);
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (!std::isfinite(v)) {
      out.row(i) << 128, 128, 128;
      continue;
    }
    const double t = hi > lo ? std::clamp((v - lo) / (hi - lo), 0.0, 1.0) : 0.5;
    double r, g, b;
    if (diverging) {
      // Blue (t = 0) -> white (t = 1/2) -> red (t = 1).
      const double s = 2.0 * t - 1.0;
      r = s < 0 ? 1.0 + s : 1.0;
      b = s > 0 ? 1.0 - s : 1.0;
      g = 1.0 - std::abs(s);
    } else {
      r = 1.0;
      g = b = 1.0 - t;
    }
    out.row(i) << static_cast<std::uint8_t>(std::lround(255 * r)),
        static_cast<std::uint8_t>(std::lround(255 * g)),
        static_cast<std::uint8_t>(std::lround(255 * b));
  }
  return out;
}

}  // namespace sdcb
