// Degree-k spherical Delaunay configurations by "link triangulation" from
// degree j - 1 and j - 2 to degree j (Lee's construction of higher-order
// Voronoi diagrams, in the form of Liu & Snoeyink), started from the convex
// hull. Why it is complete and exact: docs/CONFIGURATIONS.md.
#include "core/delaunay_configurations.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "core/knot_hull.h"
#include "core/perturbed_predicates.h"

namespace sdcb {
namespace {

constexpr int kMaxDegree = 5;
// Knot indices are packed into 21-bit fields for fast sorting; the largest
// value pads unused entries of fixed-size index sets (it sorts last).
constexpr int kIndexBits = 21;
constexpr int kNone = (1 << kIndexBits) - 1;
constexpr int kMaxKnots = kNone;

using InteriorSet = std::array<int, kMaxDegree>;

// One configuration (X_B, X_I); X_I padded with kNone.
struct Configuration {
  std::array<int, 3> boundary;  // ascending
  InteriorSet interior;         // ascending
};

// A great circle through knots u, v with exactly `inside` (padded) strictly
// on one side: where a configuration search would cross the origin.
struct HemisphereEdge {
  int u, v;
  int size;
  InteriorSet inside;
};

// "Knot x is a link candidate of interior set s", packed so that sorting
// the records groups them by s (and orders each group by x).
struct LinkRecord {
  uint64_t hi;  // s[0], s[1], s[2]
  uint64_t lo;  // s[3], s[4], x
  bool operator<(const LinkRecord& o) const {
    return hi != o.hi ? hi < o.hi : lo < o.lo;
  }
  bool operator==(const LinkRecord& o) const {
    return hi == o.hi && lo == o.lo;
  }
  bool SameSet(const LinkRecord& o) const {
    return hi == o.hi && (lo >> kIndexBits) == (o.lo >> kIndexBits);
  }
  int x() const { return static_cast<int>(lo & kNone); }
};

uint64_t Pack3(int a, int b, int c) {
  return (uint64_t{static_cast<uint32_t>(a)} << (2 * kIndexBits)) |
         (uint64_t{static_cast<uint32_t>(b)} << kIndexBits) |
         static_cast<uint32_t>(c);
}

int Field(uint64_t word, int i) {  // i = 0, 1, 2 from the most significant
  return static_cast<int>((word >> ((2 - i) * kIndexBits)) & kNone);
}

LinkRecord MakeRecord(const InteriorSet& s, int x) {
  return {Pack3(s[0], s[1], s[2]), Pack3(s[3], s[4], x)};
}

InteriorSet UnpackSet(const LinkRecord& r) {
  return {Field(r.hi, 0), Field(r.hi, 1), Field(r.hi, 2), Field(r.lo, 0),
          Field(r.lo, 1)};
}

InteriorSet EmptySet() {
  InteriorSet s;
  s.fill(kNone);
  return s;
}

// `base` (size m) plus the given extra knots, sorted.
InteriorSet Union(const InteriorSet& base, int m,
                  std::initializer_list<int> extra) {
  InteriorSet s = base;
  int size = m;
  for (int x : extra) {  // insertion keeps the padding (kNone) last
    int i = size++;
    for (; i > 0 && s[i - 1] > x; --i) s[i] = s[i - 1];
    s[i] = x;
  }
  return s;
}

Status ValidateKnots(const Eigen::MatrixX3d& knots, int degree) {
  if (degree < 0 || degree > kMaxDegree) {
    return InvalidArgumentError("configuration degree must be in 0..5, got " +
                                std::to_string(degree));
  }
  const int n = static_cast<int>(knots.rows());
  if (n < degree + 4) {
    return InvalidArgumentError(
        "degree " + std::to_string(degree) + " configurations need at least " +
        std::to_string(degree + 4) + " knots, got " + std::to_string(n));
  }
  if (n >= kMaxKnots) {
    return InvalidArgumentError("at most " + std::to_string(kMaxKnots - 1) +
                                " knots are supported, got " +
                                std::to_string(n));
  }
  for (int i = 0; i < n; ++i) {
    if (!knots.row(i).allFinite()) {
      return InvalidArgumentError("knot " + std::to_string(i) +
                                  " has a non-finite coordinate");
    }
    if (std::abs(knots.row(i).norm() - 1.0) > 1e-9) {
      return InvalidArgumentError(
          "knot " + std::to_string(i) +
          " is not on the unit sphere (|norm - 1| > 1e-9)");
    }
  }
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  auto less = [&](int a, int b) {
    for (int c = 0; c < 3; ++c) {
      if (knots(a, c) != knots(b, c)) return knots(a, c) < knots(b, c);
    }
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  for (int i = 1; i < n; ++i) {
    if (knots.row(order[i - 1]) == knots.row(order[i])) {
      return InvalidArgumentError(
          "knots " + std::to_string(std::min(order[i - 1], order[i])) +
          " and " + std::to_string(std::max(order[i - 1], order[i])) +
          " are identical");
    }
  }
  return Status::Ok();
}

// True if every open hemisphere provably contains at least `needed` knots.
// Any open hemisphere contains a cap of angular radius 50 degrees around
// one of the 20 vertices of a regular dodecahedron (these are at most
// 37.38 degrees from every point of S^2, and 37.38 + 50 < 90 leaves a
// 2.6-degree margin, far above rounding), so it suffices that each of the
// 20 caps holds `needed` knots.
bool HemisphereCertificate(const Eigen::MatrixX3d& knots, int needed) {
  if (needed <= 0) return true;
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> centers;
  for (int sx : {-1, 1}) {
    for (int sy : {-1, 1}) {
      centers.emplace_back(0.0, sx / phi, sy * phi);
      centers.emplace_back(sx / phi, sy * phi, 0.0);
      centers.emplace_back(sx * phi, 0.0, sy / phi);
      for (int sz : {-1, 1}) centers.emplace_back(sx, sy, sz);
    }
  }
  const double cos_radius = std::cos(50.0 * M_PI / 180.0);
  for (Eigen::Vector3d c : centers) {
    c.normalize();
    int count = 0;
    for (int i = 0; i < knots.rows() && count < needed; ++i) {
      if (knots.row(i).dot(c) >= cos_radius) ++count;
    }
    if (count < needed) return false;
  }
  return true;
}

// All great circles through two knots with at most max_inside knots strictly
// on one side (each side reported separately). Brute force with early exit,
// O(n^2) pairs; only run for knot sets crowded into part of the sphere.
std::vector<HemisphereEdge> FindHemisphereEdges(const Eigen::MatrixX3d& knots,
                                                int max_inside) {
  const int n = static_cast<int>(knots.rows());
  std::vector<std::vector<HemisphereEdge>> per_knot(n);
  tbb::parallel_for(tbb::blocked_range<int>(0, n), [&](const auto& range) {
    for (int u = range.begin(); u < range.end(); ++u) {
      for (int v = u + 1; v < n; ++v) {
        HemisphereEdge side[2] = {{u, v, 0, EmptySet()}, {u, v, 0, EmptySet()}};
        for (int w = 0; w < n; ++w) {
          if (w == u || w == v) continue;
          const int s = PerturbedOrient3dSign(knots, kOriginIndex, u, v, w) > 0;
          if (side[s].size <= max_inside) {
            if (side[s].size < max_inside) side[s].inside[side[s].size] = w;
            ++side[s].size;
          }
          if (side[0].size > max_inside && side[1].size > max_inside) break;
        }
        for (const HemisphereEdge& e : side) {
          if (e.size <= max_inside) per_knot[u].push_back(e);
        }
      }
    }
  });
  std::vector<HemisphereEdge> edges;
  for (const auto& list : per_knot)
    edges.insert(edges.end(), list.begin(), list.end());
  return edges;
}

struct LevelContext {
  const Eigen::MatrixX3d& knots;
  const KnotHull& hull;
  bool verify;
};

// Degree-m configurations with interior exactly s: triples of link
// candidates whose cap holds all of s and no other candidate (Lee: the
// order-(m+1) Voronoi diagram inside the order-m region of s is the
// Voronoi diagram of its neighbours). With `verify`, also no hull
// neighbour of the configuration's knots (enough by the connectivity of
// the hull graph restricted to a half-space).
void ConfigurationsWithInterior(const LevelContext& ctx, const InteriorSet& s,
                                int m, const int* cand, int num_cand,
                                std::vector<Configuration>* out) {
  for (int ia = 0; ia < num_cand; ++ia) {
    for (int ib = ia + 1; ib < num_cand; ++ib) {
      for (int ic = ib + 1; ic < num_cand; ++ic) {
        const int a = cand[ia], b = cand[ib], c = cand[ic];
        const PerturbedCap cap(ctx.knots, a, b, c);
        bool ok = true;
        for (int i = 0; i < m && ok; ++i) ok = cap.Contains(s[i]);
        for (int i = 0; i < num_cand && ok; ++i) {
          if (i != ia && i != ib && i != ic) ok = !cap.Contains(cand[i]);
        }
        if (ok && ctx.verify) {
          std::array<int, kMaxDegree + 3> members;
          std::copy(s.begin(), s.begin() + m, members.begin());
          members[m] = a;
          members[m + 1] = b;
          members[m + 2] = c;
          const auto end = members.begin() + m + 3;
          for (auto it = members.begin(); it != end && ok; ++it) {
            for (int nb : ctx.hull.neighbors[*it]) {
              if (std::find(members.begin(), end, nb) != end) continue;
              if (cap.Contains(nb)) {
                ok = false;
                break;
              }
            }
          }
        }
        if (ok) out->push_back({{a, b, c}, s});
      }
    }
  }
}

// Sorts by (s, x): a counting sort on the smallest knot of s, then small
// sorts per bucket (cache-friendly, about 3x faster than one std::sort).
void SortRecords(int num_knots, std::vector<LinkRecord>* records) {
  std::vector<int> start(num_knots + 1, 0);
  for (const LinkRecord& r : *records) ++start[Field(r.hi, 0) + 1];
  for (int i = 0; i < num_knots; ++i) start[i + 1] += start[i];
  std::vector<LinkRecord> sorted(records->size());
  std::vector<int> next(start.begin(), start.end() - 1);
  for (const LinkRecord& r : *records) sorted[next[Field(r.hi, 0)]++] = r;
  tbb::parallel_for(tbb::blocked_range<int>(0, num_knots, 64),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int i = range.begin(); i < range.end(); ++i) {
                        std::sort(sorted.begin() + start[i],
                                  sorted.begin() + start[i + 1]);
                      }
                    });
  records->swap(sorted);
}

// Degree-m configurations from those of degree m - 1 and m - 2 and the
// hemisphere edges: each configuration's interior s and boundary knots
// appear as an interior and link candidates of a configuration one or two
// degrees lower, or of a hemisphere edge (docs/CONFIGURATIONS.md).
std::vector<Configuration> NextLevel(const LevelContext& ctx, int m,
                                     const std::vector<Configuration>& lower1,
                                     const std::vector<Configuration>* lower2,
                                     const std::vector<HemisphereEdge>& hemi) {
  std::vector<LinkRecord> records;
  records.reserve(6 * lower1.size() + (lower2 ? 3 * lower2->size() : 0));
  for (const Configuration& c : lower1) {
    const auto& b = c.boundary;
    for (int i = 0; i < 3; ++i) {
      const InteriorSet s = Union(c.interior, m - 1, {b[i]});
      records.push_back(MakeRecord(s, b[(i + 1) % 3]));
      records.push_back(MakeRecord(s, b[(i + 2) % 3]));
    }
  }
  if (lower2 != nullptr) {
    for (const Configuration& c : *lower2) {
      const auto& b = c.boundary;
      for (int i = 0; i < 3; ++i) {
        records.push_back(MakeRecord(
            Union(c.interior, m - 2, {b[(i + 1) % 3], b[(i + 2) % 3]}), b[i]));
      }
    }
  }
  for (const HemisphereEdge& e : hemi) {
    if (e.size != m - 1) continue;
    records.push_back(MakeRecord(Union(e.inside, m - 1, {e.u}), e.v));
    records.push_back(MakeRecord(Union(e.inside, m - 1, {e.v}), e.u));
  }
  SortRecords(ctx.knots.rows(), &records);
  records.erase(std::unique(records.begin(), records.end()), records.end());

  std::vector<size_t> group_begin;
  for (size_t i = 0; i < records.size(); ++i) {
    if (i == 0 || !records[i].SameSet(records[i - 1])) group_begin.push_back(i);
  }
  group_begin.push_back(records.size());
  const size_t num_groups = group_begin.size() - 1;
  // Fixed blocks, concatenated in order: identical output for any number
  // of threads.
  constexpr size_t kBlock = 512;
  const size_t num_blocks = (num_groups + kBlock - 1) / kBlock;
  std::vector<std::vector<Configuration>> block_out(num_blocks);
  tbb::parallel_for(size_t{0}, num_blocks, [&](size_t block) {
    std::vector<int> cand;
    for (size_t g = block * kBlock;
         g < std::min(num_groups, (block + 1) * kBlock); ++g) {
      cand.clear();
      for (size_t i = group_begin[g]; i < group_begin[g + 1]; ++i) {
        cand.push_back(records[i].x());
      }
      ConfigurationsWithInterior(ctx, UnpackSet(records[group_begin[g]]), m,
                                 cand.data(), static_cast<int>(cand.size()),
                                 &block_out[block]);
    }
  });
  std::vector<Configuration> result;
  for (const auto& b : block_out)
    result.insert(result.end(), b.begin(), b.end());
  return result;
}

DelaunayConfigurations GroupByUnorderedSet(
    const std::vector<Configuration>& configs, int degree) {
  // X~ = X_B u X_I (k + 3 <= 8 knots) packed into three words, then the
  // boundary: sorting groups by X~ and orders each group's boundaries.
  struct Keyed {
    std::array<uint64_t, 3> set;
    std::array<int, 3> boundary;
    bool operator<(const Keyed& o) const {
      return set != o.set ? set < o.set : boundary < o.boundary;
    }
  };
  std::vector<Keyed> keyed;
  keyed.reserve(configs.size());
  for (const Configuration& c : configs) {
    std::array<int, 9> all;
    all.fill(kNone);
    const InteriorSet& in = c.interior;
    std::merge(in.begin(), in.begin() + degree, c.boundary.begin(),
               c.boundary.end(), all.begin());
    keyed.push_back(
        {{Pack3(all[0], all[1], all[2]), Pack3(all[3], all[4], all[5]),
          Pack3(all[6], all[7], all[8])},
         c.boundary});
  }
  // Keys are unique, so the (unstable) parallel sort is deterministic.
  tbb::parallel_sort(keyed.begin(), keyed.end());
  DelaunayConfigurations result;
  result.degree = degree;
  for (size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].set != keyed[i - 1].set) {
      ConfigurationSet set;
      for (int w = 0; w < 3 * 3; ++w) {
        const int x = Field(keyed[i].set[w / 3], w % 3);
        if (x != kNone) set.knots.push_back(x);
      }
      result.sets.push_back(std::move(set));
    }
    result.sets.back().boundaries.push_back(keyed[i].boundary);
  }
  return result;
}

}  // namespace

