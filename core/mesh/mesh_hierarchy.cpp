#include "sdcb/core/mesh/mesh_hierarchy.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <tuple>

#include "sdcb/core/common/constants.h"

namespace sdcb {
namespace {

// Dynamic state of the mesh while collapsing.
class Collapser {
 public:
  Collapser(const TriangleMesh& mesh, const MeshHierarchyOptions& options)
      : positions_(mesh.num_vertices()),
        faces_(mesh.num_faces()),
        face_alive_(mesh.num_faces(), 1),
        vertex_alive_(mesh.num_vertices(), true),
        vertex_faces_(mesh.num_vertices()),
        dead_incidences_(mesh.num_vertices(), 0),
        alive_vertices_(mesh.num_vertices()),
        cos_max_turn_(std::cos(options.max_normal_turn_degrees * kPi / 180.0)),
        min_quality_(options.min_triangle_quality),
        max_removed_valence_(options.max_removed_valence) {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      positions_[v] = mesh.vertices.row(v).transpose();
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      for (int i = 0; i < 3; ++i) {
        faces_[f][i] = mesh.faces(f, i);
        vertex_faces_[faces_[f][i]].push_back(f);
      }
    }
  }

  int alive_vertices() const { return alive_vertices_; }

  // Triangles around x (= its valence on a closed manifold).
  int Valence(int x) const {
    return static_cast<int>(vertex_faces_[x].size()) - dead_incidences_[x];
  }

  // Sorted neighbors of x, into *n (a buffer reused by the caller).
  void Neighbors(int x, std::vector<int>* out) const {
    std::vector<int>& n = *out;
    n.clear();
    for (int f : vertex_faces_[x]) {
      if (!face_alive_[f]) continue;
      for (int i = 0; i < 3; ++i) {
        if (faces_[f][i] != x) n.push_back(faces_[f][i]);
      }
    }
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }

  // Collapses v -> u when allowed; returns whether it did. Costs O(valence
  // of v) whatever the valence of u, so a vertex of very high valence (the
  // hub of a CAD fan) never makes the hierarchy quadratic.
  bool TryCollapse(int v, int u, HalfEdgeCollapse* record) {
    if (alive_vertices_ <= 4 || Valence(v) > max_removed_valence_) return false;
    // Link condition: the only common neighbors are the two opposite
    // vertices of the faces on edge (v, u).
    int common = 0;
    Neighbors(v, &neighbors_);
    for (int w : neighbors_) common += w != u && Adjacent(w, u);
    int edge_faces[2] = {-1, -1};
    int edge_face_count = 0;
    for (int f : vertex_faces_[v]) {
      if (face_alive_[f] && Corner(f, u) >= 0 && edge_face_count++ < 2) {
        edge_faces[edge_face_count - 1] = f;
      }
    }
    if (edge_face_count != 2 || common != 2) return false;
    // Normals of the re-pointed faces must not turn too far.
    for (int f : vertex_faces_[v]) {
      if (!face_alive_[f] || Corner(f, u) >= 0) continue;
      const Eigen::Vector3d before = Normal(f, -1, v);
      const Eigen::Vector3d after = Normal(f, v, u);
      const double nb = before.norm(), na = after.norm();
      if (!(na > 1e-14 * nb) || before.dot(after) < cos_max_turn_ * nb * na) {
        return false;
      }
      // No new slivers: they would ask the sphere triangles to be slivers.
      if (Quality(f, v, u) < std::min(min_quality_, Quality(f, -1, v)))
        return false;
    }
    record->removed = v;
    record->kept = u;
    OrderedLink(v, u, &record->link);
    record->deleted_faces = {edge_faces[0], edge_faces[1]};
    record->repointed_faces.clear();
    // Apply. Dead faces stay in the other corners' lists until those are
    // compacted (erasing from a hub's long list each time is quadratic).
    for (int f : edge_faces) {
      face_alive_[f] = 0;
      for (int i = 0; i < 3; ++i) {
        const int w = faces_[f][i];
        if (w != v) DropDeadIncidence(w);
      }
    }
    for (int f : vertex_faces_[v]) {
      if (!face_alive_[f]) continue;
      faces_[f][Corner(f, v)] = u;
      vertex_faces_[u].push_back(f);
      record->repointed_faces.push_back(f);
    }
    vertex_faces_[v].clear();
    dead_incidences_[v] = 0;
    vertex_alive_[v] = false;
    --alive_vertices_;
    return true;
  }

  bool vertex_alive(int x) const { return vertex_alive_[x]; }
  double Length(int a, int b) const {
    // Summed as x^2 + (y^2 + z^2), as Eigen's norm of a matrix row does (a
    // vectorized norm may sum in another order, and the last bit decides
    // ties between edges, so the hierarchy would change).
    const Eigen::Vector3d d = positions_[a] - positions_[b];
    return std::sqrt(d.x() * d.x() + (d.y() * d.y() + d.z() * d.z()));
  }

