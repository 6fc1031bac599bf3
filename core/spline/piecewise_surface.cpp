#include "sdcb/core/spline/piecewise_surface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/spline/piecewise_surface_cells.h"
#include "sdcb/core/spline/simplex_spline.h"

namespace sdcb {
namespace {

constexpr int kMaxLines = 64;    // bits of a region key
constexpr int kSplitLines = 40;  // cells with more lines are split
constexpr int kMaxDepth = 8;

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

}  // namespace

// The knot segments' and basis functions' bounding caps, and the quadtrees
// of the root cells built from them (for the constructor).
class PiecewiseSurface::CellBuilder {
 public:
  // One root cell's quadtree: nodes (the root first; children indices
  // local) and leaves in depth-first order.
  struct Subtree {
    std::vector<Node> nodes;
    std::vector<std::unique_ptr<Leaf>> leaves;
  };

  // The caps of surface.segments_ and of the support of each basis
  // function of `basis`.
  CellBuilder(const PiecewiseSurface& surface, const DcbBasis& basis,
              const Eigen::MatrixX3d& knots);
  // The total length of the knot segments (radians).
  double length() const { return length_; }
  // The quadtree of each of the 6 g^2 root cells, (f * g + i) * g + j for
  // cell (i, j) of face f.
  std::vector<Subtree> BuildRoots(int g) const;

 private:
  struct Candidates {
    std::vector<int> lines, sets;
  };
  // Fills tree.nodes[index] (face f, centre (uc, vc), half side h) from the
  // candidate segments and basis functions of its parent.
  void Build(Subtree& tree, int index, int f, double uc, double vc, double h,
             const Candidates& parent, int depth) const;
  // The leaf of a cell (face frame a, e1, e2; centre `origin`, half side h)
  // crossed by the segments `mine.lines`, met by the supports `mine.sets`.
  std::unique_ptr<Leaf> MakeLeaf(const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& e1,
                                 const Eigen::Vector3d& e2,
                                 const Eigen::Vector3d& origin, double h,
                                 Candidates mine) const;
  // The candidates of a group of root cells: those of `parent` whose caps
  // may meet the cap (axis, radius) that holds every cell's cap. A cell's
  // cap test passing implies the group's (triangle inequality; the 1e-4 rad
  // slack exceeds the test's own slack and rounding), so each cell filters
  // the same candidates from the group's as it would from all of them.
  Candidates Filter(const Eigen::Vector3d& axis, double radius,
                    const Candidates& parent) const;
  // The cap of the root cells [i0, i1) x [j0, j1) of face f (half side h):
  // centred at the block's centre, holding each cell's bounding cap (as
  // Build makes it).
  void BlockCap(int f, int i0, int i1, int j0, int j1, double h,
                Eigen::Vector3d* axis, double* radius) const;

