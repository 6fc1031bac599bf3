#include "sdcb/core/mesh/curvature.h"

#include <CGAL/Eigen_matrix.h>
#include <CGAL/Eigen_vector.h>
#include <CGAL/Monge_via_jet_fitting.h>
#include <CGAL/Simple_cartesian.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>
#include <vector>

namespace sdcb {
namespace {

// CGAL's SvdTraits for the jet's least-squares system M a = b (#points by
// (d+1)(d+2)/2, preconditioned by CGAL): the normal equations, solved by a
// symmetric eigendecomposition, instead of CGAL::Eigen_svd's Jacobi SVD of
// M (which took 40% of the time). Same solution (the pseudo-inverse one)
// and the same condition number sigma_max / sigma_min = sqrt(l_max / l_min);
// squaring it costs digits only for systems that the max_condition_number
// test rejects anyway.
struct NormalEquationsSolver {
  using FT = double;
  using Vector = CGAL::Eigen_vector<FT>;
  using Matrix = CGAL::Eigen_matrix<FT>;
  static FT solve(const Matrix& m, Vector& b) {
    const Eigen::MatrixXd& a = m.eigen_object();
    const Eigen::MatrixXd normal = a.transpose() * a;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(normal);
    const Eigen::VectorXd& lambda = solver.eigenvalues();  // ascending
    const Eigen::VectorXd rhs =
        solver.eigenvectors().transpose() * (a.transpose() * b.eigen_object());
    Eigen::VectorXd coefficients = Eigen::VectorXd::Zero(lambda.size());
    const double cutoff = lambda[lambda.size() - 1] * 1e-30;
    for (Eigen::Index i = 0; i < lambda.size(); ++i) {
      if (lambda[i] > cutoff) coefficients[i] = rhs[i] / lambda[i];
    }
    b.eigen_object() = solver.eigenvectors() * coefficients;
    if (!(lambda[0] > 0)) return std::numeric_limits<double>::infinity();
    return std::sqrt(lambda[lambda.size() - 1] / lambda[0]);
  }
};

using FitKernel = CGAL::Simple_cartesian<double>;
using JetFitter =
    CGAL::Monge_via_jet_fitting<FitKernel, FitKernel, NormalEquationsSolver>;

// Vertex-to-vertex adjacency in compressed rows: the neighbours of v are
// neighbors[offsets[v] .. offsets[v+1]), sorted, without duplicates.
struct VertexAdjacency {
  std::vector<int> offsets;
  std::vector<int> neighbors;
};

VertexAdjacency BuildAdjacency(const TriangleMesh& mesh) {
  const int nv = mesh.num_vertices();
  std::vector<std::vector<int>> lists(nv);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.faces(f, c), b = mesh.faces(f, (c + 1) % 3);
      lists[a].push_back(b);
      lists[b].push_back(a);
    }
  }
  VertexAdjacency adjacency;
  adjacency.offsets.assign(nv + 1, 0);
  for (int v = 0; v < nv; ++v) {
    std::sort(lists[v].begin(), lists[v].end());
    lists[v].erase(std::unique(lists[v].begin(), lists[v].end()),
                   lists[v].end());
    adjacency.offsets[v + 1] =
        adjacency.offsets[v] + static_cast<int>(lists[v].size());
  }
  adjacency.neighbors.reserve(adjacency.offsets[nv]);
  for (int v = 0; v < nv; ++v) {
    adjacency.neighbors.insert(adjacency.neighbors.end(), lists[v].begin(),
                               lists[v].end());
  }
  return adjacency;
}

// Area-weighted vertex normals (unnormalized sums of face cross products):
// outward for a counter-clockwise closed mesh.
Eigen::MatrixX3d AreaWeightedNormals(const TriangleMesh& mesh) {
  Eigen::MatrixX3d normals = Eigen::MatrixX3d::Zero(mesh.num_vertices(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) normals.row(mesh.faces(f, k)) += n;
  }
  return normals;
}