  MeshHierarchy Release(std::vector<HalfEdgeCollapse> collapses) {
    MeshHierarchy h;
    h.faces.resize(faces_.size(), 3);
    for (size_t f = 0; f < faces_.size(); ++f) {
      for (int i = 0; i < 3; ++i) h.faces(f, i) = faces_[f][i];
    }
    h.face_alive.assign(face_alive_.begin(), face_alive_.end());
    h.vertex_alive = std::move(vertex_alive_);
    h.collapses = std::move(collapses);
    return h;
  }

 private:
  // Whether edge (a, b) exists: an alive face around the end with the
  // shorter face list holds the other (O(min valence), so a hub's long
  // list is not scanned for its small neighbors).
  bool Adjacent(int a, int b) const {
    if (vertex_faces_[a].size() > vertex_faces_[b].size()) std::swap(a, b);
    for (int f : vertex_faces_[a]) {
      if (face_alive_[f] && Corner(f, b) >= 0) return true;
    }
    return false;
  }

  // Notes that one face of x died; compacts x's list once half of it is
  // dead (amortized O(1) per face).
  void DropDeadIncidence(int x) {
    std::vector<int>& list = vertex_faces_[x];
    if (2 * ++dead_incidences_[x] <= static_cast<int>(list.size())) return;
    list.erase(std::remove_if(list.begin(), list.end(),
                              [&](int f) { return !face_alive_[f]; }),
               list.end());
    dead_incidences_[x] = 0;
  }

  int Corner(int f, int x) const {
    for (int i = 0; i < 3; ++i) {
      if (faces_[f][i] == x) return i;
    }
    return -1;
  }

  // Normal of face f with vertex `from` replaced by `to` (from = -1: as is).
  Eigen::Vector3d Normal(int f, int from, int to) const {
    Eigen::Vector3d p[3];
    for (int i = 0; i < 3; ++i) {
      const int x = faces_[f][i] == from ? to : faces_[f][i];
      p[i] = positions_[x];
    }
    return (p[1] - p[0]).cross(p[2] - p[0]);
  }

  // 4 sqrt(3) area / sum of squared edges: 1 for an equilateral triangle, 0
  // for a degenerate one; face f with vertex `from` replaced by `to`.
  double Quality(int f, int from, int to) const {
    Eigen::Vector3d p[3];
    for (int i = 0; i < 3; ++i) {
      const int x = faces_[f][i] == from ? to : faces_[f][i];
      p[i] = positions_[x];
    }
    const double squares = (p[1] - p[0]).squaredNorm() +
                           (p[2] - p[1]).squaredNorm() +
                           (p[0] - p[2]).squaredNorm();
    if (squares == 0.0) return 0.0;
    return 2.0 * std::sqrt(3.0) * (p[1] - p[0]).cross(p[2] - p[0]).norm() /
           squares;
  }

  // v's neighbors counter-clockwise, starting at `first`.
  void OrderedLink(int v, int first, std::vector<int>* out) {
    std::vector<std::pair<int, int>>& next = link_pairs_;  // face (v, a, b)
    next.clear();
    for (int f : vertex_faces_[v]) {
      if (!face_alive_[f]) continue;
      const int c = Corner(f, v);
      next.emplace_back(faces_[f][(c + 1) % 3], faces_[f][(c + 2) % 3]);
    }
    std::sort(next.begin(), next.end());
    std::vector<int>& link = *out;
    link.assign(1, first);
    while (link.size() < next.size()) {
      auto it = std::lower_bound(next.begin(), next.end(),
                                 std::make_pair(link.back(), -1));
      link.push_back(it->second);
    }
  }

  // Contiguous per vertex / face (rows of column-major Eigen matrices
  // would cost three cache misses each).
  std::vector<Eigen::Vector3d> positions_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<char> face_alive_;
  std::vector<bool> vertex_alive_;
  // Faces around each vertex; may hold dead faces (dead_incidences_ counts
  // them).
  std::vector<std::vector<int>> vertex_faces_;
  std::vector<int> dead_incidences_;
  std::vector<int> neighbors_;                   // buffer of TryCollapse
  std::vector<std::pair<int, int>> link_pairs_;  // buffer of OrderedLink
  int alive_vertices_;
  double cos_max_turn_;
  double min_quality_;
  int max_removed_valence_;
};

// A candidate edge: its length and its end points (a < b), ordered by
// length, ties by the end points.
using QueueEntry = std::tuple<double, int, int>;

}  // namespace