StatusOr<DelaunayConfigurations> ComputeDelaunayConfigurations(
    const Eigen::MatrixX3d& knots, int degree) {
  return ComputeDelaunayConfigurations(knots, degree,
                                       DelaunayConfigurationOptions());
}

StatusOr<DelaunayConfigurations> ComputeDelaunayConfigurations(
    const Eigen::MatrixX3d& knots, int degree,
    const DelaunayConfigurationOptions& options,
    DelaunayConfigurationStats* stats) {
  SDCB_RETURN_IF_ERROR(ValidateKnots(knots, degree));
  SDCB_ASSIGN_OR_RETURN(const KnotHull hull, ComputeKnotHull(knots));

  // Degree 0: hull facets whose outer side avoids the origin (empty caps).
  std::vector<std::vector<Configuration>> levels(degree + 1);
  for (const auto& f : hull.facets) {
    if (PerturbedOrient3dSign(knots, f[0], f[1], f[2], kOriginIndex) < 0) {
      std::array<int, 3> b = f;
      std::sort(b.begin(), b.end());
      levels[0].push_back({b, EmptySet()});
    }
  }
  // Without the certificate a search may reach a great circle: collect the
  // crossing points and check every candidate locally.
  const bool certificate = HemisphereCertificate(knots, degree);
  std::vector<HemisphereEdge> hemi;
  if (!certificate && degree >= 1)
    hemi = FindHemisphereEdges(knots, degree - 1);
  const LevelContext ctx{knots, hull, options.always_verify || !certificate};
  for (int m = 1; m <= degree; ++m) {
    levels[m] = NextLevel(ctx, m, levels[m - 1],
                          m >= 2 ? &levels[m - 2] : nullptr, hemi);
  }
  if (stats != nullptr) {
    stats->hemisphere_certificate = certificate;
    stats->hemisphere_edges = static_cast<int>(hemi.size());
    stats->configurations_per_degree.clear();
    for (const auto& level : levels) {
      stats->configurations_per_degree.push_back(
          static_cast<int>(level.size()));
    }
  }
  return GroupByUnorderedSet(levels[degree], degree);
}

}  // namespace sdcb
