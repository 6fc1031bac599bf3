#include "sdcb/core/tessellate/sphere_triangulation.h"

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

Eigen::MatrixX3i SphereTriangulation::Faces() const {
  Eigen::MatrixX3i out(num_alive_, 3);
  int r = 0;
  for (size_t f = 0; f < faces_.size(); ++f) {
    if (!alive_[f]) continue;
    out.row(r++) << faces_[f][0], faces_[f][1], faces_[f][2];
  }
  return out;
}

Eigen::MatrixX3d SphereTriangulation::Vertices() const {
  Eigen::MatrixX3d out(vertices_.size(), 3);
  for (size_t v = 0; v < vertices_.size(); ++v) out.row(v) = vertices_[v];
  return out;
}

}  // namespace sdcb
