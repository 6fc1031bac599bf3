#include "sdcb/core/spline/piecewise_surface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "sdcb/core/spline/simplex_spline.h"

namespace sdcb {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxLines = 64;    // bits of a region key
constexpr int kSplitLines = 40;  // cells with more lines are split
constexpr int kMaxDepth = 8;
constexpr Eigen::Index kChunk = Eigen::Index{1} << 18;  // EvaluateMany

// Cube face f: axis a = sign * e_k (f = 2k + (sign < 0)) and e1 = e_i1,
// e2 = e_i2 with e1 x e2 = a, so the chart (u, v) -> a + u e1 + v e2 is
// positively oriented.
struct Face {
  int k, i1, i2;
  double sign;
};
constexpr Face kFaces[6] = {{0, 1, 2, 1.0},  {0, 2, 1, -1.0}, {1, 2, 0, 1.0},
                            {1, 0, 2, -1.0}, {2, 0, 1, 1.0},  {2, 1, 0, -1.0}};

void FaceFrame(int f, Eigen::Vector3d* a, Eigen::Vector3d* e1,
               Eigen::Vector3d* e2) {
  *a = kFaces[f].sign * Eigen::Vector3d::Unit(kFaces[f].k);
  *e1 = Eigen::Vector3d::Unit(kFaces[f].i1);
  *e2 = Eigen::Vector3d::Unit(kFaces[f].i2);
}

double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Whether two caps (unit axes a, b; angular radii whose cosines and sines
// are given) may meet: false only if the angle between the axes exceeds the
// sum of the radii (plus 1e-9 rad) by more than rounding.
bool CapsMayMeet(const Eigen::Vector3d& a, double cos_a, double sin_a,
                 double radius_a, const Eigen::Vector3d& b, double cos_b,
                 double sin_b, double radius_b) {
  if (radius_a + radius_b + 1e-9 >= kPi) return true;
  // cos(ra + rb + 1e-9) >= cos(ra + rb) - 1e-9; keep a further 1e-12.
  const double limit = cos_a * cos_b - sin_a * sin_b - 1e-9 - 1e-12;
  return !(a.dot(b) < limit);
}

uint64_t Hash(uint64_t key) { return key * 0x9E3779B97F4A7C15ULL; }

}  // namespace

// Quadtree node in (u, v) of a cube face: centre (uc, vc), half side h. An
// inner node's children are child .. child + 3, quadrant (u >= uc) + 2 (v
// >= vc); a leaf has child = -1 and its index in leaves_.
struct PiecewiseSurface::Node {
  double uc = 0.0, vc = 0.0, h = 1.0;
  int child = -1;
  int leaf = -1;
};

// Open-addressing map from region key to coefficients. Written only under
// the leaf's mutex; read without it: a slot's value is stored (release)
// after its key, so a reader that sees the value sees the key. A full table
// is replaced by a larger copy (the old one stays alive until the surface
// is destroyed, for readers still probing it).
struct PiecewiseSurface::Table {
  struct Slot {
    std::atomic<uint64_t> key{0};
    std::atomic<const double*> value{nullptr};
  };
  explicit Table(int log2)
      : shift(64 - log2),
        mask((uint64_t{1} << log2) - 1),
        slots(new Slot[uint64_t{1} << log2]) {}
  const double* Find(uint64_t key) const {
    for (uint64_t i = Hash(key) >> shift;; i = (i + 1) & mask) {
      const double* v = slots[i].value.load(std::memory_order_acquire);
      if (v == nullptr) return nullptr;
      if (slots[i].key.load(std::memory_order_relaxed) == key) return v;
    }
  }
  void Insert(uint64_t key, const double* value) {
    uint64_t i = Hash(key) >> shift;
    while (slots[i].value.load(std::memory_order_relaxed) != nullptr) {
      i = (i + 1) & mask;
    }
    slots[i].key.store(key, std::memory_order_relaxed);
    slots[i].value.store(value, std::memory_order_release);
    ++count;
  }
  int shift;
  uint64_t mask;
  std::unique_ptr<Slot[]> slots;
  int64_t count = 0;
};

// What building a leaf's regions needs (made on its first region, under the
// leaf's mutex).
struct PiecewiseSurface::Builder {
  // For the j-th basis function of the leaf: the positions in leaf.lines of
  // its knot segments, set_lines[set_start[j] .. set_start[j + 1]).
  std::vector<int> set_start, set_lines;
  // For the j-th basis function, its pieces built so far (a few): (signs
  // against its lines, offset of the piece polynomial in piece_data or -1
  // if it vanishes there).
  std::vector<std::vector<std::pair<uint32_t, int>>> pieces;
  std::vector<double> piece_data;
  std::vector<std::unique_ptr<Table>> tables;  // the last one is current
  // Region coefficients in blocks of 2, 2, 4, 8, ... regions (a leaf has
  // ~10 on average, some a few hundred).
  std::vector<std::unique_ptr<double[]>> blocks;
  int block_capacity = 0, block_used = 0;
};

// EvaluateMany's buffers for one chunk of rows.
struct PiecewiseSurface::Scratch {
  std::vector<uint64_t> order, by_leaf;  // leaf << 32 | row in the chunk
  std::vector<uint32_t> start;           // counting sort by leaf
  std::vector<uint32_t> position_of;     // row in the chunk -> place in order
  std::vector<double> sorted, results;   // directions, results in order
};

struct PiecewiseSurface::Leaf {
  Eigen::Vector3d origin, e1, e2;  // local chart o + s e1 + t e2
  std::vector<int> lines;          // indices into segments_, ascending
  // Per line: t_a x t_b, then twice PerturbedDetSign's filter (beyond it the
  // float sign is the exact one; within it PerturbedDetSign decides).
  std::vector<double> planes;
  std::vector<int> sets;  // basis functions meeting the cell
  bool slow = false;      // too many lines: use the spline
  mutable std::atomic<const Table*> table{nullptr};
  mutable std::mutex mutex;
  mutable std::unique_ptr<Builder> builder;
};

PiecewiseSurface::PiecewiseSurface(const SphericalSpline& spline, int grid)
    : spline_(spline) {
  const DcbBasis& basis = spline.basis();
  const Eigen::MatrixX3d& knots = spline.knots();
  size_ = PolynomialSize(spline.degree());
  for (int i = 0; i < basis.size(); ++i) {
    const auto& k = basis.configuration_set(i).knots;
    for (size_t a = 0; a < k.size(); ++a)
      for (size_t b = a + 1; b < k.size(); ++b) {
        segments_.push_back({std::min(k[a], k[b]), std::max(k[a], k[b])});
      }
  }
  std::sort(segments_.begin(), segments_.end());
  segments_.erase(std::unique(segments_.begin(), segments_.end()),
                  segments_.end());
  const int ns = static_cast<int>(segments_.size());
  // Each segment's bounding cap: its midpoint and half its length.
  std::vector<Eigen::Vector3d> mid(ns), normal(ns);
  std::vector<double> half(ns), cos_half(ns), sin_half(ns);
  double length = 0.0;
  for (int s = 0; s < ns; ++s) {
    const Eigen::Vector3d a = knots.row(segments_[s][0]).transpose();
    const Eigen::Vector3d b = knots.row(segments_[s][1]).transpose();
    mid[s] = (a + b).normalized();
    half[s] = 0.5 * Angle(a, b);
    cos_half[s] = std::cos(half[s]);
    sin_half[s] = std::sin(half[s]);
    normal[s] = a.cross(b);
    length += 2.0 * half[s];
  }
  // Expected crossings of a cell of side ~(pi / 2) / G: L (pi / 2) / (G pi^2).
  grid_ =
      grid > 0
          ? grid
          : std::clamp(static_cast<int>(std::ceil(length / (2.0 * kPi * 10.0))),
                       2, 96);
  const int g = grid_;
  const int nb = basis.size();
  std::vector<Eigen::Vector3d> set_axis(nb);
  std::vector<double> set_radius(nb), set_cos(nb), set_sin(nb);
  for (int i = 0; i < nb; ++i) {
    const double c = basis.support_cap(i).cos_radius;
    set_radius[i] = c <= -1.0 ? kPi : std::acos(std::min(1.0, c));
    set_cos[i] = std::cos(set_radius[i]);
    set_sin[i] = std::sin(set_radius[i]);
    set_axis[i] = basis.support_cap(i).axis.normalized();
  }

  // One root cell's quadtree: nodes (the root first; children indices
  // local) and leaves in depth-first order.
  struct Subtree {
    std::vector<Node> nodes;
    std::vector<std::unique_ptr<Leaf>> leaves;
  };
  struct Candidates {
    std::vector<int> lines, sets;
  };
  // Fills nodes[index] (face f, centre (uc, vc), half side h) from the
  // candidate segments and basis functions of its parent.
  auto build = [&](auto& self, Subtree& tree, int index, int f, double uc,
                   double vc, double h, const Candidates& parent,
                   int depth) -> void {
    Eigen::Vector3d a, e1, e2;
    FaceFrame(f, &a, &e1, &e2);
    const Eigen::Vector3d origin = a + uc * e1 + vc * e2;
    const Eigen::Vector3d center = origin.normalized();
    Eigen::Vector3d corner[4];
    double radius = 0.0;
    for (int c = 0; c < 4; ++c) {
      corner[c] = a + (uc + h * ((c & 1) ? 1 : -1)) * e1 +
                  (vc + h * ((c >> 1) ? 1 : -1)) * e2;
      radius = std::max(radius, Angle(center, corner[c]));
    }
    radius += 1e-9;
    const double cos_r = std::cos(radius), sin_r = std::sin(radius);
    Candidates mine;
    for (int s : parent.lines) {
      if (!CapsMayMeet(center, cos_r, sin_r, radius, mid[s], cos_half[s],
                       sin_half[s], half[s])) {
        continue;
      }
      // The great circle misses the (gnomonically convex) cell if all
      // four corners lie strictly on one side.
      int pos = 0, neg = 0;
      for (const Eigen::Vector3d& x : corner) {
        const double d = x.dot(normal[s]);
        const double margin = 1e-12 * x.norm() * normal[s].norm();
        pos += d > margin;
        neg += d < -margin;
      }
      if (pos == 4 || neg == 4) continue;
      mine.lines.push_back(s);
    }
    for (int b : parent.sets) {
      if (CapsMayMeet(center, cos_r, sin_r, radius, set_axis[b], set_cos[b],
                      set_sin[b], set_radius[b])) {
        mine.sets.push_back(b);
      }
    }
    tree.nodes[index].uc = uc;
    tree.nodes[index].vc = vc;
    tree.nodes[index].h = h;
    if (mine.lines.size() > kSplitLines && depth < kMaxDepth) {
      const int first = static_cast<int>(tree.nodes.size());
      tree.nodes[index].child = first;
      tree.nodes.resize(first + 4);
      for (int q = 0; q < 4; ++q) {
        self(self, tree, first + q, f, uc + 0.5 * h * ((q & 1) ? 1 : -1),
             vc + 0.5 * h * ((q >> 1) ? 1 : -1), 0.5 * h, mine, depth + 1);
      }
      return;
    }
    auto leaf = std::make_unique<Leaf>();
    leaf->origin = origin;
    leaf->e1 = h * e1;
    leaf->e2 = h * e2;
    leaf->slow = mine.lines.size() > kMaxLines;
    for (int s : mine.lines) {
      const Eigen::Vector3d ka = knots.row(segments_[s][0]).transpose();
      const Eigen::Vector3d kb = knots.row(segments_[s][1]).transpose();
      const Eigen::Vector3d n = ka.cross(kb);
      leaf->planes.insert(leaf->planes.end(),
                          {n[0], n[1], n[2],
                           2e-13 * ka.cwiseAbs().sum() * kb.cwiseAbs().sum()});
    }
    leaf->lines = std::move(mine.lines);
    leaf->sets = std::move(mine.sets);
    tree.nodes[index].leaf = static_cast<int>(tree.leaves.size());
    tree.leaves.push_back(std::move(leaf));
  };
  Candidates all;
  all.lines.resize(ns);
  all.sets.resize(nb);
  for (int s = 0; s < ns; ++s) all.lines[s] = s;
  for (int b = 0; b < nb; ++b) all.sets[b] = b;
  const int roots = 6 * g * g;
  std::vector<Subtree> trees(roots);
  tbb::parallel_for(0, roots, [&](int index) {
    const int f = index / (g * g), i = (index / g) % g, j = index % g;
    const double h = 1.0 / g;
    trees[index].nodes.resize(1);
    build(build, trees[index], 0, f, -1.0 + h * (2 * i + 1),
          -1.0 + h * (2 * j + 1), h, all, 0);
  });
  // Roots first, then each root's other nodes; leaves root by root.
  nodes_.resize(roots);
  for (int r = 0; r < roots; ++r) {
    const int node_offset = static_cast<int>(nodes_.size()) - 1;
    const int leaf_offset = static_cast<int>(leaves_.size());
    for (size_t n = 0; n < trees[r].nodes.size(); ++n) {
      Node node = trees[r].nodes[n];
      if (node.child >= 0) node.child += node_offset;
      if (node.leaf >= 0) node.leaf += leaf_offset;
      if (n == 0) {
        nodes_[r] = node;
      } else {
        nodes_.push_back(node);
      }
    }
    for (auto& leaf : trees[r].leaves) leaves_.push_back(std::move(leaf));
  }
}

PiecewiseSurface::~PiecewiseSurface() = default;

int64_t PiecewiseSurface::num_regions() const {
  int64_t n = 0;
  for (const auto& leaf : leaves_) {
    const Table* table = leaf->table.load(std::memory_order_acquire);
    if (table == nullptr) continue;
    std::lock_guard<std::mutex> lock(leaf->mutex);
    n += leaf->builder->tables.back()->count;
  }
  return n;
}

int PiecewiseSurface::Locate(const Eigen::Vector3d& p, double* s,
                             double* t) const {
  // The face of the largest |coordinate| (the first on ties).
  int k = 0;
  double largest = std::abs(p[0]);
  for (int c = 1; c < 3; ++c) {
    if (std::abs(p[c]) > largest) {
      largest = std::abs(p[c]);
      k = c;
    }
  }
  const int f = 2 * k + (p[k] < 0 ? 1 : 0);
  const Face& face = kFaces[f];
  const double w = face.sign * p[k];
  const double u = p[face.i1] / w, v = p[face.i2] / w;
  const int g = grid_;
  const int i =
      std::clamp(static_cast<int>(std::floor((u + 1.0) * 0.5 * g)), 0, g - 1);
  const int j =
      std::clamp(static_cast<int>(std::floor((v + 1.0) * 0.5 * g)), 0, g - 1);
  const Node* node = &nodes_[(f * g + i) * g + j];
  while (node->child >= 0) {
    node = &nodes_[node->child + (u >= node->uc ? 1 : 0) +
                   (v >= node->vc ? 2 : 0)];
  }
  *s = (u - node->uc) / node->h;
  *t = (v - node->vc) / node->h;
  return node->leaf;
}

const double* PiecewiseSurface::Region(const Leaf& leaf,
                                       const Eigen::Vector3d& p) const {
  // The float signs, and which of them are within the filter.
  uint64_t key = 0, unsure = 0;
  const double p1 = std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2]);
  const int n = static_cast<int>(leaf.lines.size());
  const double* plane = leaf.planes.data();
  for (int l = 0; l < n; ++l, plane += 4) {
    const double v = p[0] * plane[0] + p[1] * plane[1] + p[2] * plane[2];
    key |= static_cast<uint64_t>(v > 0) << l;
    unsure |= static_cast<uint64_t>(std::abs(v) <= plane[3] * p1) << l;
  }
  while (unsure != 0) {
    const int l = __builtin_ctzll(unsure);
    unsure &= unsure - 1;
    const auto& seg = segments_[leaf.lines[l]];
    const Eigen::MatrixX3d& knots = spline_.knots();
    const bool positive = PerturbedDetSign(p, knots.row(seg[0]).transpose(),
                                           knots.row(seg[1]).transpose()) > 0;
    key = (key & ~(uint64_t{1} << l)) | (static_cast<uint64_t>(positive) << l);
  }
  const Table* table = leaf.table.load(std::memory_order_acquire);
  if (table != nullptr) {
    if (const double* found = table->Find(key)) return found;
  }
  return BuildRegion(leaf, p, key);
}

