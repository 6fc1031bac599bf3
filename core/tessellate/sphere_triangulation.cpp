#include "sdcb/core/tessellate/sphere_triangulation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <utility>

#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {

SphereTriangulation SphereTriangulation::Icosphere(int subdivisions) {
  const TriangleMesh sphere = MakeIcosphere(subdivisions);
  // MakeIcosphere's output is a closed, consistently oriented sphere.
  return *FromFaces(sphere.vertices, sphere.faces);
}

StatusOr<SphereTriangulation> SphereTriangulation::FromFaces(
    const Eigen::MatrixX3d& directions, const Eigen::MatrixX3i& faces,
    bool allow_unused) {
  SphereTriangulation t;
  const int nv = static_cast<int>(directions.rows());
  const int nf = static_cast<int>(faces.rows());
  t.vertices_.resize(nv);
  for (int v = 0; v < nv; ++v) t.vertices_[v] = directions.row(v).transpose();
  t.faces_.resize(nf);
  t.alive_.assign(nf, 1);
  t.twin_.assign(3 * nf, -1);
  t.vertex_face_.assign(nv, -1);
  t.num_alive_ = nf;
  // Directed edges as (key, half-edge), sorted: each edge's twin is the
  // reversed key.
  std::vector<std::pair<uint64_t, int>> directed(3 * nf);
  for (int f = 0; f < nf; ++f) {
    for (int e = 0; e < 3; ++e) {
      const int a = faces(f, e), b = faces(f, (e + 1) % 3);
      if (a < 0 || a >= nv || b < 0 || b >= nv || a == b) {
        return InvalidArgumentError("face " + std::to_string(f) +
                                    " has a bad corner");
      }
      t.faces_[f][e] = a;
      t.vertex_face_[a] = f;
      directed[3 * f + e] = {(uint64_t(a) << 32) | uint32_t(b), 3 * f + e};
    }
  }
  // The keys are distinct in a valid input, so the order (and the result)
  // does not depend on the sort's threads.
  tbb::parallel_sort(directed.begin(), directed.end());
  for (size_t i = 1; i < directed.size(); ++i) {
    if (directed[i].first == directed[i - 1].first) {
      return InvalidArgumentError("a directed edge is used twice");
    }
  }
  std::vector<char> open(directed.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, directed.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i < range.end(); ++i) {
                        const uint64_t key = directed[i].first;
                        const uint64_t reversed = (key << 32) | (key >> 32);
                        const auto it =
                            std::lower_bound(directed.begin(), directed.end(),
                                             std::make_pair(reversed, -1));
                        if (it == directed.end() || it->first != reversed) {
                          open[i] = 1;
                        } else {
                          t.twin_[directed[i].second] = it->second;
                        }
                      }
                    });
  if (std::find(open.begin(), open.end(), 1) != open.end()) {
    return InvalidArgumentError("the faces are not closed");
  }
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_face_[v] < 0 && !allow_unused) {
      return InvalidArgumentError("vertex " + std::to_string(v) +
                                  " is in no face");
    }
  }
  return t;
}

int SphereTriangulation::HalfEdge(int a, int b) const {
  const int start = vertex_face_[a];
  int f = start;
  do {
    const Face& t = faces_[f];
    const int i = t[0] == a ? 0 : t[1] == a ? 1 : 2;
    if (t[(i + 1) % 3] == b) return 3 * f + i;
    f = twin_[3 * f + (i + 2) % 3] / 3;
  } while (f != start);
  return -1;
}

void SphereTriangulation::Star(int v, std::vector<int>* faces,
                               std::vector<int>* ring) const {
  if (faces) faces->clear();
  if (ring) ring->clear();
  const int start = vertex_face_[v];
  int f = start;
  do {
    const Face& t = faces_[f];
    const int i = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    if (faces) faces->push_back(f);
    if (ring) ring->push_back(t[(i + 1) % 3]);
    // The next face counter-clockwise is across the edge into v.
    f = twin_[3 * f + (i + 2) % 3] / 3;
  } while (f != start);
}

int SphereTriangulation::AppendFace() {
  faces_.push_back({-1, -1, -1});
  alive_.push_back(1);
  twin_.insert(twin_.end(), 3, -1);
  ++num_alive_;
  return static_cast<int>(faces_.size()) - 1;
}

