#include "sdcb/core/cage/sphere_cage_topology.h"

#include <algorithm>
#include <cassert>
#include <deque>
#include <utility>

#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {
namespace {

// Cells are refined at most this deep (edges of ~1e-7 on the unit sphere).
constexpr int kMaxLevel = 22;

uint64_t EdgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | static_cast<uint32_t>(b);
}

// Appends the unit vector of p to `points`; returns its index.
int AddPoint(const Eigen::Vector3d& p, std::vector<Eigen::Vector3d>* points) {
  points->push_back(p.normalized());
  return static_cast<int>(points->size()) - 1;
}

// A cage as its leaves' templates emit it: all points (the forest's first),
// the faces and the leaf cell of each.
struct CageFaces {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 4>> faces;
  std::vector<int> face_cell;

  int AddPointAt(const Eigen::Vector3d& p) { return AddPoint(p, &points); }
  void Emit(int cell, int a, int b, int c, int d) {
    faces.push_back({a, b, c, d});
    face_cell.push_back(cell);
  }
};

// The faces of quad leaf `cell` (corners v, edge points m, -1 where none)
// by the template of its hanging points: none, two opposite, two adjacent
// (around its centre) or four.
void EmitQuadLeaf(int cell, const std::array<int, 4>& v,
                  const std::array<int, 4>& m, CageFaces* out) {
  int hanging = 0;
  for (int i = 0; i < 4; ++i) hanging += m[i] >= 0;
  auto centre = [&]() {
    const std::vector<Eigen::Vector3d>& points = out->points;
    return out->AddPointAt(points[v[0]] + points[v[1]] + points[v[2]] +
                           points[v[3]]);
  };
  if (hanging == 0) {
    out->Emit(cell, v[0], v[1], v[2], v[3]);
  } else if (hanging == 4) {
    const int c = centre();
    out->Emit(cell, v[0], m[0], c, m[3]);
    out->Emit(cell, m[0], v[1], m[1], c);
    out->Emit(cell, c, m[1], v[2], m[2]);
    out->Emit(cell, m[3], c, m[2], v[3]);
  } else {
    assert(hanging == 2);
    int i = 0;
    while (m[i] < 0) ++i;
    if (i == 0 && m[3] >= 0) i = 3;  // the pair (3, 0) starts at 3
    const int i1 = (i + 1) % 4, i2 = (i + 2) % 4, i3 = (i + 3) % 4;
    if (m[i2] >= 0) {  // opposite edges
      out->Emit(cell, v[i], m[i], m[i2], v[i3]);
      out->Emit(cell, m[i], v[i1], v[i2], m[i2]);
    } else {  // adjacent edges i and i + 1, corner v[i + 1]
      const int c = centre();
      out->Emit(cell, m[i], v[i1], m[i1], c);
      out->Emit(cell, v[i], m[i], c, v[i3]);
      out->Emit(cell, c, m[i1], v[i2], v[i3]);
    }
  }
}

// The faces of triangle leaf `cell` (corners v, edge points m, -1 where
// none) by green closure: one hanging point gives two triangles, two give
// three, three give four.
void EmitTriangleLeaf(int cell, const std::array<int, 4>& v,
                      const std::array<int, 4>& m, CageFaces* out) {
  int hanging = 0;
  for (int i = 0; i < 3; ++i) hanging += m[i] >= 0;
  if (hanging == 0) {
    out->Emit(cell, v[0], v[1], v[2], -1);
  } else if (hanging == 1) {
    int i = 0;
    while (m[i] < 0) ++i;
    out->Emit(cell, v[i], m[i], v[(i + 2) % 3], -1);
    out->Emit(cell, m[i], v[(i + 1) % 3], v[(i + 2) % 3], -1);
  } else if (hanging == 2) {
    int j = 0;  // the edge without a point
    while (m[j] >= 0) ++j;
    const int a = v[j], b = v[(j + 1) % 3], c = v[(j + 2) % 3];
    const int m1 = m[(j + 1) % 3], m2 = m[(j + 2) % 3];
    out->Emit(cell, m1, c, m2, -1);
    // The quad a, b, m1, m2 split along its shorter diagonal.
    const std::vector<Eigen::Vector3d>& points = out->points;
    if ((points[a] - points[m1]).squaredNorm() <=
        (points[b] - points[m2]).squaredNorm()) {
      out->Emit(cell, a, b, m1, -1);
      out->Emit(cell, a, m1, m2, -1);
    } else {
      out->Emit(cell, a, b, m2, -1);
      out->Emit(cell, b, m1, m2, -1);
    }
  } else {
    out->Emit(cell, v[0], m[0], m[2], -1);
    out->Emit(cell, m[0], v[1], m[1], -1);
    out->Emit(cell, m[2], m[1], v[2], -1);
    out->Emit(cell, m[0], m[1], m[2], -1);
  }
}