const double* PiecewiseSurface::BuildRegion(const Leaf& leaf,
                                            const Eigen::Vector3d& p,
                                            uint64_t key) const {
  std::lock_guard<std::mutex> lock(leaf.mutex);
  const DcbBasis& basis = spline_.basis();
  if (!leaf.builder) {
    auto builder = std::make_unique<Builder>();
    builder->set_start.push_back(0);
    for (int b : leaf.sets) {
      const auto& k = basis.configuration_set(b).knots;
      for (size_t x = 0; x < k.size(); ++x)
        for (size_t y = x + 1; y < k.size(); ++y) {
          const std::array<int, 2> pair = {std::min(k[x], k[y]),
                                           std::max(k[x], k[y])};
          const int s = static_cast<int>(
              std::lower_bound(segments_.begin(), segments_.end(), pair) -
              segments_.begin());
          const auto it =
              std::lower_bound(leaf.lines.begin(), leaf.lines.end(), s);
          if (it != leaf.lines.end() && *it == s) {
            builder->set_lines.push_back(
                static_cast<int>(it - leaf.lines.begin()));
          }
        }
      builder->set_start.push_back(static_cast<int>(builder->set_lines.size()));
    }
    builder->pieces.resize(leaf.sets.size());
    builder->tables.push_back(std::make_unique<Table>(4));
    leaf.builder = std::move(builder);
  }
  Builder& builder = *leaf.builder;
  Table* table = builder.tables.back().get();
  if (const double* found = table->Find(key)) return found;

  // N = sum B_i c_i and I = sum B_i on p's region. B_i's piece depends only
  // on p's signs against B_i's own segments (those that do not cross the
  // cell do not change B_i's degree-0 leaves in it), so it is built once per
  // sign pattern and does not depend on which point of the region built it.
  const int size = size_;
  thread_local std::vector<double> poly;
  poly.assign(4 * size, 0.0);
  for (size_t j = 0; j < leaf.sets.size(); ++j) {
    uint32_t signs = 0;
    for (int x = builder.set_start[j]; x < builder.set_start[j + 1]; ++x) {
      signs |= static_cast<uint32_t>((key >> builder.set_lines[x]) & 1)
               << (x - builder.set_start[j]);
    }
    const int b = leaf.sets[j];
    auto& known = builder.pieces[j];
    auto it = std::find_if(known.begin(), known.end(),
                           [&](const auto& e) { return e.first == signs; });
    if (it == known.end()) {
      const size_t offset = builder.piece_data.size();
      builder.piece_data.resize(offset + size, 0.0);
      const bool any =
          basis.AddPiecePolynomial(b, p, leaf.origin, leaf.e1, leaf.e2,
                                   builder.piece_data.data() + offset);
      if (!any) builder.piece_data.resize(offset);
      known.emplace_back(signs, any ? static_cast<int>(offset) : -1);
      it = known.end() - 1;
    }
    if (it->second < 0) continue;
    const double* piece = builder.piece_data.data() + it->second;
    const Eigen::RowVector3d c = spline_.control_points().row(b);
    for (int m = 0; m < size; ++m) {
      for (int d = 0; d < 3; ++d) poly[d * size + m] += c[d] * piece[m];
      poly[3 * size + m] += piece[m];
    }
  }
  if (builder.block_used == builder.block_capacity) {
    builder.block_capacity = std::max<int>(2, table->count);
    builder.blocks.emplace_back(new double[builder.block_capacity * 4 * size]);
    builder.block_used = 0;
  }
  double* coefficients =
      builder.blocks.back().get() + 4 * size * builder.block_used++;
  for (int m = 0; m < size; ++m)
    for (int d = 0; d < 4; ++d) coefficients[4 * m + d] = poly[d * size + m];
  if (2 * (table->count + 1) > static_cast<int64_t>(table->mask + 1)) {
    // Grow: a new table, filled before it is published.
    auto larger = std::make_unique<Table>(64 - table->shift + 1);
    for (uint64_t i = 0; i <= table->mask; ++i) {
      const double* v = table->slots[i].value.load(std::memory_order_relaxed);
      if (v != nullptr) {
        larger->Insert(table->slots[i].key.load(std::memory_order_relaxed), v);
      }
    }
    builder.tables.push_back(std::move(larger));
    table = builder.tables.back().get();
  }
  table->Insert(key, coefficients);
  leaf.table.store(table, std::memory_order_release);
  return coefficients;
}

