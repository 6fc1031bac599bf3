// Degree-k spherical Delaunay configurations: all j-facets of the knots
// (planes through three knots with exactly j knots on one side, j <= k) by
// "link triangulation" from j - 1 and j - 2 to j (Lee's construction of
// higher-order Voronoi diagrams, in the form of Liu & Snoeyink), started
// from the convex hull; the configurations are the k-facets whose k knots
// lie on the side without the origin. Why it is complete and exact:
// docs/CONFIGURATIONS.md.
#include "sdcb/core/spline/delaunay_configurations.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "sdcb/core/sphere/perturbed_predicates.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/knot_hull.h"

namespace sdcb {
namespace {

constexpr int kMaxDegree = 5;
// Knot indices are packed into 21-bit fields for fast sorting; the largest
// value pads unused entries of fixed-size index sets (it sorts last).
constexpr int kIndexBits = 21;
constexpr int kNone = (1 << kIndexBits) - 1;
constexpr int kMaxKnots = kNone;

using InteriorSet = std::array<int, kMaxDegree>;

// One j-facet: boundary triple and the j knots on one side of its plane
// (padded with kNone). A configuration when that side avoids the origin.
struct JFacet {
  std::array<int, 3> boundary;  // ascending
  InteriorSet interior;         // ascending
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
    if (std::abs(knots.row(i).norm() - 1.0) > kUnitVectorTolerance) {
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

struct LevelContext {
  const Eigen::MatrixX3d& knots;
  const KnotHull& hull;
  bool verify;
};

// The redundant local emptiness test of DelaunayConfigurationOptions::
// always_verify: every hull neighbour of the facet's knots that is not in s
// must be off the `inner` side (the vertices of a polytope in a closed
// half-space induce a connected subgraph, so that suffices).
bool PassesLocalCheck(const LevelContext& ctx, const PerturbedPlane& plane,
                      int inner, const InteriorSet& s, int m, int a, int b,
                      int c) {
  std::array<int, kMaxDegree + 3> members;
  std::copy(s.begin(), s.begin() + m, members.begin());
  members[m] = a;
  members[m + 1] = b;
  members[m + 2] = c;
  const auto end = members.begin() + m + 3;
  for (auto it = members.begin(); it != end; ++it) {
    for (int nb : ctx.hull.neighbors[*it]) {
      if (std::find(members.begin(), end, nb) == end &&
          plane.Side(nb) == inner) {
        return false;
      }
    }
  }
  return true;
}

// The m-facets with the m knots s on one side: triples of link candidates
// with all of s on one side of their plane and every other candidate on
// the other (Lee: inside the order-m region of s, the order-(m+1) diagram
// is the Voronoi diagram of its neighbours). Those are the facets of the
// candidates' hull with s outside: tested triple by triple for few
// candidates, from that hull for many (co-circular knots make fans with
// hundreds of candidates).
void FacetsWithInterior(const LevelContext& ctx, const InteriorSet& s, int m,
                        const std::vector<int>& cand,
                        std::vector<JFacet>* out) {
  const int num_cand = static_cast<int>(cand.size());
  auto emit = [&](int a, int b, int c, int inner, const PerturbedPlane& plane) {
    if (ctx.verify && !PassesLocalCheck(ctx, plane, inner, s, m, a, b, c))
      return;
    std::array<int, 3> boundary = {a, b, c};
    std::sort(boundary.begin(), boundary.end());
    out->push_back({boundary, s});
  };
  constexpr int kMaxCandidatesForTriples = 8;
  if (num_cand > kMaxCandidatesForTriples) {
    const auto facets = ComputeKnotSubsetHull(ctx.knots, cand);
    if (!facets.ok()) return;  // unreachable: the knots passed the full hull
    for (const auto& f : *facets) {
      const PerturbedPlane plane(ctx.knots, f[0], f[1], f[2]);
      bool ok = true;
      for (int i = 0; i < m && ok; ++i) ok = plane.Side(s[i]) > 0;  // outside
      if (ok) emit(f[0], f[1], f[2], +1, plane);
    }
    return;
  }
  for (int ia = 0; ia < num_cand; ++ia) {
    for (int ib = ia + 1; ib < num_cand; ++ib) {
      for (int ic = ib + 1; ic < num_cand; ++ic) {
        const int a = cand[ia], b = cand[ib], c = cand[ic];
        const PerturbedPlane plane(ctx.knots, a, b, c);
        const int inner = plane.Side(s[0]);
        bool ok = true;
        for (int i = 1; i < m && ok; ++i) ok = plane.Side(s[i]) == inner;
        for (int i = 0; i < num_cand && ok; ++i) {
          if (i != ia && i != ib && i != ic) ok = plane.Side(cand[i]) != inner;
        }
        if (ok) emit(a, b, c, inner, plane);
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

// The m-facets from the (m-1)- and (m-2)-facets: the m knots s of an
// m-facet and its boundary knots appear as an interior set and link
// candidates of facets one or two levels lower (docs/CONFIGURATIONS.md).
std::vector<JFacet> NextLevel(const LevelContext& ctx, int m,
                              const std::vector<JFacet>& lower1,
                              const std::vector<JFacet>* lower2) {
  std::vector<LinkRecord> records;
  records.reserve(6 * lower1.size() + (lower2 ? 3 * lower2->size() : 0));
  for (const JFacet& c : lower1) {
    const auto& b = c.boundary;
    for (int i = 0; i < 3; ++i) {
      const InteriorSet s = Union(c.interior, m - 1, {b[i]});
      records.push_back(MakeRecord(s, b[(i + 1) % 3]));
      records.push_back(MakeRecord(s, b[(i + 2) % 3]));
    }
  }
  if (lower2 != nullptr) {
    for (const JFacet& c : *lower2) {
      const auto& b = c.boundary;
      for (int i = 0; i < 3; ++i) {
        records.push_back(MakeRecord(
            Union(c.interior, m - 2, {b[(i + 1) % 3], b[(i + 2) % 3]}), b[i]));
      }
    }
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
  std::vector<std::vector<JFacet>> block_out(num_blocks);
  tbb::parallel_for(size_t{0}, num_blocks, [&](size_t block) {
    std::vector<int> cand;
    for (size_t g = block * kBlock;
         g < std::min(num_groups, (block + 1) * kBlock); ++g) {
      cand.clear();
      for (size_t i = group_begin[g]; i < group_begin[g + 1]; ++i) {
        cand.push_back(records[i].x());
      }
      FacetsWithInterior(ctx, UnpackSet(records[group_begin[g]]), m, cand,
                         &block_out[block]);
    }
  });
  std::vector<JFacet> result;
  for (const auto& b : block_out)
    result.insert(result.end(), b.begin(), b.end());
  return result;
}

DelaunayConfigurations GroupByUnorderedSet(const std::vector<JFacet>& configs,
                                           int degree) {
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
  for (const JFacet& c : configs) {
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

  // 0-facets: the hull facets (nothing on their outer side); degree-0
  // configurations: those whose outer side avoids the origin.
  std::vector<std::vector<JFacet>> facets(degree + 1);
  std::vector<JFacet> empty_caps;
  for (const auto& f : hull.facets) {
    std::array<int, 3> b = f;
    std::sort(b.begin(), b.end());
    facets[0].push_back({b, EmptySet()});
    if (PerturbedOrient3dSign(knots, f[0], f[1], f[2], kOriginIndex) < 0) {
      empty_caps.push_back({b, EmptySet()});
    }
  }
  const LevelContext ctx{knots, hull, options.always_verify};
  for (int m = 1; m <= degree; ++m) {
    facets[m] =
        NextLevel(ctx, m, facets[m - 1], m >= 2 ? &facets[m - 2] : nullptr);
  }
  // Degree-m configurations: m-facets whose m knots are on the side of the
  // plane without the origin (the smaller cap).
  auto configurations = [&](int m) {
    if (m == 0) return empty_caps;
    std::vector<JFacet> result;
    for (const JFacet& f : facets[m]) {
      const auto& b = f.boundary;
      if (PerturbedOrient3dSign(knots, b[0], b[1], b[2], f.interior[0]) !=
          PerturbedOrient3dSign(knots, b[0], b[1], b[2], kOriginIndex)) {
        result.push_back(f);
      }
    }
    return result;
  };
  std::vector<JFacet> top = configurations(degree);
  if (stats != nullptr) {
    stats->facets_per_degree.clear();
    stats->configurations_per_degree.clear();
    for (int m = 0; m <= degree; ++m) {
      stats->facets_per_degree.push_back(static_cast<int>(facets[m].size()));
      stats->configurations_per_degree.push_back(static_cast<int>(
          m == degree ? top.size() : configurations(m).size()));
    }
  }
  return GroupByUnorderedSet(top, degree);
}

}  // namespace sdcb