  const std::vector<std::array<int, 2>>& segments_;
  const Eigen::MatrixX3d& knots_;
  int nb_ = 0;
  // Each segment's bounding cap (its midpoint and half its length) and the
  // normal of its great circle.
  std::vector<Eigen::Vector3d> mid_, normal_;
  std::vector<double> half_, cos_half_, sin_half_;
  double length_ = 0.0;
  // Each basis function's support cap.
  std::vector<Eigen::Vector3d> set_axis_;
  std::vector<double> set_radius_, set_cos_, set_sin_;
};

PiecewiseSurface::CellBuilder::CellBuilder(const PiecewiseSurface& surface,
                                           const DcbBasis& basis,
                                           const Eigen::MatrixX3d& knots)
    : segments_(surface.segments_), knots_(knots), nb_(basis.size()) {
  const int ns = static_cast<int>(segments_.size());
  mid_.resize(ns);
  normal_.resize(ns);
  half_.resize(ns);
  cos_half_.resize(ns);
  sin_half_.resize(ns);
  for (int s = 0; s < ns; ++s) {
    const Eigen::Vector3d a = knots.row(segments_[s][0]).transpose();
    const Eigen::Vector3d b = knots.row(segments_[s][1]).transpose();
    mid_[s] = (a + b).normalized();
    half_[s] = 0.5 * Angle(a, b);
    cos_half_[s] = std::cos(half_[s]);
    sin_half_[s] = std::sin(half_[s]);
    normal_[s] = a.cross(b);
    length_ += 2.0 * half_[s];
  }
  set_axis_.resize(nb_);
  set_radius_.resize(nb_);
  set_cos_.resize(nb_);
  set_sin_.resize(nb_);
  for (int i = 0; i < nb_; ++i) {
    const double c = basis.support_cap(i).cos_radius;
    set_radius_[i] = c <= -1.0 ? kPi : std::acos(std::min(1.0, c));
    set_cos_[i] = std::cos(set_radius_[i]);
    set_sin_[i] = std::sin(set_radius_[i]);
    set_axis_[i] = basis.support_cap(i).axis.normalized();
  }
}

void PiecewiseSurface::CellBuilder::Build(Subtree& tree, int index, int f,
                                          double uc, double vc, double h,
                                          const Candidates& parent,
                                          int depth) const {
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
    if (!CapsMayMeet(center, cos_r, sin_r, radius, mid_[s], cos_half_[s],
                     sin_half_[s], half_[s])) {
      continue;
    }
    // The great circle misses the (gnomonically convex) cell if all four
    // corners lie strictly on one side.
    int pos = 0, neg = 0;
    for (const Eigen::Vector3d& x : corner) {
      const double d = x.dot(normal_[s]);
      const double margin = 1e-12 * x.norm() * normal_[s].norm();
      pos += d > margin;
      neg += d < -margin;
    }
    if (pos == 4 || neg == 4) continue;
    mine.lines.push_back(s);
  }
  for (int b : parent.sets) {
    if (CapsMayMeet(center, cos_r, sin_r, radius, set_axis_[b], set_cos_[b],
                    set_sin_[b], set_radius_[b])) {
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
      Build(tree, first + q, f, uc + 0.5 * h * ((q & 1) ? 1 : -1),
            vc + 0.5 * h * ((q >> 1) ? 1 : -1), 0.5 * h, mine, depth + 1);
    }
    return;
  }
  tree.nodes[index].leaf = static_cast<int>(tree.leaves.size());
  tree.leaves.push_back(MakeLeaf(a, e1, e2, origin, h, std::move(mine)));
}

std::unique_ptr<PiecewiseSurface::Leaf> PiecewiseSurface::CellBuilder::MakeLeaf(
    const Eigen::Vector3d& a, const Eigen::Vector3d& e1,
    const Eigen::Vector3d& e2, const Eigen::Vector3d& origin, double h,
    Candidates mine) const {
  auto leaf = std::make_unique<Leaf>();
  leaf->origin = origin;
  leaf->axis = a;
  leaf->e1 = h * e1;
  leaf->e2 = h * e2;
  leaf->slow = mine.lines.size() > kMaxLines;
  for (int s : mine.lines) {
    const Eigen::Vector3d ka = knots_.row(segments_[s][0]).transpose();
    const Eigen::Vector3d kb = knots_.row(segments_[s][1]).transpose();
    const Eigen::Vector3d n = ka.cross(kb);
    leaf->planes.insert(
        leaf->planes.end(),
        {n[0], n[1], n[2], 2e-13 * ka.cwiseAbs().sum() * kb.cwiseAbs().sum()});
  }
  leaf->lines = std::move(mine.lines);
  leaf->sets = std::move(mine.sets);
  return leaf;
}

PiecewiseSurface::CellBuilder::Candidates PiecewiseSurface::CellBuilder::Filter(
    const Eigen::Vector3d& axis, double radius,
    const Candidates& parent) const {
  const double cos_r = std::cos(radius), sin_r = std::sin(radius);
  Candidates mine;
  for (int s : parent.lines) {
    if (CapsMayMeet(axis, cos_r, sin_r, radius, mid_[s], cos_half_[s],
                    sin_half_[s], half_[s])) {
      mine.lines.push_back(s);
    }
  }
  for (int b : parent.sets) {
    if (CapsMayMeet(axis, cos_r, sin_r, radius, set_axis_[b], set_cos_[b],
                    set_sin_[b], set_radius_[b])) {
      mine.sets.push_back(b);
    }
  }
  return mine;
}