// Whether a growing set of points spans a 2-D patch of the tangent plane of
// `normal` (the vertex normal): the smaller principal variance of the
// points projected onto that plane is at least `min_ratio` times the larger
// one. Without this, a curved row of points (a thin strip along a
// long-triangle fan) looks 2-D to CGAL's 3-D PCA, which then takes the
// strip's own plane as the tangent plane; and CGAL's preconditioning
// divides by ~0 on a line. Running sums (of coordinates relative to the
// first point, which keeps them well conditioned): each point and each test
// cost O(1), so a neighbourhood that grows to max_points along a strip
// costs linear, not quadratic, time.
class PatchSpread {
 public:
  PatchSpread(const Eigen::Vector3d& normal, const Eigen::Vector3d& origin)
      : origin_(origin) {
    Eigen::Vector3d n = normal;
    valid_ = n.squaredNorm() > 0;
    if (valid_) n.normalize();
    e1_ = n.unitOrthogonal();
    e2_ = n.cross(e1_);
  }
  void Add(const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = p - origin_;
    const Eigen::Vector2d q(d.dot(e1_), d.dot(e2_));
    sum_ += q;
    sum_squares_ += q * q.transpose();
    ++count_;
  }
  bool Spans(double min_ratio) const {
    if (!valid_ || count_ == 0) return false;
    const Eigen::Vector2d mean = sum_ / static_cast<double>(count_);
    const Eigen::Matrix2d covariance =
        sum_squares_ - static_cast<double>(count_) * mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(
        covariance, Eigen::EigenvaluesOnly);
    const Eigen::Vector2d lambda = solver.eigenvalues();  // ascending
    return lambda[1] > 0 && lambda[0] >= min_ratio * lambda[1];
  }

 private:
  Eigen::Vector3d origin_, e1_, e2_;
  bool valid_ = false;
  Eigen::Vector2d sum_ = Eigen::Vector2d::Zero();
  Eigen::Matrix2d sum_squares_ = Eigen::Matrix2d::Zero();
  int count_ = 0;
};

Status ValidateInput(const TriangleMesh& mesh,
                     const CurvatureOptions& options) {
  if (options.jet_degree < 2 || options.jet_degree > 4) {
    return InvalidArgumentError("curvature jet degree must be 2, 3 or 4, got " +
                                std::to_string(options.jet_degree));
  }
  const int needed = (options.jet_degree + 1) * (options.jet_degree + 2) / 2;
  if (options.min_points < needed) {
    return InvalidArgumentError("curvature min_points must be at least " +
                                std::to_string(needed) + " for jet degree " +
                                std::to_string(options.jet_degree));
  }
  if (options.max_points < options.min_points) {
    return InvalidArgumentError(
        "curvature max_points must be at least min_points");
  }
  if (!(options.min_spread_ratio > 0 && options.min_spread_ratio < 1)) {
    return InvalidArgumentError("curvature min_spread_ratio must be in (0, 1)");
  }
  if (!(options.max_condition_number > 1)) {
    return InvalidArgumentError(
        "curvature max_condition_number must be greater than 1");
  }
  if (!mesh.vertices.allFinite()) {
    return InvalidInputError("mesh has non-finite vertex coordinates");
  }
  const int nv = mesh.num_vertices();
  if (mesh.faces.size() > 0 &&
      (mesh.faces.minCoeff() < 0 || mesh.faces.maxCoeff() >= nv)) {
    return InvalidInputError(
        "mesh has a face with a vertex index out of range");
  }
  return Status::Ok();
}

// Replaces the values of vertices with valid[v] == false by the mean of their
// valid neighbours, in breadth-first passes (each pass reads only values
// settled in earlier passes, so the result is order independent). Vertices
// in components without any valid vertex get 0.
void FillFromNeighbours(const VertexAdjacency& adjacency,
                        std::vector<char> valid, Eigen::VectorXd* k_max,
                        Eigen::VectorXd* k_min) {
  const int nv = static_cast<int>(valid.size());
  while (true) {
    std::vector<int> settled;
    for (int v = 0; v < nv; ++v) {
      if (valid[v]) continue;
      double sum_max = 0, sum_min = 0;
      int count = 0;
      for (int i = adjacency.offsets[v]; i < adjacency.offsets[v + 1]; ++i) {
        const int u = adjacency.neighbors[i];
        if (!valid[u]) continue;
        sum_max += (*k_max)[u];
        sum_min += (*k_min)[u];
        ++count;
      }
      if (count == 0) continue;
      (*k_max)[v] = sum_max / count;
      (*k_min)[v] = sum_min / count;
      settled.push_back(v);
    }
    if (settled.empty()) break;
    for (int v : settled) valid[v] = 1;
  }
  for (int v = 0; v < nv; ++v) {
    if (!valid[v]) (*k_max)[v] = (*k_min)[v] = 0;
  }
}

}  // namespace

