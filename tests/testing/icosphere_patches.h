// Open meshes cut from core/mesh/icosphere.h's icosphere by face centroid
// (a disk, a tube, a sphere with holes), their faces' membership, and the
// boundary loops of a face set found by brute force: the shared fixture of
// the hole-filling and trim-region tests.
#ifndef SDCB_TESTS_TESTING_ICOSPHERE_PATCHES_H_
#define SDCB_TESTS_TESTING_ICOSPHERE_PATCHES_H_

#include <Eigen/Core>
#include <functional>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::testing {

// Per face of `mesh`, whether `keep` holds at its centroid direction.
inline std::vector<bool> FacesWhere(
    const TriangleMesh& mesh,
    const std::function<bool(const Eigen::Vector3d&)>& keep) {
  std::vector<bool> out(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d c = (mesh.vertices.row(mesh.faces(f, 0)) +
                               mesh.vertices.row(mesh.faces(f, 1)) +
                               mesh.vertices.row(mesh.faces(f, 2)))
                                  .transpose()
                                  .normalized();
    out[f] = keep(c);
  }
  return out;
}

// The faces of `mesh` marked in `keep` and the vertices they use (in
// ascending order of their row), like a part of sdcb::SplitIntoParts.
inline TriangleMesh Submesh(const TriangleMesh& mesh,
                            const std::vector<bool>& keep) {
  std::vector<int> row(mesh.num_vertices(), -1);
  int faces = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (!keep[f]) continue;
    ++faces;
    for (int k = 0; k < 3; ++k) row[mesh.faces(f, k)] = 0;
  }
  int next = 0;
  for (int& r : row) {
    if (r == 0) r = next++;
  }
  TriangleMesh out;
  out.vertices.resize(next, 3);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (row[v] >= 0) out.vertices.row(row[v]) = mesh.vertices.row(v);
  }
  out.faces.resize(faces, 3);
  int i = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (!keep[f]) continue;
    for (int k = 0; k < 3; ++k) out.faces(i, k) = row[mesh.faces(f, k)];
    ++i;
  }
  return out;
}

// The boundary loops of the faces marked in `keep`, by brute force: the
// directed edges a -> b of those faces whose reverse b -> a no marked face
// has, chained (each loop starts at its smallest vertex; loops sorted by
// it). Empty with *ok false when a vertex starts two boundary edges.
inline std::vector<std::vector<int>> BruteForceLoops(
    const TriangleMesh& mesh, const std::vector<bool>& keep, bool* ok) {
  std::set<std::pair<int, int>> directed;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (!keep[f]) continue;
    for (int k = 0; k < 3; ++k) {
      directed.emplace(mesh.faces(f, k), mesh.faces(f, (k + 1) % 3));
    }
  }
  std::map<int, int> next;
  *ok = true;
  for (const auto& [a, b] : directed) {
    if (directed.count({b, a})) continue;
    if (next.count(a)) *ok = false;
    next[a] = b;
  }
  std::vector<std::vector<int>> loops;
  std::set<int> used;
  for (const auto& [start, unused] : next) {  // ascending: smallest first
    if (used.count(start)) continue;
    std::vector<int> loop;
    int v = start;
    do {
      loop.push_back(v);
      used.insert(v);
      v = next.at(v);
    } while (v != start && loop.size() <= next.size());
    loops.push_back(loop);
  }
  return loops;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_ICOSPHERE_PATCHES_H_
