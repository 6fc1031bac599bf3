#include "sdcb/core/spline/piecewise_region_builder.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <memory>

#include "sdcb/core/spline/simplex_spline.h"

namespace sdcb {
namespace {

// out[4 m + d] += c4[d] * poly[m].
void AddScaled(const double* poly, const double c4[4], int size, double* out) {
  for (int m = 0; m < size; ++m)
    for (int d = 0; d < 4; ++d) out[4 * m + d] += c4[d] * poly[m];
}

// A copy of `v` in the arena (null if empty).
template <typename T>
T* CopyToArena(const std::vector<T>& v, BlockArena* arena) {
  if (v.empty()) return nullptr;
  T* out = static_cast<T*>(arena->Allocate(v.size() * sizeof(T)));
  std::uninitialized_copy(v.begin(), v.end(), out);
  return out;
}

}  // namespace

// The sums of a cell (see the header), as MakeCell makes them.
struct PiecewiseRegionBuilder::Cell {
  // A triangle edge that is not a line: the perturbed sign of det(p, t_a,
  // t_b) the triangle needs (constant wherever its lines' signs are right).
  struct Edge {
    Eigen::Vector3d normal;  // t_a x t_b
    int a = 0, b = 0;        // knots
    int sign = 0;
  };
  struct Triangle {
    int first_edge = 0, num_edges = 0;  // in edges
    int next = -1;                      // the group's next triangle
    int sum = 0;                        // offset in sums
  };
  struct Group {
    uint64_t mask = 0, want = 0;  // the key's bits and their values
    int first = -1, last = -1;    // its triangles
    const double* sum = nullptr;  // in the arena, null until found
  };

  std::vector<double> base;
  std::vector<Edge> edges;
  std::vector<Triangle> triangles;
  std::vector<Group> groups;
  std::vector<double> sums;  // the triangles'
  // The largest |coefficient| of a triangle's term, w P_iT / |det T|, before
  // the terms are summed.
  double largest_term = 0.0;
  // Open addressing: (knots, triangle) by the triangle's knots; only while
  // the cell is made.
  std::vector<std::pair<uint64_t, int>> triangle_of;