void SphereTriangulation::SetFeatures(std::vector<std::array<int, 2>> arc_ends,
                                      std::vector<int> vertex_arc) {
  arc_ends_ = std::move(arc_ends);
  vertex_arc_ = std::move(vertex_arc);
  vertex_arc_.resize(vertices_.size(), kFreeVertex);
  corner_pairs_.clear();
  for (int arc = 0; arc < static_cast<int>(arc_ends_.size()); ++arc) {
    const uint32_t a = arc_ends_[arc][0], b = arc_ends_[arc][1];
    corner_pairs_.push_back(
        {(uint64_t(std::min(a, b)) << 32) | std::max(a, b), arc});
  }
  std::sort(corner_pairs_.begin(), corner_pairs_.end());
}

int SphereTriangulation::CommonArc(int a, int b) const {
  if (!has_features()) return -1;
  const int ta = vertex_arc_[a], tb = vertex_arc_[b];
  if (ta == kFreeVertex || tb == kFreeVertex) return -1;
  if (ta >= 0) return OnArc(b, ta) ? ta : -1;
  if (tb >= 0) return OnArc(a, tb) ? tb : -1;
  // Two corners: the arc between them, if any (the first when several).
  const uint64_t key =
      (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
  const auto it = std::lower_bound(corner_pairs_.begin(), corner_pairs_.end(),
                                   std::make_pair(key, -1));
  return it != corner_pairs_.end() && it->first == key ? it->second : -1;
}

int SphereTriangulation::SplitEdge(int h, const Eigen::Vector3d& direction) {
  const int m = num_vertices();
  if (has_features()) {
    const int arc = CommonArc(Origin(h), Target(h));
    vertex_arc_.push_back(arc >= 0 ? arc : kFreeVertex);
  }
  vertices_.push_back(direction);
  vertex_face_.push_back(-1);
  SplitEdgeAt(h, m);
  return m;
}

SphereTriangulation::Quad SphereTriangulation::QuadOf(int h) const {
  const int f = h / 3, t = twin_[h], g = t / 3;
  return {f,
          g,
          Origin(h),
          Target(h),
          Apex(h),
          Apex(t),
          twin_[3 * f + (h % 3 + 1) % 3],
          twin_[3 * f + (h % 3 + 2) % 3],
          twin_[3 * g + (t % 3 + 1) % 3],
          twin_[3 * g + (t % 3 + 2) % 3]};
}

void SphereTriangulation::SplitEdgeAt(int h, int m) {
  const auto [f, g, a, b, c, d, out_bc, out_ca, out_ad, out_db] = QuadOf(h);
  const int f2 = AppendFace(), g2 = AppendFace();
  SetFace(f, a, m, c);
  SetFace(f2, m, b, c);
  SetFace(g, b, m, d);
  SetFace(g2, m, a, d);
  Link(3 * f, 3 * g2);
  Link(3 * f2, 3 * g);
  Link(3 * f + 1, 3 * f2 + 2);
  Link(3 * g + 1, 3 * g2 + 2);
  Link(3 * f + 2, out_ca);
  Link(3 * f2 + 1, out_bc);
  Link(3 * g + 2, out_db);
  Link(3 * g2 + 1, out_ad);
  vertex_face_[a] = f;
  vertex_face_[b] = g;
  vertex_face_[c] = f;
  vertex_face_[d] = g;
  vertex_face_[m] = f;
}

bool SphereTriangulation::PreviewCollapse(int v, int w,
                                          std::vector<Face>* faces,
                                          std::vector<int>* slots) const {
  if (has_features()) {
    // Corners stay; an arc's vertex moves only along its arc.
    const int arc = vertex_arc_[v];
    if (arc == kCornerVertex) return false;
    if (arc >= 0 && !OnArc(w, arc)) return false;
  }
  thread_local std::vector<int> star, ring, ring_w;
  Star(v, &star, &ring);
  const int n = static_cast<int>(ring.size());
  int j = -1;
  for (int i = 0; i < n; ++i) {
    if (ring[i] == w) j = i;
  }
  if (j < 0 || n < 3) return false;
  faces->clear();
  if (slots) slots->clear();
  for (int i = 0; i < n; ++i) {
    if (i == j || i == (j + n - 1) % n) continue;  // the faces of (v, w)
    const Face t = {w, ring[i], ring[(i + 1) % n]};
    if (!IsPositive(vertices_[t[0]], vertices_[t[1]], vertices_[t[2]])) {
      return false;
    }
    faces->push_back(t);
    if (slots) slots->push_back(star[i]);
  }
  // Link condition: v and w share exactly the two apexes of edge (v, w).
  const int x = ring[(j + 1) % n], y = ring[(j + n - 1) % n];
  Star(w, nullptr, &ring_w);
  if (ring_w.size() < 4 && n < 4) return false;  // a tetrahedron's corner
  for (int u : ring_w) {
    if (u == v || u == x || u == y) continue;
    if (std::find(ring.begin(), ring.end(), u) != ring.end()) return false;
  }
  return true;
}

void SphereTriangulation::Collapse(int v, int w) {
  std::vector<int> star, ring;
  Star(v, &star, &ring);
  const int n = static_cast<int>(ring.size());
  int j = 0;
  while (ring[j] != w) ++j;
  // fa = (v, w, x) = star[j], fb = (v, y, w) = star[j - 1].
  const int fa = star[j], fb = star[(j + n - 1) % n];
  const int x = ring[(j + 1) % n], y = ring[(j + n - 1) % n];
  const int ha = HalfEdge(w, x), hb = HalfEdge(y, w);  // in fa and fb
  const int out_wx = twin_[ha], out_yw = twin_[hb];
  const int in_xv = twin_[3 * fa + (ha % 3 + 1) % 3];  // v -> x, next face
  const int in_vy = twin_[3 * fb + (hb % 3 + 2) % 3];  // y -> v, face before
  for (int i = 0; i < n; ++i) {
    const int f = star[i];
    if (f == fa || f == fb) continue;
    for (int& corner : faces_[f]) {
      if (corner == v) corner = w;
    }
  }
  Link(in_xv, out_wx);
  Link(in_vy, out_yw);
  for (int f : {fa, fb}) {
    alive_[f] = 0;
    for (int e = 0; e < 3; ++e) twin_[3 * f + e] = -1;
    --num_alive_;
  }
  vertex_face_[v] = -1;
  vertex_face_[w] = in_xv / 3;
  vertex_face_[x] = in_xv / 3;
  vertex_face_[y] = in_vy / 3;
}

bool SphereTriangulation::PreviewFlip(int h, std::array<Face, 2>* faces) const {
  const int t = twin_[h];
  const int a = Origin(h), b = Target(h), c = Apex(h), d = Apex(t);
  if (c == d || HalfEdge(c, d) >= 0 || IsFeatureEdge(a, b)) return false;
  if (!IsPositive(vertices_[a], vertices_[d], vertices_[c]) ||
      !IsPositive(vertices_[d], vertices_[b], vertices_[c])) {
    return false;
  }
  *faces = {Face{a, d, c}, Face{d, b, c}};
  return true;
}

void SphereTriangulation::Flip(int h) {
  const auto [f, g, a, b, c, d, out_bc, out_ca, out_ad, out_db] = QuadOf(h);
  SetFace(f, a, d, c);
  SetFace(g, d, b, c);
  Link(3 * f, out_ad);
  Link(3 * f + 1, 3 * g + 2);
  Link(3 * f + 2, out_ca);
  Link(3 * g, out_db);
  Link(3 * g + 1, out_bc);
  vertex_face_[a] = f;
  vertex_face_[b] = g;
  vertex_face_[c] = f;
  vertex_face_[d] = f;
}

bool SphereTriangulation::IsPositive(const Eigen::Vector3d& x,
                                     const Eigen::Vector3d& y,
                                     const Eigen::Vector3d& z) {
  // det(x, y, z) = (y - x) x (z - x) . x for unit vectors; relative margin
  // against rounding.
  const Eigen::Vector3d n = (y - x).cross(z - x);
  return n.dot(x) > 1e-12 * (y - x).norm() * (z - x).norm();
}

std::vector<int> SphereTriangulation::AliveVertices() const {
  std::vector<int> out;
  for (int v = 0; v < num_vertices(); ++v) {
    if (vertex_alive(v)) out.push_back(v);
  }
  return out;
}

Eigen::MatrixX3i SphereTriangulation::Faces() const {
  std::vector<int> index(vertices_.size(), -1);
  int next = 0;
  for (int v = 0; v < num_vertices(); ++v) {
    if (vertex_alive(v)) index[v] = next++;
  }
  Eigen::MatrixX3i out(num_alive_, 3);
  int r = 0;
  for (size_t f = 0; f < faces_.size(); ++f) {
    if (!alive_[f]) continue;
    out.row(r++) << index[faces_[f][0]], index[faces_[f][1]],
        index[faces_[f][2]];
  }
  return out;
}

}  // namespace sdcb