template <int K>
void PiecewiseSurface::EvalDegree(const Eigen::Vector3d& p,
                                  Eigen::Vector3d* position,
                                  Eigen::Vector3d* normal) const {
  double s, t;
  const Leaf& leaf = *leaves_[Locate(p, &s, &t)];
  if (leaf.slow) {
    // The same position with or without the normal.
    *position = spline_.Evaluate(p.normalized());
    if (normal != nullptr) {
      *normal =
          spline_.EvaluateDifferential(p.normalized(), JetOrder::kGradient)
              .normal;
    }
    return;
  }
  const double* c = Region(leaf, p);
  constexpr int kSize = PolynomialSize(K);
  double sp[K + 1], tp[K + 1];
  sp[0] = tp[0] = 1.0;
  for (int e = 1; e <= K; ++e) {
    sp[e] = sp[e - 1] * s;
    tp[e] = tp[e - 1] * t;
  }
  double mono[kSize];
  for (int n = 0; n <= K; ++n)
    for (int j = 0; j <= n; ++j)
      mono[MonomialIndex(n - j, j)] = sp[n - j] * tp[j];
  double v[4] = {0, 0, 0, 0}, vs[4] = {0, 0, 0, 0}, vt[4] = {0, 0, 0, 0};
  for (int m = 0; m < kSize; ++m)
    for (int d = 0; d < 4; ++d) v[d] += c[4 * m + d] * mono[m];
  if (normal != nullptr) {
    double ds[kSize], dt[kSize];
    for (int n = 0; n <= K; ++n)
      for (int j = 0; j <= n; ++j) {
        const int i = n - j, m = MonomialIndex(i, j);
        ds[m] = i > 0 ? i * sp[i - 1] * tp[j] : 0.0;
        dt[m] = j > 0 ? j * sp[i] * tp[j - 1] : 0.0;
      }
    for (int m = 0; m < kSize; ++m)
      for (int d = 0; d < 4; ++d) {
        vs[d] += c[4 * m + d] * ds[m];
        vt[d] += c[4 * m + d] * dt[m];
      }
  }
  if (spline_.basis_form() == BasisForm::kRaw) {
    // F = N / |x|^k (the raw basis extended homogeneously of degree 0) at
    // the point x of the cell's plane, with its derivatives in s and t.
    const Eigen::Vector3d x = leaf.origin + s * leaf.e1 + t * leaf.e2;
    const double r2 = x.squaredNorm();
    const double rk = std::pow(r2, 0.5 * K);
    v[3] = rk;
    vs[3] = K * rk / r2 * x.dot(leaf.e1);
    vt[3] = K * rk / r2 * x.dot(leaf.e2);
  }
  const double inv = 1.0 / v[3];
  *position = Eigen::Vector3d(v[0], v[1], v[2]) * inv;
  if (normal == nullptr) return;
  Eigen::Vector3d fs, ft;
  for (int d = 0; d < 3; ++d) {
    fs[d] = (vs[d] - (*position)[d] * vs[3]) * inv;
    ft[d] = (vt[d] - (*position)[d] * vt[3]) * inv;
  }
  const Eigen::Vector3d cross = fs.cross(ft);
  const double len = cross.norm();
  *normal = len > 0 ? Eigen::Vector3d(cross / len) : Eigen::Vector3d::Zero();
}

