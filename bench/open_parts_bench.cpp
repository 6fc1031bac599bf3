// An export of an open or many-part mesh measured against its input, as a
// user would judge it: per part, the dense two-sided distance between the
// exported triangles and the input's (area-weighted random samples both ways,
// CGAL's AABB tree), the boundary loops of both, and the two-sided distance
// between the two boundaries (points every 1/2000 of the part's largest side
// along the edges, measured to the other boundary's edges). Distances in
// percent of each input part's largest bounding-box side. One line per part,
// then a SUMMARY line with the largest of each figure.
//
//   open_parts_bench INPUT EXPORT.obj [SAMPLES]
#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "bench/garland_heckbert.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/mesh_parts.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/spline/spline_model.h"
#include "sdcb/io/mesh/mesh_reader.h"

namespace {

// `mesh` with vertices at the same position merged (an export splits a
// vertex per side of a crease or per normal; the surface is one).
sdcb::TriangleMesh MergedByPosition(const sdcb::TriangleMesh& mesh) {
  std::map<std::array<double, 3>, int> index;
  std::vector<int> remap(mesh.num_vertices());
  std::vector<Eigen::Vector3d> kept;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const std::array<double, 3> key = {mesh.vertices(v, 0), mesh.vertices(v, 1),
                                       mesh.vertices(v, 2)};
    auto [it, added] = index.emplace(key, static_cast<int>(kept.size()));
    if (added) kept.push_back(mesh.vertices.row(v).transpose());
    remap[v] = it->second;
  }
  sdcb::TriangleMesh out;
  out.vertices.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (size_t i = 0; i < kept.size(); ++i) {
    out.vertices.row(static_cast<Eigen::Index>(i)) = kept[i].transpose();
  }
  out.faces = mesh.faces;
  for (Eigen::Index f = 0; f < out.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) out.faces(f, k) = remap[out.faces(f, k)];
  }
  return out;
}

// The boundary edges (one incident triangle) of `mesh`, counted here rather
// than by sdcb::BoundaryEdges: the bench checks the library's exports.
std::vector<std::array<int, 2>> CountedBoundaryEdges(
    const sdcb::TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> count;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces(f, k), b = mesh.faces(f, (k + 1) % 3);
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::vector<std::array<int, 2>> out;
  for (const auto& [edge, n] : count) {
    if (n == 1) out.push_back({edge.first, edge.second});
  }
  return out;
}

// The boundary of `mesh` as a degenerate triangle mesh (each edge a
// triangle a, b, b) for the AABB tree, and points along it every `step`.
void Boundary(const sdcb::TriangleMesh& mesh, double step,
              sdcb::TriangleMesh* segments, Eigen::MatrixX3d* points) {
  const std::vector<std::array<int, 2>> edges = CountedBoundaryEdges(mesh);
  segments->vertices = mesh.vertices;
  segments->faces.resize(static_cast<Eigen::Index>(edges.size()), 3);
  std::vector<Eigen::Vector3d> along;
  for (size_t e = 0; e < edges.size(); ++e) {
    segments->faces.row(static_cast<Eigen::Index>(e)) << edges[e][0],
        edges[e][1], edges[e][1];
    const Eigen::Vector3d a = mesh.vertices.row(edges[e][0]);
    const Eigen::Vector3d b = mesh.vertices.row(edges[e][1]);
    const int n =
        std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int i = 0; i < n; ++i) along.push_back(a + (b - a) * (double(i) / n));
  }
  points->resize(static_cast<Eigen::Index>(along.size()), 3);
  for (size_t i = 0; i < along.size(); ++i) {
    points->row(static_cast<Eigen::Index>(i)) = along[i].transpose();
  }
}

// Brute force over the segments (the AABB tree wants triangles with area).
double PointSegmentsDistance(const Eigen::Vector3d& p,
                             const sdcb::TriangleMesh& segments) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index e = 0; e < segments.faces.rows(); ++e) {
    const Eigen::Vector3d a = segments.vertices.row(segments.faces(e, 0));
    const Eigen::Vector3d b = segments.vertices.row(segments.faces(e, 1));
    const Eigen::Vector3d d = b - a;
    const double t = std::clamp(
        d.squaredNorm() > 0 ? (p - a).dot(d) / d.squaredNorm() : 0.0, 0.0, 1.0);
    best = std::min(best, (a + t * d - p).norm());
  }
  return best;
}