StatusOr<PrincipalCurvatures> EstimatePrincipalCurvatures(
    const TriangleMesh& mesh, const CurvatureOptions& options) {
  SDCB_RETURN_IF_ERROR(ValidateInput(mesh, options));
  const int nv = mesh.num_vertices();
  const VertexAdjacency adjacency = BuildAdjacency(mesh);
  const Eigen::MatrixX3d normals = AreaWeightedNormals(mesh);
  const size_t needed = static_cast<size_t>((options.jet_degree + 1) *
                                            (options.jet_degree + 2) / 2);

  PrincipalCurvatures result;
  result.k_max = Eigen::VectorXd::Zero(nv);
  result.k_min = Eigen::VectorXd::Zero(nv);
  std::vector<char> valid(nv, 0);

  // mark[u] == v: u has been discovered for vertex v. Every vertex is handled
  // by exactly one thread, so v itself is a unique stamp.
  tbb::enumerable_thread_specific<std::vector<int>> marks(
      [nv] { return std::vector<int>(nv, -1); });
  tbb::parallel_for(tbb::blocked_range<int>(0, nv), [&](const auto& range) {
    std::vector<int>& mark = marks.local();
    std::vector<FitKernel::Point_3> points;
    // Best-first growth by Euclidean distance to v over mesh edges: a
    // connected, round neighbourhood even where triangles are long and thin
    // (topological rings would be strips there).
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    std::vector<Entry> candidates;
    for (int v = range.begin(); v < range.end(); ++v) {
      if (adjacency.offsets[v] == adjacency.offsets[v + 1]) continue;
      const Eigen::Vector3d center = mesh.vertices.row(v);
      const Eigen::Vector3d normal = normals.row(v);
      points.clear();
      PatchSpread spread(normal, center);
      queue = {};
      queue.emplace(0.0, v);
      mark[v] = v;
      while (!queue.empty() &&
             points.size() < static_cast<size_t>(options.max_points)) {
        const double distance = queue.top().first;
        const int w = queue.top().second;
        queue.pop();
        // The first point is where CGAL evaluates the Monge form.
        points.emplace_back(mesh.vertices(w, 0), mesh.vertices(w, 1),
                            mesh.vertices(w, 2));
        spread.Add(mesh.vertices.row(w).transpose());
        // At most max_points more pops can follow, so of a hub's many
        // neighbours (a CAD fan's centre) only the nearest max_points can
        // ever be taken: push those (ties included), not all, so that work
        // stays linear in the hub's valence instead of its square times
        // log.
        candidates.clear();
        for (int i = adjacency.offsets[w]; i < adjacency.offsets[w + 1]; ++i) {
          const int u = adjacency.neighbors[i];
          if (mark[u] == v) continue;
          candidates.emplace_back(
              (mesh.vertices.row(u).transpose() - center).squaredNorm(), u);
        }
        const size_t keep = static_cast<size_t>(options.max_points);
        if (candidates.size() > keep) {
          std::nth_element(candidates.begin(), candidates.begin() + (keep - 1),
                           candidates.end());
          const Entry cut = candidates[keep - 1];
          candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                          [&](const Entry& e) {
                                            return e.first > cut.first;
                                          }),
                           candidates.end());
        }
        for (const Entry& e : candidates) {
          mark[e.second] = v;
          queue.push(e);
        }
        // Take all vertices at the same distance (up to rounding) together,
        // so that a symmetric neighbourhood stays symmetric and a rigid
        // motion of the mesh does not change the neighbourhood.
        if (!queue.empty() &&
            (points.size() < static_cast<size_t>(options.min_points) ||
             queue.top().first <= distance * (1 + 1e-9))) {
          continue;
        }
        if (points.size() < needed || !spread.Spans(options.min_spread_ratio)) {
          continue;
        }
        JetFitter fitter;
        JetFitter::Monge_form form =
            fitter(points.begin(), points.end(), options.jet_degree, 2);
        form.comply_wrt_given_normal(
            FitKernel::Vector_3(normal.x(), normal.y(), normal.z()));
        // A large condition number means the points do not determine the
        // jet (e.g. only two distinct heights across a strip): grow further.
        if (!(fitter.condition_number() <= options.max_condition_number)) {
          continue;
        }
        // CGAL's Monge coefficients are w.r.t. the (outward) normal, where a
        // convex surface bends away: negate so that convex is positive.
        const double k_max = -form.principal_curvatures(1);
        const double k_min = -form.principal_curvatures(0);
        if (std::isfinite(k_max) && std::isfinite(k_min)) {
          result.k_max[v] = k_max;
          result.k_min[v] = k_min;
          valid[v] = 1;
        }
        break;
      }
    }
  });

  result.fallback_vertices =
      static_cast<int>(std::count(valid.begin(), valid.end(), 0));
  if (result.fallback_vertices > 0) {
    FillFromNeighbours(adjacency, valid, &result.k_max, &result.k_min);
  }
  return result;
}

StatusOr<Eigen::VectorXd> Curvedness(const TriangleMesh& mesh,
                                     const CurvatureOptions& options) {
  SDCB_ASSIGN_OR_RETURN(PrincipalCurvatures curvatures,
                        EstimatePrincipalCurvatures(mesh, options));
  return Eigen::VectorXd(curvatures.k_max.cwiseAbs() +
                         curvatures.k_min.cwiseAbs());
}

}  // namespace sdcb