void PiecewiseSurface::Eval(const Eigen::Vector3d& p, Eigen::Vector3d* position,
                            Eigen::Vector3d* normal) const {
  switch (spline_.degree()) {
    case 0:
      return EvalDegree<0>(p, position, normal);
    case 1:
      return EvalDegree<1>(p, position, normal);
    case 2:
      return EvalDegree<2>(p, position, normal);
    case 3:
      return EvalDegree<3>(p, position, normal);
    case 4:
      return EvalDegree<4>(p, position, normal);
    default:
      return EvalDegree<5>(p, position, normal);
  }
}

Eigen::Vector3d PiecewiseSurface::Evaluate(const Eigen::Vector3d& p) const {
  Eigen::Vector3d position;
  Eval(p, &position, nullptr);
  return position;
}

void PiecewiseSurface::EvaluateWithNormal(const Eigen::Vector3d& p,
                                          Eigen::Vector3d* position,
                                          Eigen::Vector3d* normal) const {
  Eval(p, position, normal);
}

void PiecewiseSurface::EvaluateMany(const Eigen::MatrixX3d& directions,
                                    Eigen::MatrixX3d* positions,
                                    Eigen::MatrixX3d* normals) const {
  const Eigen::Index rows = directions.rows();
  positions->resize(rows, 3);
  if (normals) normals->resize(rows, 3);
  const auto parallel = [](Eigen::Index n, Eigen::Index grain,
                           const auto& body) {
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, grain),
                      [&](const tbb::blocked_range<Eigen::Index>& range) {
                        for (Eigen::Index r = range.begin(); r < range.end();
                             ++r) {
                          body(r);
                        }
                      });
  };
  const auto evaluate_row = [&](Eigen::Index r) {
    Eigen::Vector3d x, n;
    Eval(directions.row(r).transpose(), &x, normals ? &n : nullptr);
    positions->row(r) = x.transpose();
    if (normals) normals->row(r) = n.transpose();
  };
  if (rows < 64) {
    for (Eigen::Index r = 0; r < rows; ++r) evaluate_row(r);
    return;
  }
  // In chunks of up to kChunk rows, leaf by leaf (stable), so that a leaf's
  // regions stay in cache: the chunk's directions are copied to that order
  // (x, y, z together), the results written in it and copied back. The
  // buffers are reused from call to call (fresh pages cost more than the
  // evaluation of a small batch).
  std::unique_ptr<Scratch> scratch;
  {
    std::lock_guard<std::mutex> lock(scratch_mutex_);
    if (!scratch_.empty()) {
      scratch = std::move(scratch_.back());
      scratch_.pop_back();
    }
  }
  if (!scratch) scratch = std::make_unique<Scratch>();
  const int width = normals ? 6 : 3;
  std::vector<uint64_t>& order = scratch->order;
  std::vector<uint32_t>& position_of = scratch->position_of;
  std::vector<double>& sorted = scratch->sorted;
  std::vector<double>& results = scratch->results;
  for (Eigen::Index begin = 0; begin < rows; begin += kChunk) {
    const Eigen::Index n = std::min(kChunk, rows - begin);
    if (static_cast<Eigen::Index>(order.size()) < n) {
      order.resize(n);
      position_of.resize(n);
      sorted.resize(3 * n);
    }
    if (static_cast<Eigen::Index>(results.size()) < width * n) {
      results.resize(width * n);
    }
    parallel(n, 4096, [&](Eigen::Index r) {
      double s, t;
      const int leaf = Locate(directions.row(begin + r).transpose(), &s, &t);
      order[r] = static_cast<uint64_t>(leaf) << 32 | static_cast<uint64_t>(r);
    });
    if (n < static_cast<Eigen::Index>(leaves_.size())) {
      std::sort(order.begin(), order.begin() + n);
    } else {
      // Counting sort by leaf (n >= #leaves: linear).
      std::vector<uint32_t>& start = scratch->start;
      std::vector<uint64_t>& by_leaf = scratch->by_leaf;
      start.assign(leaves_.size() + 1, 0);
      for (Eigen::Index r = 0; r < n; ++r) ++start[(order[r] >> 32) + 1];
      for (size_t l = 0; l < leaves_.size(); ++l) start[l + 1] += start[l];
      by_leaf.resize(order.size());
      for (Eigen::Index r = 0; r < n; ++r) {
        by_leaf[start[order[r] >> 32]++] = order[r];
      }
      order.swap(by_leaf);
    }
    parallel(n, 4096, [&](Eigen::Index o) {
      const uint32_t r = static_cast<uint32_t>(order[o]);
      position_of[r] = static_cast<uint32_t>(o);
      for (int d = 0; d < 3; ++d) sorted[3 * o + d] = directions(begin + r, d);
    });
    parallel(n, 256, [&](Eigen::Index o) {
      Eigen::Vector3d x, nrm;
      Eval(Eigen::Vector3d(sorted[3 * o], sorted[3 * o + 1], sorted[3 * o + 2]),
           &x, normals ? &nrm : nullptr);
      double* out = &results[width * o];
      for (int d = 0; d < 3; ++d) out[d] = x[d];
      if (normals) {
        for (int d = 0; d < 3; ++d) out[3 + d] = nrm[d];
      }
    });
    // Back to row order: sequential writes, one gathered read per row.
    parallel(n, 4096, [&](Eigen::Index r) {
      const double* in = &results[width * Eigen::Index{position_of[r]}];
      for (int d = 0; d < 3; ++d) (*positions)(begin + r, d) = in[d];
      if (normals) {
        for (int d = 0; d < 3; ++d) (*normals)(begin + r, d) = in[3 + d];
      }
    });
  }
  std::lock_guard<std::mutex> lock(scratch_mutex_);
  scratch_.push_back(std::move(scratch));
}

}  // namespace sdcb