// The cage of `made` (faces of `n` corners): only the points some face
// uses, in index order.
SphereCage CompactCage(CageFaces made, int n) {
  SphereCage cage;
  cage.face_size = n;
  std::vector<int> index(made.points.size(), -1);
  for (const auto& f : made.faces) {
    for (int k = 0; k < n; ++k) index[f[k]] = 0;
  }
  int used = 0;
  for (int& i : index) {
    if (i >= 0) i = used++;
  }
  cage.sphere_points.resize(used, 3);
  for (size_t i = 0; i < made.points.size(); ++i) {
    if (index[i] >= 0) cage.sphere_points.row(index[i]) = made.points[i];
  }
  for (auto& f : made.faces) {
    for (int k = 0; k < n; ++k) f[k] = index[f[k]];
  }
  cage.faces = std::move(made.faces);
  cage.face_cell = std::move(made.face_cell);
  return cage;
}

}  // namespace

Eigen::Vector3d SphereCage::SpherePoint(int f, double u, double v) const {
  const std::array<int, 4>& c = faces[f];
  Eigen::Vector3d p;
  if (face_size == 4) {
    p = (1 - u) * (1 - v) * sphere_points.row(c[0]).transpose() +
        u * (1 - v) * sphere_points.row(c[1]).transpose() +
        u * v * sphere_points.row(c[2]).transpose() +
        (1 - u) * v * sphere_points.row(c[3]).transpose();
  } else {
    p = (1 - u - v) * sphere_points.row(c[0]).transpose() +
        u * sphere_points.row(c[1]).transpose() +
        v * sphere_points.row(c[2]).transpose();
  }
  return p.normalized();
}

SphereCageTopology SphereCageTopology::Create(CageCellShape shape, int levels) {
  assert(levels >= 0 && levels <= 8);
  SphereCageTopology t;
  t.shape_ = shape;
  if (shape == CageCellShape::kQuad) {
    // The cube [-1, 1]^3; vertex i has coordinate signs from its bits.
    for (int i = 0; i < 8; ++i) {
      t.points_.push_back(
          Eigen::Vector3d(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1)
              .normalized());
    }
    // Counter-clockwise seen from outside.
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
      Cell c;
      c.corners = {f[0], f[1], f[2], f[3]};
      t.cells_.push_back(c);
    }
  } else {
    const TriangleMesh ico = MakeIcosphere(0);
    for (Eigen::Index i = 0; i < ico.vertices.rows(); ++i) {
      t.points_.push_back(ico.vertices.row(i).transpose());
    }
    for (Eigen::Index f = 0; f < ico.faces.rows(); ++f) {
      Cell c;
      c.corners = {ico.faces(f, 0), ico.faces(f, 1), ico.faces(f, 2), -1};
      t.cells_.push_back(c);
    }
  }
  for (int l = 0; l < levels; ++l) {
    const int n = static_cast<int>(t.cells_.size());
    for (int c = 0; c < n; ++c) {
      if (t.cells_[c].first_child < 0) t.RefineCell(c);
    }
  }
  t.Refine({});
  return t;
}

int SphereCageTopology::Midpoint(int a, int b) const {
  const auto it = midpoints_.find(EdgeKey(a, b));
  return it == midpoints_.end() ? -1 : it->second;
}