StatusOr<MeshHierarchy> BuildMeshHierarchy(
    const TriangleMesh& mesh, const MeshHierarchyOptions& options) {
  if (options.base_vertices < 4) {
    return InvalidArgumentError("base_vertices must be at least 4");
  }
  Collapser collapser(mesh, options);
  // Shortest allowed collapse first. Edge lengths never change (a collapse
  // keeps u where it is), only whether an edge may collapse, and only when
  // a collapse changes the neighborhood of one of its ends. So the queue
  // holds every edge not yet tried, by key (length, then end points); an
  // edge that was tried (popped) and failed is queued again when a collapse
  // changes one of its ends, and a collapse queues the edges it creates.
  // `tried` is the largest key popped so far: edges with larger keys were
  // never popped and are still queued. The collapses are those of the
  // earlier form of this loop, which re-queued every edge of every changed
  // vertex (and skipped the outdated entries), with a fraction of its
  // queue traffic; the one difference: an edge the collapse creates between
  // two vertices of valence above max_removed_valence is queued here (the
  // earlier form queued it only once one of them changed).
  //
  // The queue is two sorted streams: every edge, sorted once, and a heap of
  // the edges queued again; the smaller head is the next entry, so entries
  // come out in the order of one heap holding both (equal entries are the
  // same edge), and the millions of initial edges are not sifted through a
  // heap one by one.
  const int nv = mesh.num_vertices();
  constexpr int kBlock = 4096;
  std::vector<std::vector<QueueEntry>> block_edges((nv + kBlock - 1) / kBlock);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, block_edges.size()),
      [&](const tbb::blocked_range<size_t>& r) {
        std::vector<int> link;
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const int end = std::min(nv, static_cast<int>(i + 1) * kBlock);
          for (int a = static_cast<int>(i) * kBlock; a < end; ++a) {
            collapser.Neighbors(a, &link);
            for (int b : link) {
              if (a < b)
                block_edges[i].emplace_back(collapser.Length(a, b), a, b);
            }
          }
        }
      });
  std::vector<QueueEntry> sorted_edges;
  sorted_edges.reserve(3 * static_cast<size_t>(nv));
  for (const std::vector<QueueEntry>& edges : block_edges) {
    sorted_edges.insert(sorted_edges.end(), edges.begin(), edges.end());
  }
  block_edges.clear();
  tbb::parallel_sort(sorted_edges.begin(), sorted_edges.end());
  size_t next_sorted = 0;
  std::priority_queue<QueueEntry, std::vector<QueueEntry>, std::greater<>>
      queue;
  std::vector<int> neighbors;
  QueueEntry tried(-1.0, -1, -1);
  auto entry = [&](int a, int b) {
    const int lo = std::min(a, b), hi = std::max(a, b);
    return QueueEntry(collapser.Length(lo, hi), lo, hi);
  };
  // Whether `record` created edge (a, b): kept to a vertex of the removed
  // one's link other than the two it shared a face with.
  auto created = [](const HalfEdgeCollapse& record, int a, int b) {
    const int x = a == record.kept ? b : b == record.kept ? a : -1;
    return x >= 0 && x != record.link[1] && x != record.link.back() &&
           std::find(record.link.begin(), record.link.end(), x) !=
               record.link.end();
  };
  std::vector<HalfEdgeCollapse> collapses;
  collapses.reserve(std::max(0, mesh.num_vertices() - options.base_vertices));
  HalfEdgeCollapse record;
  std::vector<int> changed;
  while ((next_sorted < sorted_edges.size() || !queue.empty()) &&
         collapser.alive_vertices() > options.base_vertices) {
    QueueEntry top;
    if (queue.empty() || (next_sorted < sorted_edges.size() &&
                          sorted_edges[next_sorted] < queue.top())) {
      top = sorted_edges[next_sorted++];
    } else {
      top = queue.top();
      queue.pop();
    }
    const auto [length, a, b] = top;
    if (!collapser.vertex_alive(a) || !collapser.vertex_alive(b)) continue;
    tried = std::max(tried, top);
    if (!collapser.TryCollapse(a, b, &record) &&
        !collapser.TryCollapse(b, a, &record)) {
      continue;
    }
    // Every vertex whose neighborhood changed gets its tried edges queued
    // again; except vertices of high valence, which are never removed: their
    // edges to unchanged vertices can only have become less collapsible
    // (more common neighbors), so they are not tried again, and their edges
    // to changed vertices are queued from the other end. This keeps the
    // work per collapse bounded by max_removed_valence.
    for (size_t i = 2; i + 1 < record.link.size(); ++i) {
      queue.push(entry(record.kept, record.link[i]));
    }
    changed.clear();
    for (int w : record.link) {
      if (collapser.Valence(w) <= options.max_removed_valence)
        changed.push_back(w);
    }
    for (int w : changed) {
      collapser.Neighbors(w, &neighbors);
      for (int x : neighbors) {
        if (x < w &&
            std::find(changed.begin(), changed.end(), x) != changed.end()) {
          continue;  // queued from x
        }
        const QueueEntry e = entry(w, x);
        if (!(tried < e) && !created(record, w, x)) queue.push(e);
      }
    }
    collapses.push_back(record);
  }
  return collapser.Release(std::move(collapses));
}

void UndoCollapse(const HalfEdgeCollapse& collapse, Eigen::MatrixX3i* faces,
                  std::vector<bool>* face_alive,
                  std::vector<bool>* vertex_alive) {
  for (int f : collapse.repointed_faces) {
    for (int i = 0; i < 3; ++i) {
      if ((*faces)(f, i) == collapse.kept) (*faces)(f, i) = collapse.removed;
    }
  }
  for (int f : collapse.deleted_faces) (*face_alive)[f] = true;
  (*vertex_alive)[collapse.removed] = true;
}

}  // namespace sdcb
