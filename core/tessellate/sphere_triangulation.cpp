#include "sdcb/core/tessellate/sphere_triangulation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <tuple>

namespace sdcb {

SphereTriangulation SphereTriangulation::Icosahedron(const EdgeLength& length) {
  SphereTriangulation t;
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  const double v[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                           {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                           {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (const auto& p : v) {
    t.vertices_.push_back(Eigen::Vector3d(p[0], p[1], p[2]).normalized());
  }
  const Face f[20] = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10},
                      {0, 10, 11}, {1, 5, 9},  {5, 11, 4}, {11, 10, 2},
                      {10, 7, 6},  {7, 1, 8},  {3, 9, 4},  {3, 4, 2},
                      {3, 2, 6},   {3, 6, 8},  {3, 8, 9},  {4, 9, 5},
                      {2, 4, 11},  {6, 2, 10}, {8, 6, 7},  {9, 8, 1}};
  for (const Face& face : f) t.AddFace(face, length);
  return t;
}

bool SphereTriangulation::Longer(int a, int b, int c, int d) const {
  const double lab = edges_.at(Key(a, b)).length;
  const double lcd = edges_.at(Key(c, d)).length;
  if (lab != lcd) return lab > lcd;
  return std::make_tuple(std::min(a, b), std::max(a, b)) >
         std::make_tuple(std::min(c, d), std::max(c, d));
}

std::array<int, 2> SphereTriangulation::LongestEdge(int f) const {
  const Face& t = faces_[f];
  int best = 0;
  for (int i = 1; i < 3; ++i) {
    if (Longer(t[i], t[(i + 1) % 3], t[best], t[(best + 1) % 3])) best = i;
  }
  return {t[best], t[(best + 1) % 3]};
}

int SphereTriangulation::AddFace(const Face& face, const EdgeLength& length) {
  const int f = static_cast<int>(faces_.size());
  faces_.push_back(face);
  for (int v : face) {
    if (static_cast<int>(vertex_face_.size()) <= v)
      vertex_face_.resize(v + 1, -1);
    vertex_face_[v] = f;
  }
  alive_.push_back(1);
  ++num_alive_;
  for (int i = 0; i < 3; ++i) {
    const int a = face[i], b = face[(i + 1) % 3];
    auto [it, inserted] = edges_.try_emplace(Key(a, b));
    Edge& e = it->second;
    if (inserted) e.length = length(a, b);
    // Slot 0 holds the face that traverses the edge from the smaller index.
    e.face[a < b ? 0 : 1] = f;
  }
  return f;
}

void SphereTriangulation::DetachFace(int f) {
  const Face& face = faces_[f];
  for (int i = 0; i < 3; ++i) {
    const int a = face[i], b = face[(i + 1) % 3];
    auto it = edges_.find(Key(a, b));
    Edge& e = it->second;
    e.face[a < b ? 0 : 1] = -1;
    if (e.face[0] < 0 && e.face[1] < 0) edges_.erase(it);
  }
  alive_[f] = 0;
  --num_alive_;
}

int SphereTriangulation::Opposite(int f, int a, int b) const {
  auto it = edges_.find(Key(a, b));
  if (it == edges_.end()) return -1;
  const Edge& e = it->second;
  return e.face[0] == f ? e.face[1] : e.face[0];
}

int SphereTriangulation::FaceOf(int a, int b) const {
  auto it = edges_.find(Key(a, b));
  if (it == edges_.end()) return -1;
  return it->second.face[a < b ? 0 : 1];
}

void SphereTriangulation::SplitEdge(int a, int b, const EdgeLength& length,
                                    const std::function<void(int)>& on_vertex) {
  const Edge e = edges_.at(Key(a, b));
  // Face (a, b, c) and face (b, a, d).
  auto apex = [&](int f, int from, int to) {
    const Face& t = faces_[f];
    for (int i = 0; i < 3; ++i) {
      if (t[i] == from && t[(i + 1) % 3] == to) return t[(i + 2) % 3];
    }
    return -1;
  };
  const int f1 = e.face[a < b ? 0 : 1], f2 = e.face[a < b ? 1 : 0];
  const int c = apex(f1, a, b), d = apex(f2, b, a);
  assert(c >= 0 && d >= 0);
  const int m = static_cast<int>(vertices_.size());
  vertices_.push_back((vertices_[a] + vertices_[b]).normalized());
  on_vertex(m);
  DetachFace(f1);
  DetachFace(f2);
  AddFace({a, m, c}, length);
  AddFace({m, b, c}, length);
  AddFace({b, m, d}, length);
  AddFace({m, a, d}, length);
}

void SphereTriangulation::Bisect(int f, const EdgeLength& length,
                                 const std::function<void(int)>& on_vertex) {
  std::vector<int> path = {f};
  while (!path.empty()) {
    const int g = path.back();
    if (!alive(g)) {
      path.pop_back();
      continue;
    }
    const auto [a, b] = LongestEdge(g);
    const int h = Opposite(g, a, b);
    const auto [c, d] = LongestEdge(h);
    if ((c == b && d == a) || (c == a && d == b)) {
      SplitEdge(a, b, length, on_vertex);
      path.pop_back();
    } else {
      // h's longest edge is longer than (a, b): split it first.
      path.push_back(h);
    }
  }
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

bool SphereTriangulation::Positive(int a, int b, int c) const {
  return IsPositive(vertices_[a], vertices_[b], vertices_[c]);
}

bool SphereTriangulation::IsPositive(const Eigen::Vector3d& x,
                                     const Eigen::Vector3d& y,
                                     const Eigen::Vector3d& z) {
  // det(x, y, z) = (y - x) x (z - x) . x for unit vectors; relative margin
  // against rounding.
  const Eigen::Vector3d n = (y - x).cross(z - x);
  return n.dot(x) > 1e-12 * (y - x).norm() * (z - x).norm();
}

std::vector<int> SphereTriangulation::Ring(int v) const {
  std::vector<int> ring;
  const int start = vertex_face_[v];
  int f = start;
  do {
    const Face& t = faces_[f];
    const int i = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    const int x = t[(i + 1) % 3], y = t[(i + 2) % 3];
    ring.push_back(x);
    // The next face counter-clockwise shares edge (v, y).
    f = Opposite(f, v, y);
  } while (f != start && f >= 0 && ring.size() < 10000);
  return ring;
}

std::vector<int> SphereTriangulation::Star(int v) const {
  std::vector<int> star;
  const int start = vertex_face_[v];
  int f = start;
  do {
    star.push_back(f);
    const Face& t = faces_[f];
    const int i = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    f = Opposite(f, v, t[(i + 2) % 3]);
  } while (f != start && f >= 0 && star.size() < 10000);
  return star;
}

bool SphereTriangulation::PreviewCollapse(int v, int w,
                                          std::vector<Face>* faces) const {
  faces->clear();
  const std::vector<int> rv = Ring(v), rw = Ring(w);
  if (rv.size() < 3 || rw.size() < 3) return false;
  // Link condition: exactly two common neighbours.
  int common = 0;
  for (int x : rv) {
    for (int y : rw) common += x == y;
  }
  if (common != 2) return false;
  // Collapsing would leave a vertex of degree < 3 (a tetrahedron's corner).
  if (rv.size() + rw.size() - 4 < 3) return false;
  const int n = static_cast<int>(rv.size());
  for (int i = 0; i < n; ++i) {
    const int x = rv[i], y = rv[(i + 1) % n];
    if (x == w || y == w) continue;  // one of the two faces of (v, w)
    if (!Positive(w, x, y)) return false;
    faces->push_back({w, x, y});
  }
  return true;
}

void SphereTriangulation::Collapse(int v, int w, const EdgeLength& length) {
  const std::vector<int> rv = Ring(v);
  std::vector<int> dead;
  int f = vertex_face_[v];
  for (size_t i = 0; i < rv.size(); ++i) {
    dead.push_back(f);
    const Face& t = faces_[f];
    const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    f = Opposite(f, v, t[(k + 2) % 3]);
  }
  std::vector<Face> replaced;
  for (int g : dead) {
    Face t = faces_[g];
    bool has_w = false;
    for (int& x : t) {
      has_w = has_w || x == w;
      if (x == v) x = w;
    }
    if (!has_w) replaced.push_back(t);
  }
  for (int g : dead) DetachFace(g);
  vertex_face_[v] = -1;
  for (const Face& t : replaced) AddFace(t, length);
  // The apexes of the removed faces may point at dead faces.
  for (int x : rv) {
    if (!alive(vertex_face_[x])) {
      for (int g = num_face_slots() - 1; g >= 0; --g) {
        const Face& t = faces_[g];
        if (alive(g) && (t[0] == x || t[1] == x || t[2] == x)) {
          vertex_face_[x] = g;
          break;
        }
      }
    }
  }
}

bool SphereTriangulation::PreviewFlip(int a, int b,
                                      std::vector<Face>* faces) const {
  faces->clear();
  auto it = edges_.find(Key(a, b));
  if (it == edges_.end()) return false;
  const int f1 = it->second.face[a < b ? 0 : 1];
  const int f2 = it->second.face[a < b ? 1 : 0];
  auto apex = [&](int f, int from, int to) {
    const Face& t = faces_[f];
    for (int i = 0; i < 3; ++i) {
      if (t[i] == from && t[(i + 1) % 3] == to) return t[(i + 2) % 3];
    }
    return -1;
  };
  const int c = apex(f1, a, b), d = apex(f2, b, a);
  if (c < 0 || d < 0 || c == d || HasEdge(c, d)) return false;
  if (!Positive(a, d, c) || !Positive(d, b, c)) return false;
  *faces = {Face{a, d, c}, Face{d, b, c}};
  return true;
}

void SphereTriangulation::Flip(int a, int b, const EdgeLength& length) {
  std::vector<Face> faces;
  if (!PreviewFlip(a, b, &faces)) return;
  const Edge e = edges_.at(Key(a, b));
  DetachFace(e.face[0]);
  DetachFace(e.face[1]);
  for (const Face& t : faces) AddFace(t, length);
}

void SphereTriangulation::MoveVertex(int v, const Eigen::Vector3d& direction,
                                     const EdgeLength& length) {
  vertices_[v] = direction;
  for (int x : Ring(v)) edges_.at(Key(v, x)).length = length(v, x);
}

std::vector<std::array<int, 2>> SphereTriangulation::Edges() const {
  std::vector<std::array<int, 2>> out;
  out.reserve(edges_.size());
  for (const auto& [key, e] : edges_) {
    out.push_back(
        {static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu)});
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace sdcb