int SphereCageTopology::GetOrCreateMidpoint(int a, int b) {
  const uint64_t key = EdgeKey(a, b);
  const auto it = midpoints_.find(key);
  if (it != midpoints_.end()) return it->second;
  points_.push_back((points_[a] + points_[b]).normalized());
  const int index = static_cast<int>(points_.size()) - 1;
  midpoints_.emplace(key, index);
  return index;
}

void SphereCageTopology::RefineCell(int cell) {
  const int n = corner_count();
  const std::array<int, 4> v = cells_[cell].corners;
  const int level = cells_[cell].level + 1;
  std::array<int, 4> m{-1, -1, -1, -1};
  for (int i = 0; i < n; ++i) m[i] = GetOrCreateMidpoint(v[i], v[(i + 1) % n]);
  std::vector<std::array<int, 4>> children;
  if (n == 4) {
    points_.push_back(
        (points_[v[0]] + points_[v[1]] + points_[v[2]] + points_[v[3]])
            .normalized());
    const int centre = static_cast<int>(points_.size()) - 1;
    children = {{v[0], m[0], centre, m[3]},
                {m[0], v[1], m[1], centre},
                {centre, m[1], v[2], m[2]},
                {m[3], centre, m[2], v[3]}};
  } else {
    children = {{v[0], m[0], m[2], -1},
                {m[0], v[1], m[1], -1},
                {m[2], m[1], v[2], -1},
                {m[0], m[1], m[2], -1}};
  }
  cells_[cell].first_child = static_cast<int>(cells_.size());
  for (const auto& corners : children) {
    Cell c;
    c.corners = corners;
    c.level = level;
    cells_.push_back(c);
  }
}

void SphereCageTopology::Balance() {
  const int n = corner_count();
  for (bool changed = true; changed;) {
    changed = false;
    const int count = static_cast<int>(cells_.size());
    for (int c = 0; c < count; ++c) {
      if (cells_[c].first_child >= 0) continue;
      const std::array<int, 4> v = cells_[c].corners;
      for (int i = 0; i < n; ++i) {
        const int a = v[i], b = v[(i + 1) % n];
        const int m = Midpoint(a, b);
        if (m >= 0 && (Midpoint(a, m) >= 0 || Midpoint(m, b) >= 0)) {
          RefineCell(c);
          changed = true;
          break;
        }
      }
    }
  }
}

void SphereCageTopology::Refine(const std::vector<int>& leaf_cells) {
  for (int c : leaf_cells) {
    if (c >= 0 && c < static_cast<int>(cells_.size()) &&
        cells_[c].first_child < 0 && cells_[c].level < kMaxLevel) {
      RefineCell(c);
    }
  }
  for (;;) {
    Balance();
    const std::vector<int> more = BuildCage();
    if (more.empty()) break;
    for (int c : more) {
      if (cells_[c].first_child < 0) RefineCell(c);
    }
  }
}

std::vector<int> SphereCageTopology::BuildCage() {
  const int n = corner_count();
  std::vector<int> leaves;
  for (int c = 0; c < static_cast<int>(cells_.size()); ++c) {
    if (cells_[c].first_child < 0) leaves.push_back(c);
  }
  const int nl = static_cast<int>(leaves.size());
  num_leaves_ = nl;
  // Points of the cage: the forest's, then those only the closure adds.
  CageFaces out;
  out.points = points_;
  // The point on each leaf edge (edge i from corner i to corner i + 1).
  std::vector<std::array<int, 4>> mid(nl, {-1, -1, -1, -1});
  for (int l = 0; l < nl; ++l) {
    const std::array<int, 4>& v = cells_[leaves[l]].corners;
    for (int i = 0; i < n; ++i) mid[l][i] = Midpoint(v[i], v[(i + 1) % n]);
  }
  if (n == 4) {
    const std::vector<int> refine = PairQuadParity(leaves, &mid, &out.points);
    if (!refine.empty()) return refine;
  }
  // Faces by template.
  for (int l = 0; l < nl; ++l) {
    const int cell = leaves[l];
    if (n == 4) {
      EmitQuadLeaf(cell, cells_[cell].corners, mid[l], &out);
    } else {
      EmitTriangleLeaf(cell, cells_[cell].corners, mid[l], &out);
    }
  }
  cage_ = CompactCage(std::move(out), n);
  return {};
}

