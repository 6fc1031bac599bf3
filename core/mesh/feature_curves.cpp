#include "sdcb/core/mesh/feature_curves.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "sdcb/core/common/constants.h"

namespace sdcb {
namespace {

uint64_t EdgeKey(int a, int b) {
  return (uint64_t(std::min(a, b)) << 32) | uint32_t(std::max(a, b));
}

}  // namespace

StatusOr<MeshFeatures> DetectFeatures(const TriangleMesh& mesh,
                                      double angle_degrees) {
  if (!(angle_degrees > 0.0 && angle_degrees <= 180.0)) {
    return InvalidArgumentError("the feature angle must be in (0, 180]");
  }
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  std::vector<Eigen::Vector3d> normals(nf);
  std::vector<std::pair<uint64_t, int>> edge_faces;
  edge_faces.reserve(3 * size_t(nf));
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      if (v < 0 || v >= nv) {
        return InvalidInputError("face " + std::to_string(f) +
                                 " has a vertex index out of range");
      }
    }
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double length = n.norm();
    normals[f] =
        length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      edge_faces.emplace_back(
          EdgeKey(mesh.faces(f, k), mesh.faces(f, (k + 1) % 3)), f);
    }
  }
  std::sort(edge_faces.begin(), edge_faces.end());

  const double cos_angle = std::cos(angle_degrees * kPi / 180.0);
  MeshFeatures out;
  out.angle_degrees = angle_degrees;
  for (size_t i = 0; i < edge_faces.size();) {
    size_t j = i;
    while (j < edge_faces.size() && edge_faces[j].first == edge_faces[i].first)
      ++j;
    if (j - i == 2) {
      const Eigen::Vector3d& n0 = normals[edge_faces[i].second];
      const Eigen::Vector3d& n1 = normals[edge_faces[i + 1].second];
      if (!n0.isZero(0.0) && !n1.isZero(0.0) && n0.dot(n1) < cos_angle) {
        const uint64_t key = edge_faces[i].first;
        out.edges.push_back({int(key >> 32), int(key & 0xffffffffu)});
      }
    }
    i = j;
  }

  // The feature graph: each vertex's feature neighbours, ascending.
  std::vector<std::vector<int>> neighbours(nv);
  for (const auto& e : out.edges) {
    neighbours[e[0]].push_back(e[1]);
    neighbours[e[1]].push_back(e[0]);
  }
  for (auto& n : neighbours) std::sort(n.begin(), n.end());
  std::vector<char> stops(nv, 0);  // corners and ends
  for (int v = 0; v < nv; ++v) {
    const size_t degree = neighbours[v].size();
    bool corner = degree >= 3;
    if (degree == 2) {
      const Eigen::Vector3d p = mesh.vertices.row(v);
      const Eigen::Vector3d in =
          p - mesh.vertices.row(neighbours[v][0]).transpose();
      const Eigen::Vector3d out_dir =
          mesh.vertices.row(neighbours[v][1]).transpose() - p;
      const double norms = in.norm() * out_dir.norm();
      corner = norms > 0.0 && in.dot(out_dir) < cos_angle * norms;
    }
    if (corner) out.corners.push_back(v);
    stops[v] = corner || degree == 1;
  }

  // Per feature edge (in the sorted order of out.edges): whether a curve
  // holds it already.
  std::vector<uint64_t> keys(out.edges.size());
  for (size_t e = 0; e < keys.size(); ++e) {
    keys[e] = EdgeKey(out.edges[e][0], out.edges[e][1]);
  }
  std::vector<char> used(keys.size(), 0);
  const auto edge_index = [&](int a, int b) {
    return std::lower_bound(keys.begin(), keys.end(), EdgeKey(a, b)) -
           keys.begin();
  };
  const auto is_used = [&](int a, int b) {
    return used[edge_index(a, b)] != 0;
  };
  // Walks the chain from `from` through `to` until a stop vertex (or, for a
  // loop, back to its start), marking the edges it uses.
  const auto walk = [&](int from, int to) {
    FeatureCurve curve;
    curve.vertices = {from};
    used[edge_index(from, to)] = 1;
    int previous = from, current = to;
    while (!stops[current] && current != from) {
      curve.vertices.push_back(current);
      // Not a stop: exactly two feature neighbours.
      const int next = neighbours[current][0] == previous
                           ? neighbours[current][1]
                           : neighbours[current][0];
      used[edge_index(current, next)] = 1;
      previous = current;
      current = next;
    }
    if (current == from && !stops[from]) {
      curve.closed = true;
    } else {
      curve.vertices.push_back(current);
    }
    return curve;
  };
  for (int v = 0; v < nv; ++v) {
    if (!stops[v]) continue;
    for (int w : neighbours[v]) {
      if (!is_used(v, w)) out.curves.push_back(walk(v, w));
    }
  }
  for (const auto& e : out.edges) {
    if (!is_used(e[0], e[1])) out.curves.push_back(walk(e[0], e[1]));
  }
  return out;
}

}  // namespace sdcb