void PiecewiseSurface::CellBuilder::BlockCap(int f, int i0, int i1, int j0,
                                             int j1, double h,
                                             Eigen::Vector3d* axis,
                                             double* radius) const {
  Eigen::Vector3d a, e1, e2;
  FaceFrame(f, &a, &e1, &e2);
  *axis = (a + (-1.0 + h * (i0 + i1)) * e1 + (-1.0 + h * (j0 + j1)) * e2)
              .normalized();
  *radius = 0.0;
  for (int i = i0; i < i1; ++i)
    for (int j = j0; j < j1; ++j) {
      const double uc = -1.0 + h * (2 * i + 1), vc = -1.0 + h * (2 * j + 1);
      const Eigen::Vector3d center = (a + uc * e1 + vc * e2).normalized();
      double cell = 0.0;
      for (int c = 0; c < 4; ++c) {
        const Eigen::Vector3d corner = a + (uc + h * ((c & 1) ? 1 : -1)) * e1 +
                                       (vc + h * ((c >> 1) ? 1 : -1)) * e2;
        cell = std::max(cell, Angle(center, corner));
      }
      *radius = std::max(*radius, Angle(*axis, center) + cell + 1e-9);
    }
  *radius += 1e-4;
}

std::vector<PiecewiseSurface::CellBuilder::Subtree>
PiecewiseSurface::CellBuilder::BuildRoots(int g) const {
  const int ns = static_cast<int>(segments_.size());
  const double h = 1.0 / g;
  Candidates all;
  all.lines.resize(ns);
  all.sets.resize(nb_);
  for (int s = 0; s < ns; ++s) all.lines[s] = s;
  for (int b = 0; b < nb_; ++b) all.sets[b] = b;
  std::vector<Candidates> face_candidates(6);
  tbb::parallel_for(0, 6, [&](int f) {
    Eigen::Vector3d axis;
    double radius = 0.0;
    BlockCap(f, 0, g, 0, g, h, &axis, &radius);
    face_candidates[f] = Filter(axis, radius, all);
  });
  // Blocks of up to kBlock x kBlock root cells, each filtered from its face.
  constexpr int kBlock = 4;
  const int blocks = (g + kBlock - 1) / kBlock;
  std::vector<Subtree> trees(6 * g * g);
  tbb::parallel_for(0, 6 * blocks * blocks, [&](int index) {
    const int f = index / (blocks * blocks);
    const int i0 = (index / blocks) % blocks * kBlock;
    const int j0 = index % blocks * kBlock;
    const int i1 = std::min(g, i0 + kBlock), j1 = std::min(g, j0 + kBlock);
    Eigen::Vector3d axis;
    double radius = 0.0;
    BlockCap(f, i0, i1, j0, j1, h, &axis, &radius);
    const Candidates block = Filter(axis, radius, face_candidates[f]);
    for (int i = i0; i < i1; ++i)
      for (int j = j0; j < j1; ++j) {
        Subtree& tree = trees[(f * g + i) * g + j];
        tree.nodes.resize(1);
        Build(tree, 0, f, -1.0 + h * (2 * i + 1), -1.0 + h * (2 * j + 1), h,
              block, 0);
      }
  });
  return trees;
}