  // The index of the triangle `id`, or -1 with its slot in `*slot`.
  int FindTriangle(uint64_t id, std::size_t* slot) const {
    const std::size_t mask = triangle_of.size() - 1;
    std::size_t i = (id * 0x9E3779B97F4A7C15ULL) >> 40 & mask;
    while (triangle_of[i].second >= 0 && triangle_of[i].first != id) {
      i = (i + 1) & mask;
    }
    *slot = i;
    return triangle_of[i].second;
  }
  void ClearTriangles(std::size_t expected) {
    std::size_t size = 64;
    while (size < 2 * expected) size *= 2;
    triangle_of.assign(size, {0, -1});
  }
  // Inserts the known triangles again into a larger triangle_of.
  void GrowTriangles() {
    std::vector<std::pair<uint64_t, int>> known;
    for (const auto& entry : triangle_of) {
      if (entry.second >= 0) known.push_back(entry);
    }
    ClearTriangles(2 * known.size() + 2);
    for (const auto& entry : known) {
      std::size_t s = 0;
      FindTriangle(entry.first, &s);
      triangle_of[s] = entry;
    }
  }
  // Adds the triangle `id` (not yet in triangle_of, whose free `slot` for it
  // FindTriangle gave): the leaf of local knots k (ascending) and
  // orientation `orientation` of a set of m knots, global indices `global`
  // and pair bits `bits`. Records its lines' bits and the signs it needs
  // there, its other edges, its group and 4 * size zero sums; returns its
  // index.
  int AddTriangle(uint64_t id, std::size_t slot, const std::array<int, 3>& k,
                  int orientation, const int8_t* bits,
                  const std::vector<int>& global, int m,
                  const Eigen::MatrixX3d& knots, int size) {
    if (2 * (triangles.size() + 1) > triangle_of.size()) {
      GrowTriangles();
      FindTriangle(id, &slot);
    }
    const int index = static_cast<int>(triangles.size());
    triangle_of[slot] = {id, index};
    Triangle t;
    t.first_edge = static_cast<int>(edges.size());
    t.sum = static_cast<int>(sums.size());
    sums.resize(sums.size() + 4 * size, 0.0);
    uint64_t mask = 0, want = 0;
    for (int e = 0; e < 3; ++e) {
      const int x = k[e == 0 ? 1 : 0], y = k[e == 2 ? 1 : 2];
      const int sign = e == 1 ? -orientation : orientation;
      const int bit = bits[PairIndex(x, y, m)];
      if (bit >= 0) {
        // The key's bit is the sign with the knots ascending.
        mask |= uint64_t{1} << bit;
        if ((global[x] < global[y]) == (sign > 0)) {
          want |= uint64_t{1} << bit;
        }
      } else {
        Edge edge;
        edge.a = global[x];
        edge.b = global[y];
        const Eigen::Vector3d ta = knots.row(edge.a).transpose();
        const Eigen::Vector3d tb = knots.row(edge.b).transpose();
        edge.normal = ta.cross(tb);
        edge.sign = sign;
        edges.push_back(edge);
      }
    }
    t.num_edges = static_cast<int>(edges.size()) - t.first_edge;
    size_t g = 0;
    while (g < groups.size() &&
           (groups[g].mask != mask || groups[g].want != want)) {
      ++g;
    }
    if (g == groups.size()) {
      Group group;
      group.mask = mask;
      group.want = want;
      groups.push_back(group);
    }
    Group& group = groups[g];
    if (group.last >= 0) {
      triangles[group.last].next = index;
    } else {
      group.first = index;
    }
    group.last = index;
    triangles.push_back(t);
    return index;
  }
};

// The cell's sums kept for its life: Cell's arrays copied to the arena.
struct PiecewiseRegionBuilder::Kept {
  const double* base = nullptr;
  const Cell::Edge* edges = nullptr;
  const Cell::Triangle* triangles = nullptr;
  Cell::Group* groups = nullptr;
  int num_groups = 0;
  const double* sums = nullptr;
  bool ill_conditioned = false;
};

PiecewiseRegionBuilder::PiecewiseRegionBuilder(
    const SphericalSpline& spline, const Eigen::Vector3d& o,
    const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
    const std::vector<int>& sets, const std::vector<int8_t>& pair_bits,
    const Eigen::Vector3d& p, BlockArena* arena)
    : spline_(spline),
      arena_(arena),
      o_(o),
      e1_(e1),
      e2_(e2),
      size_(PolynomialSize(spline.degree())) {
  const DcbBasis& basis = spline_.basis();
  const int m = spline.degree() + 3;
  const int pairs = m * (m - 1) / 2;
  fixed_.assign(4 * size_, 0.0);
  pair_bits_.reserve(pair_bits.size());
  std::vector<double> piece(size_);
  for (size_t j = 0; j < sets.size(); ++j) {
    const int b = sets[j];
    const bool lines = std::any_of(pair_bits.begin() + j * pairs,
                                   pair_bits.begin() + (j + 1) * pairs,
                                   [](int8_t bit) { return bit >= 0; });
    if (lines) {
      if (basis.num_limit_terms(b) > 0 || !basis.has_simplex_spline(b)) {
        other_sets_.push_back(b);
      } else if (basis.weight(b) != 0.0) {
        sets_.push_back(b);
        pair_bits_.insert(pair_bits_.end(), pair_bits.begin() + j * pairs,
                          pair_bits.begin() + (j + 1) * pairs);
      }
      continue;
    }
    // One piece in the whole cell.
    std::fill(piece.begin(), piece.end(), 0.0);
    if (basis.AddPiecePolynomial(b, p, o_, e1_, e2_, piece.data())) {
      const Eigen::RowVector3d c = spline_.control_points().row(b);
      const double c4[4] = {c[0], c[1], c[2], 1.0};
      AddScaled(piece.data(), c4, size_, fixed_.data());
    }
  }
}

PiecewiseRegionBuilder::~PiecewiseRegionBuilder() = default;

void PiecewiseRegionBuilder::MakeCell(const Eigen::Vector3d& p,
                                      Cell* cell) const {
  const DcbBasis& basis = spline_.basis();
  const Eigen::MatrixX3d& knots = spline_.knots();
  const int m = spline_.degree() + 3;
  const int pairs = m * (m - 1) / 2;
  const uint64_t n = static_cast<uint64_t>(knots.rows());
  cell->base = fixed_;
  cell->edges.clear();
  cell->triangles.clear();
  cell->groups.clear();
  cell->sums.clear();
  cell->largest_term = 0.0;
  cell->ClearTriangles(sets_.size() * 8);
  thread_local std::vector<double> paths;
  // Per leaf of a set's recursion: 0 off in the cell, 1 on everywhere, 2
  // with lines; and whether its path polynomial is wanted (1 or 2).
  char kind[256];
  bool wanted[256];
  for (size_t j = 0; j < sets_.size(); ++j) {
    const int b = sets_[j];
    const SimplexSpline& spline = basis.simplex_spline(b);
    const std::vector<int>& global = basis.configuration_set(b).knots;
    const int8_t* bits = pair_bits_.data() + j * pairs;
    const int leaves = spline.num_leaves();
    std::fill(kind, kind + leaves, 0);
    int signs[SimplexSpline::kMaxKnots * (SimplexSpline::kMaxKnots - 1) / 2];
    spline.PairSigns(p, signs);
    for (int i = 0; i < leaves; ++i) {
      const SimplexSpline::Leaf leaf = spline.leaf(i);
      const int o = leaf.orientation;
      if (o == 0) continue;
      // Inside [ta, tb, tc) iff the signs of the pairs (b,c), (a,c), (a,b)
      // are o, -o, o (SimplexSpline::LeafValue).
      const auto& k = leaf.knots;
      const int bc = PairIndex(k[1], k[2], m), ac = PairIndex(k[0], k[2], m),
                ab = PairIndex(k[0], k[1], m);
      if (bits[bc] >= 0 || bits[ac] >= 0 || bits[ab] >= 0) {
        kind[i] = 2;
      } else if (signs[bc] == o && signs[ac] == -o && signs[ab] == o) {
        kind[i] = 1;
      }
    }
    for (int i = 0; i < leaves; ++i) wanted[i] = kind[i] != 0;
    paths.resize(static_cast<size_t>(leaves) * size_);
    spline.LeafPathPolynomials(o_, e1_, e2_, wanted, paths.data());
    const Eigen::RowVector3d c = spline_.control_points().row(b);
    const double w = basis.weight(b);
    for (int i = 0; i < leaves; ++i) {
      if (kind[i] == 0) continue;
      const SimplexSpline::Leaf leaf = spline.leaf(i);
      const double scale = w * leaf.inv_abs_det;
      const double c4[4] = {scale * c[0], scale * c[1], scale * c[2], scale};
      const double* poly = paths.data() + static_cast<size_t>(i) * size_;
      for (int q = 0; q < size_; ++q) {
        cell->largest_term =
            std::max(cell->largest_term, std::abs(scale * poly[q]));
      }
      if (kind[i] == 1) {
        AddScaled(poly, c4, size_, cell->base.data());
        continue;
      }
      const auto& k = leaf.knots;
      std::array<uint64_t, 3> sorted = {static_cast<uint64_t>(global[k[0]]),
                                        static_cast<uint64_t>(global[k[1]]),
                                        static_cast<uint64_t>(global[k[2]])};
      std::sort(sorted.begin(), sorted.end());
      const uint64_t id = (sorted[0] * n + sorted[1]) * n + sorted[2];
      std::size_t slot = 0;
      int index = cell->FindTriangle(id, &slot);
      if (index < 0) {
        index = cell->AddTriangle(id, slot, k, leaf.orientation, bits, global,
                                  m, knots, size_);
      }
      AddScaled(poly, c4, size_,
                cell->sums.data() + cell->triangles[index].sum);
    }
  }
}

bool PiecewiseRegionBuilder::Build(const Eigen::Vector3d& p, uint64_t key,
                                   double* out) {
  const int n = 4 * size_;
  if (kept_ == nullptr) {
    // Made in this thread's buffers, kept in the arena.
    thread_local Cell made;
    MakeCell(p, &made);
    Kept* kept = arena_->New<Kept>();
    kept->base = CopyToArena(made.base, arena_);
    kept->edges = CopyToArena(made.edges, arena_);
    kept->triangles = CopyToArena(made.triangles, arena_);
    kept->groups = CopyToArena(made.groups, arena_);
    kept->num_groups = static_cast<int>(made.groups.size());
    kept->sums = CopyToArena(made.sums, arena_);
    kept->ill_conditioned = made.largest_term > kMaxTermMagnitude;
    kept_ = kept;
    // Only MakeCell reads these: freed for the next cells' builders.
    std::vector<double>().swap(fixed_);
    std::vector<int>().swap(sets_);
    std::vector<int8_t>().swap(pair_bits_);
  }
  const Kept* cell = kept_;
  if (cell->ill_conditioned) return false;
  std::copy(cell->base, cell->base + n, out);
  const Eigen::MatrixX3d& knots = spline_.knots();
  const double bound = kSignFilter * 3.01 * p.cwiseAbs().sum();
  for (int g = 0; g < cell->num_groups; ++g) {
    Cell::Group& group = cell->groups[g];
    if ((key & group.mask) != group.want) continue;
    if (group.sum == nullptr) {
      // The first region with these signs: its triangles that are on there
      // (their other edges' signs are the same at every such point).
      double* sum = arena_->New<double>(n);
      for (int t = group.first; t >= 0; t = cell->triangles[t].next) {
        const Cell::Triangle& triangle = cell->triangles[t];
        bool on = true;
        for (int e = 0; e < triangle.num_edges && on; ++e) {
          const Cell::Edge& edge = cell->edges[triangle.first_edge + e];
          on = FilteredSign(p.dot(edge.normal), bound, p,
                            knots.row(edge.a).transpose(),
                            knots.row(edge.b).transpose()) == edge.sign;
        }
        if (!on) continue;
        const double* a = cell->sums + triangle.sum;
        for (int i = 0; i < n; ++i) sum[i] += a[i];
      }
      group.sum = sum;
    }
    for (int i = 0; i < n; ++i) out[i] += group.sum[i];
  }
  if (!other_sets_.empty()) {
    std::vector<double> piece(size_);
    const DcbBasis& basis = spline_.basis();
    for (int b : other_sets_) {
      std::fill(piece.begin(), piece.end(), 0.0);
      if (!basis.AddPiecePolynomial(b, p, o_, e1_, e2_, piece.data())) continue;
      const Eigen::RowVector3d c = spline_.control_points().row(b);
      const double c4[4] = {c[0], c[1], c[2], 1.0};
      AddScaled(piece.data(), c4, size_, out);
    }
  }
  return true;
}

}  // namespace sdcb
