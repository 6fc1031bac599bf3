#include "sdcb/core/fit/fit_samples.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>

#include "sdcb/core/sphere/point_kd_tree.h"

namespace sdcb {

Eigen::VectorXd KnotSpacing(const Eigen::MatrixX3d& knots) {
  const PointKdTree tree(knots);
  Eigen::VectorXd spacing(knots.rows());
  for (Eigen::Index k = 0; k < knots.rows(); ++k) {
    const PointKdTree::Neighbor n = tree.Nearest(
        knots.row(k).transpose(), std::numeric_limits<double>::infinity(),
        static_cast<int>(k));
    spacing[k] = std::sqrt(n.squared_distance);
  }
  return spacing;
}

namespace {

// A sub-triangle of a mesh triangle in barycentric coordinates (weights of
// corners 1 and 2; corner 0 gets the rest). Dyadic values: exact doubles.
struct Sub {
  Eigen::Vector2d v[3];
};

Eigen::Vector3d OnSphere(const Eigen::Vector2d& b, const Eigen::Vector3d s[3]) {
  return ((1.0 - b[0] - b[1]) * s[0] + b[0] * s[1] + b[1] * s[2]).normalized();
}

// Splits `t` by longest-edge bisection (lengths measured on the sphere)
// until every edge is at most `length(centroid)`; appends the leaves, each
// taking one from `*budget`. Returns false, early, when the budget runs out.
template <typename Length>
bool Bisect(const Sub& t, const Eigen::Vector3d s[3], const Length& length,
            int depth, int64_t* budget, std::vector<Sub>* leaves) {
  double longest = 0;
  int edge = 0;
  for (int e = 0; e < 3; ++e) {
    const double l =
        (OnSphere(t.v[(e + 1) % 3], s) - OnSphere(t.v[e], s)).norm();
    if (l > longest) {
      longest = l;
      edge = e;
    }
  }
  if (depth == 0 ||
      longest <= length(OnSphere((t.v[0] + t.v[1] + t.v[2]) / 3.0, s))) {
    if (*budget <= 0) return false;
    --*budget;
    leaves->push_back(t);
    return true;
  }
  const Eigen::Vector2d mid = 0.5 * (t.v[edge] + t.v[(edge + 1) % 3]);
  const Eigen::Vector2d& opposite = t.v[(edge + 2) % 3];
  return Bisect(Sub{{t.v[edge], mid, opposite}}, s, length, depth - 1, budget,
                leaves) &&
         Bisect(Sub{{mid, t.v[(edge + 1) % 3], opposite}}, s, length, depth - 1,
                budget, leaves);
}

// The pieces of every triangle to split at `per_spacing` samples per knot
// spacing (`spacing`: per knot, `knot_tree`: the knots); false when they
// would exceed options.max_pieces (then `leaves` is to be discarded).
bool SplitTriangles(const TriangleMesh& mesh, const Eigen::MatrixX3d& sphere,
                    const Eigen::VectorXd& spacing,
                    const PointKdTree& knot_tree, double per_spacing,
                    const FitSampleOptions& options,
                    std::vector<std::vector<Sub>>* leaves, int* split) {
  int64_t budget = options.max_pieces > 0 ? options.max_pieces
                                          : std::numeric_limits<int64_t>::max();
  *split = 0;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    (*leaves)[f].clear();
    const Eigen::Vector3d s[3] = {sphere.row(mesh.faces(f, 0)),
                                  sphere.row(mesh.faces(f, 1)),
                                  sphere.row(mesh.faces(f, 2))};
    const double longest = std::max(
        {(s[1] - s[0]).norm(), (s[2] - s[1]).norm(), (s[0] - s[2]).norm()});
    // The sample spacing at a point: the spacing of the knot nearest to it
    // over per_spacing.
    const auto length = [&](const Eigen::Vector3d& p) {
      const PointKdTree::Neighbor near = knot_tree.Nearest(p);
      return near.index >= 0 ? spacing[near.index] / per_spacing
                             : std::numeric_limits<double>::infinity();
    };
    if (longest <= length((s[0] + s[1] + s[2]).normalized())) continue;
    const Sub whole{
        {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)}};
    if (!Bisect(whole, s, length, options.max_depth, &budget, &(*leaves)[f])) {
      return false;
    }
    ++*split;
  }
  return true;
}

}  // namespace