PiecewiseSurface::PiecewiseSurface(const SphericalSpline& spline, int grid)
    : spline_(spline) {
  size_ = PolynomialSize(spline.degree());
  CollectSegments();
  const CellBuilder cells(*this, spline.basis(), spline.knots());
  // Expected crossings of a cell of side ~(pi / 2) / G: L (pi / 2) / (G pi^2).
  grid_ = grid > 0 ? grid
                   : std::clamp(static_cast<int>(std::ceil(cells.length() /
                                                           (2.0 * kPi * 10.0))),
                                2, 96);
  std::vector<CellBuilder::Subtree> trees = cells.BuildRoots(grid_);
  // Roots first, then each root's other nodes; leaves root by root.
  const int roots = static_cast<int>(trees.size());
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

// segments_ (the knot pairs of every configuration set, ascending, once) and
// each basis function's segments (set_segment_start_, set_segments_).
void PiecewiseSurface::CollectSegments() {
  const DcbBasis& basis = spline_.basis();
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
  set_segment_start_.push_back(0);
  for (int i = 0; i < basis.size(); ++i) {
    const auto& k = basis.configuration_set(i).knots;
    for (size_t a = 0; a < k.size(); ++a)
      for (size_t b = a + 1; b < k.size(); ++b) {
        const std::array<int, 2> pair = {std::min(k[a], k[b]),
                                         std::max(k[a], k[b])};
        set_segments_.push_back(static_cast<int>(
            std::lower_bound(segments_.begin(), segments_.end(), pair) -
            segments_.begin()));
      }
    set_segment_start_.push_back(static_cast<int>(set_segments_.size()));
  }
}

PiecewiseSurface::~PiecewiseSurface() = default;

int64_t PiecewiseSurface::num_regions() const {
  int64_t n = 0;
  for (const auto& leaf : leaves_) {
    const Table* table = leaf->table.load(std::memory_order_acquire);
    if (table == nullptr) continue;
    std::lock_guard<std::mutex> lock(leaf->mutex);
    n += table->count;
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
  if (leaf.ill_conditioned.load(std::memory_order_acquire)) return nullptr;
  return BuildRegion(leaf, p, key);
}

const double* PiecewiseSurface::BuildRegion(const Leaf& leaf,
                                            const Eigen::Vector3d& p,
                                            uint64_t key) const {
  std::lock_guard<std::mutex> lock(leaf.mutex);
  if (!leaf.builder) {
    // Each set's lines: the bits of its segments among the leaf's lines.
    thread_local std::vector<int> bit_of;  // segment -> bit, or -1
    bit_of.resize(segments_.size(), -1);
    for (size_t l = 0; l < leaf.lines.size(); ++l) {
      bit_of[leaf.lines[l]] = static_cast<int>(l);
    }
    const int m = spline_.degree() + 3;
    std::vector<int8_t> pair_bits;
    pair_bits.reserve(leaf.sets.size() * (m * (m - 1) / 2));
    for (int b : leaf.sets) {
      for (int x = set_segment_start_[b]; x < set_segment_start_[b + 1]; ++x) {
        pair_bits.push_back(static_cast<int8_t>(bit_of[set_segments_[x]]));
      }
    }
    for (int line : leaf.lines) bit_of[line] = -1;
    leaf.builder = std::make_unique<PiecewiseRegionBuilder>(
        spline_, leaf.origin, leaf.e1, leaf.e2, leaf.sets, pair_bits, p,
        &arena_);
  }
  Table* table = leaf.table.load(std::memory_order_relaxed);
  if (table == nullptr) {
    table = Table::Make(4, &arena_);
  } else if (const double* found = table->Find(key)) {
    return found;  // built since this thread looked
  }
  if (leaf.ill_conditioned.load(std::memory_order_relaxed)) return nullptr;
  thread_local std::vector<double> built;
  built.resize(4 * size_);
  if (!leaf.builder->Build(p, key, built.data())) {
    leaf.ill_conditioned.store(true, std::memory_order_release);
    return nullptr;
  }
  double* coefficients =
      static_cast<double*>(arena_.Allocate(4 * size_ * sizeof(double)));
  std::copy(built.begin(), built.end(), coefficients);
  if (2 * (table->count + 1) > static_cast<int64_t>(table->mask + 1)) {
    // Grow: a new table, filled before it is published.
    Table* larger = Table::Make(64 - table->shift + 1, &arena_);
    for (uint64_t i = 0; i <= table->mask; ++i) {
      const double* v = table->slots[i].value.load(std::memory_order_relaxed);
      if (v != nullptr) {
        larger->Insert(table->slots[i].key.load(std::memory_order_relaxed), v);
      }
    }
    table = larger;
  }
  table->Insert(key, coefficients);
  leaf.table.store(table, std::memory_order_release);
  return coefficients;
}

}  // namespace sdcb