double OneWayBoundary(const Eigen::MatrixX3d& points,
                      const sdcb::TriangleMesh& segments) {
  double worst = 0;
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    worst = std::max(
        worst, PointSegmentsDistance(points.row(i).transpose(), segments));
  }
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: open_parts_bench INPUT EXPORT.obj [SAMPLES]\n");
    return 2;
  }
  const int samples = argc > 3 ? std::atoi(argv[3]) : 400000;
  auto input = sdcb::ReadMesh(argv[1]);
  auto exported = sdcb::ReadMesh(argv[2]);
  if (!input.ok() || !exported.ok()) {
    std::fprintf(
        stderr, "open_parts_bench: %s\n",
        (!input.ok() ? input.status() : exported.status()).message().c_str());
    return 1;
  }
  auto in_parts = sdcb::SplitIntoParts(*input, 0);
  auto out_parts = sdcb::SplitIntoParts(MergedByPosition(*exported), 0);
  if (!in_parts.ok() || !out_parts.ok() ||
      in_parts->size() != out_parts->size()) {
    std::printf("PARTS MISMATCH input %zu export %zu\n",
                in_parts.ok() ? in_parts->size() : 0,
                out_parts.ok() ? out_parts->size() : 0);
    return 1;
  }
  double worst_h = 0, worst_rms = 0, worst_boundary = 0;
  int loop_mismatches = 0;
  for (size_t i = 0; i < in_parts->size(); ++i) {
    const sdcb::TriangleMesh& a = (*in_parts)[i].mesh;
    const sdcb::TriangleMesh& b = (*out_parts)[i].mesh;
    const double unit = sdcb::ComputeNormalizingTransform(a)->scale;
    auto to_a = sdcb::MeshDistance::Create(a);
    auto to_b = sdcb::MeshDistance::Create(b);
    const int n = std::max(20000, static_cast<int>(samples / in_parts->size()));
    const sdcb_bench::TwoSidedDistance d =
        sdcb_bench::MeasureTwoSided(a, *to_a, b, *to_b, n);
    const int loops_a = sdcb::AnalyzeMeshTopology(a)->boundary_loops;
    const int loops_b = sdcb::AnalyzeMeshTopology(b)->boundary_loops;
    double boundary = 0;
    if (loops_a > 0 || loops_b > 0) {
      sdcb::TriangleMesh seg_a, seg_b;
      Eigen::MatrixX3d pts_a, pts_b;
      Boundary(a, unit / 2000, &seg_a, &pts_a);
      Boundary(b, unit / 2000, &seg_b, &pts_b);
      boundary = (seg_a.faces.rows() == 0 || seg_b.faces.rows() == 0)
                     ? std::numeric_limits<double>::infinity()
                     : std::max(OneWayBoundary(pts_a, seg_b),
                                OneWayBoundary(pts_b, seg_a));
    }
    const double h = 100 * d.max / unit, rms = 100 * d.rms / unit;
    const double bd = 100 * boundary / unit;
    std::printf(
        "part %zu: input %d triangles, export %d; loops %d / %d; rms %.4f%% "
        "hausdorff %.4f%% boundary %.4f%%\n",
        i + 1, a.num_faces(), b.num_faces(), loops_a, loops_b, rms, h, bd);
    worst_h = std::max(worst_h, h);
    worst_rms = std::max(worst_rms, rms);
    worst_boundary = std::max(worst_boundary, bd);
    loop_mismatches += loops_a != loops_b;
  }
  std::printf(
      "SUMMARY parts %zu max_rms %.4f%% max_hausdorff %.4f%% "
      "max_boundary %.4f%% loop_mismatches %d\n",
      in_parts->size(), worst_rms, worst_h, worst_boundary, loop_mismatches);
  return 0;
}