std::vector<int> SphereCageTopology::PairQuadParity(
    const std::vector<int>& leaves, std::vector<std::array<int, 4>>* mid_of,
    std::vector<Eigen::Vector3d>* points) const {
  const int nl = static_cast<int>(leaves.size());
  std::vector<std::array<int, 4>>& mid = *mid_of;
  // Parity: leaves sharing a whole edge (equal leaves) can take a new
  // midpoint on it together.
  std::unordered_map<uint64_t, std::array<int, 2>> edge_leaves;
  for (int l = 0; l < nl; ++l) {
    const std::array<int, 4>& v = cells_[leaves[l]].corners;
    for (int i = 0; i < 4; ++i) {
      auto [it, inserted] = edge_leaves.try_emplace(
          EdgeKey(v[i], v[(i + 1) % 4]), std::array<int, 2>{-1, -1});
      (it->second[0] < 0 ? it->second[0] : it->second[1]) = 4 * l + i;
    }
  }
  auto neighbour = [&](int l, int i) {  // 4 * leaf + edge across, or -1
    const std::array<int, 4>& v = cells_[leaves[l]].corners;
    const std::array<int, 2>& e = edge_leaves.at(EdgeKey(v[i], v[(i + 1) % 4]));
    if (e[1] < 0) return -1;
    return e[0] == 4 * l + i ? e[1] : e[0];
  };
  // Parity as a T-join: every leaf's forced points plus the toggled
  // equal edges must be even. Each odd leaf is paired with the nearest
  // odd leaf (breadth-first over equal leaves) and the edges of the path
  // between them are toggled, which flips only the two ends. A quad grid
  // on the cube is bipartite, so the level-l edges where a region of equal
  // leaves meets finer ones add up to an even number and every such region
  // holds an even number of odd leaves: a partner always exists.
  std::vector<int> parity(nl, 0);
  for (int l = 0; l < nl; ++l) {
    for (int i = 0; i < 4; ++i) parity[l] ^= mid[l][i] >= 0;
  }
  std::vector<char> toggled(4 * static_cast<size_t>(nl), 0);
  std::vector<int> from(nl, -1);  // BFS: 4 * leaf + edge it was reached by
  std::vector<int> visited_at(nl, -1);
  std::vector<int> refine;
  for (int s = 0; s < nl; ++s) {
    if (!parity[s]) continue;
    std::deque<int> queue = {s};
    visited_at[s] = s;
    int t = -1;
    while (!queue.empty() && t < 0) {
      const int l = queue.front();
      queue.pop_front();
      for (int i = 0; i < 4; ++i) {
        if (mid[l][i] >= 0) continue;  // a forced point: a finer leaf
        const int across = neighbour(l, i);
        if (across < 0 || visited_at[across / 4] == s) continue;
        visited_at[across / 4] = s;
        from[across / 4] = 4 * l + i;
        if (parity[across / 4]) {
          t = across / 4;
          break;
        }
        queue.push_back(across / 4);
      }
    }
    if (t < 0) {  // not expected (see above); refining s is always valid
      refine.push_back(leaves[s]);
      continue;
    }
    for (int l = t; l != s;) {
      const int edge = from[l];
      const int across = neighbour(edge / 4, edge % 4);
      toggled[edge] ^= 1;
      toggled[across] ^= 1;
      l = edge / 4;
    }
    parity[s] = parity[t] = 0;
  }
  for (int l = 0; l < nl; ++l) {
    for (int i = 0; i < 4; ++i) {
      const int across = neighbour(l, i);
      if (!toggled[4 * l + i] || across < 4 * l + i) continue;
      const std::array<int, 4>& v = cells_[leaves[l]].corners;
      const int p =
          AddPoint((*points)[v[i]] + (*points)[v[(i + 1) % 4]], points);
      mid[l][i] = p;
      mid[across / 4][across % 4] = p;
    }
  }
  return refine;
}

}  // namespace sdcb