FitSamples BuildFitSamples(const TriangleMesh& mesh,
                           const Eigen::MatrixX3d& sphere,
                           const Eigen::MatrixX3d& knots,
                           const FitSampleOptions& options) {
  const Eigen::Index nv = mesh.vertices.rows(), nf = mesh.faces.rows();
  const Eigen::VectorXd spacing = KnotSpacing(knots);
  const PointKdTree knot_tree(knots);

  // The sub-triangles of every triangle whose spherical image has an edge
  // longer than the sample spacing h / samples_per_spacing (h: the spacing
  // of the knot nearest to its centroid); again with half the samples per
  // spacing while they exceed max_pieces.
  FitSamples out;
  out.num_vertices = nv;
  std::vector<std::vector<Sub>> leaves(nf);
  double per_spacing = options.samples_per_spacing;
  for (int halvings = 0;; ++halvings) {
    if (halvings == 64) {
      // Only coincident knots (spacing 0) get here: one piece per triangle.
      FitSampleOptions whole = options;
      whole.max_depth = 0;
      whole.max_pieces = 0;
      SplitTriangles(mesh, sphere, spacing, knot_tree, per_spacing, whole,
                     &leaves, &out.split_triangles);
      break;
    }
    if (SplitTriangles(mesh, sphere, spacing, knot_tree, per_spacing, options,
                       &leaves, &out.split_triangles)) {
      break;
    }
    per_spacing /= 2;
  }
  out.samples_per_spacing = per_spacing;

  // Rows: the vertices, then per split triangle its new lattice points and
  // its leaves' centroids.
  Eigen::Index extra = 0;
  for (const auto& l : leaves) extra += l.empty() ? 0 : 4 * l.size();  // bound
  out.points.resize(nv + extra, 3);
  out.targets.resize(nv + extra, 3);
  out.weights = Eigen::VectorXd::Zero(nv + extra);
  out.triangle.assign(extra, -1);
  out.points.topRows(nv) = sphere;
  out.targets.topRows(nv) = mesh.vertices;
  Eigen::Index next = nv;
  std::map<std::pair<double, double>, Eigen::Index> point_row;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const int corner[3] = {mesh.faces(f, 0), mesh.faces(f, 1),
                           mesh.faces(f, 2)};
    Eigen::Vector3d s[3], x[3];
    for (int k = 0; k < 3; ++k) {
      s[k] = sphere.row(corner[k]).transpose();
      x[k] = mesh.vertices.row(corner[k]).transpose();
    }
    const double area = 0.5 * (x[1] - x[0]).cross(x[2] - x[0]).norm();
    if (leaves[f].empty()) {
      for (int k = 0; k < 3; ++k) out.weights[corner[k]] += area / 3.0;
      continue;
    }
    auto add_point = [&](const Eigen::Vector2d& b) {
      out.points.row(next) = OnSphere(b, s).transpose();
      out.targets.row(next) =
          ((1.0 - b[0] - b[1]) * x[0] + b[0] * x[1] + b[1] * x[2]).transpose();
      out.triangle[next - nv] = static_cast<int>(f);
      return next++;
    };
    point_row.clear();
    auto row_of = [&](const Eigen::Vector2d& b) -> Eigen::Index {
      if (b[0] == 0 && b[1] == 0) return corner[0];
      if (b[0] == 1 && b[1] == 0) return corner[1];
      if (b[0] == 0 && b[1] == 1) return corner[2];
      const auto [it, inserted] = point_row.emplace(std::pair{b[0], b[1]}, 0);
      if (inserted) it->second = add_point(b);
      return it->second;
    };
    for (const Sub& t : leaves[f]) {
      // Barycentric area share of the leaf (affine in the mesh triangle).
      const Eigen::Vector2d e0 = t.v[1] - t.v[0], e1 = t.v[2] - t.v[0];
      const double leaf_area = area * std::abs(e0[0] * e1[1] - e0[1] * e1[0]);
      for (int k = 0; k < 3; ++k) {
        out.weights[row_of(t.v[k])] += leaf_area / 12.0;
      }
      out.weights[add_point((t.v[0] + t.v[1] + t.v[2]) / 3.0)] =
          0.75 * leaf_area;
    }
  }
  out.points.conservativeResize(next, 3);
  out.targets.conservativeResize(next, 3);
  out.weights.conservativeResize(next);
  out.triangle.resize(next - nv);
  return out;
}

}  // namespace sdcb
