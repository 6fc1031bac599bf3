#include "sdcb/core/knots/spherical_cvt.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/sphere/point_kd_tree.h"
#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Samples per parallel block. Fixed (not derived from the thread count) so
// that the per-block partial sums, added in block order, are the same for
// any number of threads.
constexpr int kBlockSize = 4096;

// Area of the spherical triangle with unit-vector corners a, b, c:
// tan(A/2) = |det(a,b,c)| / (1 + a.b + b.c + c.a) (Van Oosterom & Strackee).
double SphericalTriangleArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  return 2 * std::atan2(std::abs(Det3(a, b, c)),
                        1 + a.dot(b) + b.dot(c) + c.dot(a));
}

// The fixed quadrature of the CVT energy (see the header).
struct Quadrature {
  // Unit vectors, or after Aggregate() the weighted mean of a bin's samples
  // (inside the ball). Either way the nearest unit knot t to a point c is
  // the one maximizing c.t, since |c - t|^2 = |c|^2 + 1 - 2 c.t.
  std::vector<Eigen::Vector3d> points;
  std::vector<double> areas;    // steradians, sum 4 pi
  std::vector<double> weights;  // integral of the density
  // Energy of the samples a point stands for about the point itself,
  // sum w |x - c|^2 = W (1 - |c|^2); 0 for plain samples.
  double spread_energy = 0;
  int size() const { return static_cast<int>(points.size()); }
};

Quadrature BuildQuadrature(const SphericalDensity& density, int m) {
  // Barycentric grid node (i, j) of a triangle (a, b, c) is
  // (i a + j b + (m - i - j) c) / m. Up triangles (i,j),(i+1,j),(i,j+1) for
  // i + j <= m - 1 and down triangles (i+1,j),(i+1,j+1),(i,j+1) for
  // i + j <= m - 2: m^2 in all.
  std::vector<Eigen::Vector3i> sub;  // (i, j, up ? 1 : 0)
  for (int i = 0; i < m; ++i) {
    for (int j = 0; i + j < m; ++j) {
      sub.emplace_back(i, j, 1);
      if (i + j <= m - 2) sub.emplace_back(i, j, 0);
    }
  }
  const int per_face = static_cast<int>(sub.size());
  const int num_faces = static_cast<int>(density.faces.rows());
  Quadrature q;
  q.points.resize(static_cast<size_t>(num_faces) * per_face);
  q.areas.resize(q.points.size());
  q.weights.resize(q.points.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, num_faces), [&](const auto& r) {
    for (int f = r.begin(); f < r.end(); ++f) {
      Eigen::Matrix3d corners;  // columns a, b, c
      Eigen::Vector3d rho;
      for (int k = 0; k < 3; ++k) {
        corners.col(k) = density.sphere_vertices.row(density.faces(f, k));
        rho[k] = density.values[density.faces(f, k)];
      }
      auto node = [&](int i, int j) -> Eigen::Vector3d {
        return Eigen::Vector3d(i, j, m - i - j) / m;  // barycentric
      };
      for (int s = 0; s < per_face; ++s) {
        const int i = sub[s][0], j = sub[s][1];
        Eigen::Vector3d l0, l1, l2;
        if (sub[s][2]) {
          l0 = node(i, j), l1 = node(i + 1, j), l2 = node(i, j + 1);
        } else {
          l0 = node(i + 1, j), l1 = node(i + 1, j + 1), l2 = node(i, j + 1);
        }
        const Eigen::Vector3d centroid = (l0 + l1 + l2) / 3;
        const size_t out = static_cast<size_t>(f) * per_face + s;
        q.points[out] = (corners * centroid).normalized();
        q.areas[out] = SphericalTriangleArea((corners * l0).normalized(),
                                             (corners * l1).normalized(),
                                             (corners * l2).normalized());
        q.weights[out] = q.areas[out] * rho.dot(centroid);
      }
    }
  });
  return q;
}

// Reorders the points along a Morton (Z-order) curve of their position, so
// that consecutive points, hence the points of a block, are close in space:
// the seeding skips whole blocks far from a new knot, and nearest-knot
// queries in a block touch the same part of the k-d tree. The quadrature is
// a set; only rounding of the sums depends on the order.
void SortSpatially(Quadrature* q) {
  auto spread = [](std::uint64_t v) {  // 10 bits -> every third of 30 bits
    std::uint64_t x = v & 0x3ff;
    x = (x | (x << 16)) & 0x30000ff;
    x = (x | (x << 8)) & 0x300f00f;
    x = (x | (x << 4)) & 0x30c30c3;
    x = (x | (x << 2)) & 0x9249249;
    return x;
  };
  const int n = q->size();
  std::vector<std::pair<std::uint64_t, int>> keys(n);
  for (int s = 0; s < n; ++s) {
    std::uint64_t code = 0;
    for (int k = 0; k < 3; ++k) {
      const double u = std::clamp((q->points[s][k] + 1) / 2, 0.0, 1.0);
      code |= spread(static_cast<std::uint64_t>(u * 1023)) << k;
    }
    keys[s] = {code, s};
  }
  std::sort(keys.begin(), keys.end());
  Quadrature sorted;
  sorted.spread_energy = q->spread_energy;
  sorted.points.reserve(n);
  sorted.areas.reserve(n);
  sorted.weights.reserve(n);
  for (const auto& key : keys) {
    sorted.points.push_back(q->points[key.second]);
    sorted.areas.push_back(q->areas[key.second]);
    sorted.weights.push_back(q->weights[key.second]);
  }
  *q = std::move(sorted);
}

// Merges the samples into bins: each bin becomes one point, the weighted
// mean c of its samples, with their total weight W. Since
// sum w |x - t|^2 = W |c - t|^2 + sum w |x - c|^2 for any t, the CVT energy
// is unchanged wherever all of a bin's samples share their nearest knot
// (all but the bins on Voronoi edges), and Lloyd's centroids likewise.
// Bins adapt to the density like CVT cells do: a cell's area goes as
// rho^(-1/2), so bins are split (median cuts along their widest axis) until
// each holds at most 1/bins of the total integral of rho^(1/2), and none is
// wider than 16 uniform bins in area. Bins without density keep an
// area-weighted position (for seeding by area).
Quadrature Aggregate(const Quadrature& fine, int bins) {
  const int n = fine.size();
  std::vector<double> root_mass(n);  // area * rho^(1/2) = sqrt(w * area)
  double total_root_mass = 0;
  for (int s = 0; s < n; ++s) {
    root_mass[s] = std::sqrt(fine.weights[s] * fine.areas[s]);
    total_root_mass += root_mass[s];
  }
  const double max_root_mass = total_root_mass / bins;
  const double max_area = 16 * 4 * kPi / bins;
  std::vector<int> order(n);
  for (int s = 0; s < n; ++s) order[s] = s;
  // One bin: its point, area, weight and spread energy.
  struct Bin {
    Eigen::Vector3d point;
    double area, weight, spread;
  };
  auto emit = [&](int begin, int end, std::vector<Bin>* out) {
    Eigen::Vector3d moment = Eigen::Vector3d::Zero(),
                    area_moment = Eigen::Vector3d::Zero();
    double weight = 0, area = 0;
    for (int i = begin; i < end; ++i) {
      const int s = order[i];
      moment += fine.weights[s] * fine.points[s];
      area_moment += fine.areas[s] * fine.points[s];
      weight += fine.weights[s];
      area += fine.areas[s];
    }
    if (!(area > 0)) return;
    const Eigen::Vector3d c = weight > 0 ? Eigen::Vector3d(moment / weight)
                                         : Eigen::Vector3d(area_moment / area);
    out->push_back(
        {c, area, weight, weight * std::max(0.0, 1 - c.squaredNorm())});
  };
  // Depth first, left half first: a fixed order. Halves of more than
  // kParallelBins points are split concurrently (they own disjoint ranges
  // of `order`), their bins concatenated in that order.
  constexpr int kParallelBins = 8192;
  std::function<void(int, int, std::vector<Bin>*)> split =
      [&](int begin, int end, std::vector<Bin>* out) {
        double root = 0, area = 0;
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(kInf), hi = -lo;
        for (int i = begin; i < end; ++i) {
          root += root_mass[order[i]];
          area += fine.areas[order[i]];
          lo = lo.cwiseMin(fine.points[order[i]]);
          hi = hi.cwiseMax(fine.points[order[i]]);
        }
        if (end - begin == 1 || (root <= max_root_mass && area <= max_area)) {
          emit(begin, end, out);
          return;
        }
        int axis;
        (hi - lo).maxCoeff(&axis);
        const int mid = begin + (end - begin) / 2;
        std::nth_element(order.begin() + begin, order.begin() + mid,
                         order.begin() + end, [&](int a, int b) {
                           const double pa = fine.points[a][axis],
                                        pb = fine.points[b][axis];
                           return pa < pb || (pa == pb && a < b);
                         });
        if (end - begin <= kParallelBins) {
          split(begin, mid, out);
          split(mid, end, out);
          return;
        }
        std::vector<Bin> right;
        tbb::parallel_invoke([&] { split(begin, mid, out); },
                             [&] { split(mid, end, &right); });
        out->insert(out->end(), right.begin(), right.end());
      };
  std::vector<Bin> all;
  if (n > 0) split(0, n, &all);
  Quadrature q;
  q.points.reserve(all.size());
  q.areas.reserve(all.size());
  q.weights.reserve(all.size());
  for (const Bin& bin : all) {  // in emission order, as the sums were
    q.points.push_back(bin.point);
    q.areas.push_back(bin.area);
    q.weights.push_back(bin.weight);
    q.spread_energy += bin.spread;
  }
  return q;
}

Status ValidateDensity(const SphericalDensity& density) {
  const Eigen::Index nv = density.sphere_vertices.rows();
  if (nv < 3 || density.faces.rows() < 1) {
    return InvalidArgumentError("density mesh has no triangles");
  }
  if (density.values.size() != nv) {
    return InvalidArgumentError(
        "density has " + std::to_string(density.values.size()) +
        " values for " + std::to_string(nv) + " vertices");
  }
  if (!AllUnitRows(density.sphere_vertices)) {
    return InvalidArgumentError("density mesh vertices must be unit vectors");
  }
  if (density.faces.minCoeff() < 0 || density.faces.maxCoeff() >= nv) {
    return InvalidArgumentError("density mesh has a vertex index out of range");
  }
  if (!density.values.allFinite() || density.values.minCoeff() < 0) {
    return InvalidArgumentError("density values must be finite and >= 0");
  }
  return Status::Ok();
}

Status ValidateOptions(const CvtOptions& options, int new_knots) {
  if (new_knots < 0) {
    return InvalidArgumentError("number of new knots must be >= 0");
  }
  if (options.max_iterations < 0) {
    return InvalidArgumentError("CVT max_iterations must be >= 0");
  }
  if (!(options.relative_energy_tolerance >= 0)) {
    return InvalidArgumentError("CVT relative_energy_tolerance must be >= 0");
  }
  if (!(options.min_separation >= 0 && options.min_separation < 1)) {
    return InvalidArgumentError("CVT min_separation must be in [0, 1) radians");
  }
  if (options.samples_per_knot < 1 || options.max_subdivision < 1 ||
      options.bins_per_knot < 0) {
    return InvalidArgumentError(
        "CVT samples_per_knot and max_subdivision must be >= 1, "
        "bins_per_knot >= 0");
  }
  return Status::Ok();
}

// Result of assigning every sample to its nearest knot.
struct Assignment {
  double energy = 0;
  // Per free knot: density-weighted sum of sample positions and mass.
  std::vector<Eigen::Vector3d> moment;
  std::vector<double> mass;
};

// Which points provably still belong to their nearest fixed knot, so that
// Lloyd iterations skip them (with many fixed knots, most points). When
// point s was last searched, its nearest free knot was at least margin[s]
// (chord) farther than its nearest fixed knot; since then every free knot
// has moved by at most travel - travel_at[s] (sum over the iterations of the
// largest move), so by the triangle inequality the fixed knot is still
// strictly nearer while margin[s] > travel - travel_at[s]. Skipping does not
// change the assignment, only its cost.
struct FixedCapture {
  std::vector<double> margin;     // chord; -1: search again
  std::vector<double> travel_at;  // `travel` when margin was recorded
  double travel = 0;
  double window = 0;  // how far beyond the fixed distance searches look
  bool enabled = true;
};

// Nearest-knot assignment against the free knots, given each point's
// squared distance to the nearest fixed knot (a fixed knot wins ties).
// First every point's nearest free knot, in parallel over small chunks (the
// searches are most of the work, and the settled points that cost nothing
// cluster: whole kBlockSize blocks would leave a thread idle); then the sums
// per kBlockSize block in point order, added in block order: the same bits
// for any thread count and chunking.
Assignment Assign(const Quadrature& q, const std::vector<double>& fixed_d2,
                  const Eigen::MatrixX3d& free_knots, FixedCapture* capture) {
  // Rounding allowance (chord) on the skip test and recorded margins.
  constexpr double kSlack = 1e-9;
  constexpr int kChunk = 256;
  const int num_free = static_cast<int>(free_knots.rows());
  const PointKdTree tree(free_knots);
  // Per point: its nearest free knot if that is strictly nearer than the
  // fixed one, else -1; and the squared distance to the knot it belongs to.
  std::vector<int> nearest(q.size());
  std::vector<double> d2(q.size());
  tbb::parallel_for(
      tbb::blocked_range<int>(0, q.size(), kChunk), [&](const auto& r) {
        int previous = -1;  // nearest free knot of the last searched point
        for (int s = r.begin(); s < r.end(); ++s) {
          const double d2_fixed = fixed_d2[s];
          nearest[s] = -1;
          d2[s] = d2_fixed;
          if (capture->enabled &&
              capture->margin[s] - (capture->travel - capture->travel_at[s]) >
                  kSlack) {
            continue;
          }
          const double d_fixed = std::sqrt(d2_fixed);
          const double reach = d_fixed + capture->window;
          // The previous point's nearest free knot (points are in Morton
          // order) tightens the bound without changing the answer.
          const PointKdTree::Neighbor n =
              tree.NearestNear(q.points[s], previous, reach * reach);
          if (n.index >= 0) previous = n.index;
          capture->travel_at[s] = capture->travel;
          if (n.index >= 0 && n.squared_distance < d2_fixed) {
            capture->margin[s] = -1;
            nearest[s] = n.index;
            d2[s] = n.squared_distance;
            continue;
          }
          capture->margin[s] =
              (n.index >= 0 ? std::sqrt(n.squared_distance) : reach) - d_fixed -
              kSlack;
        }
      });
  const int num_blocks = (q.size() + kBlockSize - 1) / kBlockSize;
  std::vector<Assignment> blocks(num_blocks);
  tbb::parallel_for(tbb::blocked_range<int>(0, num_blocks), [&](const auto& r) {
    for (int b = r.begin(); b < r.end(); ++b) {
      Assignment& out = blocks[b];
      out.moment.assign(num_free, Eigen::Vector3d::Zero());
      out.mass.assign(num_free, 0.0);
      const int end = std::min(q.size(), (b + 1) * kBlockSize);
      for (int s = b * kBlockSize; s < end; ++s) {
        out.energy += q.weights[s] * d2[s];
        const int k = nearest[s];
        if (k < 0) continue;
        out.moment[k] += q.weights[s] * q.points[s];
        out.mass[k] += q.weights[s];
      }
    }
  });
  Assignment total;
  total.energy = q.spread_energy;
  total.moment.assign(num_free, Eigen::Vector3d::Zero());
  total.mass.assign(num_free, 0.0);
  for (const Assignment& block : blocks) {  // ordered reduction
    total.energy += block.energy;
    for (int k = 0; k < num_free; ++k) {
      total.moment[k] += block.moment[k];
      total.mass[k] += block.mass[k];
    }
  }
  return total;
}

// Uniform double in [0, 1) from 53 random bits (the same on every
// platform, unlike std::uniform_real_distribution).
double UnitUniform(std::mt19937_64* rng) {
  return static_cast<double>((*rng)() >> 11) * 0x1.0p-53;
}

// Sampling probabilities of the seeding, p[s] = base[s] * d2[s] for the two
// bases (density weight, area), kept with per-block sums so that a draw
// costs O(#blocks + block size). An update visits only the blocks whose
// bounding box is nearer to the new knot than their largest d2 (points are
// in Morton order, so blocks are compact).
class SeedSampler {
 public:
  SeedSampler(const Quadrature& q, std::vector<double> d2)
      : q_(q),
        d2_(std::move(d2)),
        excluded_(q.size(), 0),
        p_{std::vector<double>(q.size()), std::vector<double>(q.size())},
        block_sum_{std::vector<double>(NumBlocks()),
                   std::vector<double>(NumBlocks())},
        block_lo_(NumBlocks()),
        block_hi_(NumBlocks()),
        block_max_d2_(NumBlocks()) {
    for (int b = 0; b < NumBlocks(); ++b) {
      block_lo_[b] = Eigen::Vector3d::Constant(kInf);
      block_hi_[b] = -block_lo_[b];
      for (int s = b * kSeedBlock; s < BlockEnd(b); ++s) {
        block_lo_[b] = block_lo_[b].cwiseMin(q.points[s]);
        block_hi_[b] = block_hi_[b].cwiseMax(q.points[s]);
      }
      block_max_d2_[b] = kInf;
    }
    Update(nullptr);
  }

  // Lowers every point's d2 to its distance to t (if given) and refreshes
  // the probabilities and the block sums.
  void Update(const Eigen::Vector3d* t) {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, NumBlocks()), [&](const auto& r) {
          for (int b = r.begin(); b < r.end(); ++b) {
            if (t != nullptr) {
              const Eigen::Vector3d gap =
                  (block_lo_[b] - *t).cwiseMax(*t - block_hi_[b]).cwiseMax(0);
              if (gap.squaredNorm() >= block_max_d2_[b]) continue;
            }
            double max_d2 = 0;
            for (int s = b * kSeedBlock; s < BlockEnd(b); ++s) {
              if (t != nullptr) {
                d2_[s] = std::min(d2_[s], (q_.points[s] - *t).squaredNorm());
              }
              max_d2 = std::max(max_d2, d2_[s]);
              Refresh(s);
            }
            block_max_d2_[b] = max_d2;
            SumBlock(b);
          }
        });
  }

  // Never draws point s again.
  void Exclude(int s) {
    excluded_[s] = 1;
    Refresh(s);
    SumBlock(s / kSeedBlock);
  }

  // A point drawn with probability p_base[s] / sum(p_base), base 0 the
  // density weight and 1 the area; -1 if that sum is 0.
  int Draw(int base, std::mt19937_64* rng) const {
    const std::vector<double>& sums = block_sum_[base];
    double total = 0;
    for (double v : sums) total += v;  // in block order
    if (!(total > 0)) return -1;
    double target = UnitUniform(rng) * total;
    int last_positive = -1;
    for (int b = 0; b < NumBlocks(); ++b) {
      if (!(sums[b] > 0)) continue;
      if (target >= sums[b]) {  // not in this block (up to rounding)
        target -= sums[b];
        last_positive = b;
        continue;
      }
      return DrawInBlock(base, b, target);
    }
    // Rounding pushed the target past the end: the last positive block.
    return last_positive < 0 ? -1 : DrawInBlock(base, last_positive, kInf);
  }

 private:
  static constexpr int kSeedBlock = 256;
  int NumBlocks() const { return (q_.size() + kSeedBlock - 1) / kSeedBlock; }
  int BlockEnd(int b) const {
    return std::min(q_.size(), (b + 1) * kSeedBlock);
  }

  void Refresh(int s) {
    const bool usable = !excluded_[s] && q_.points[s].squaredNorm() > 0;
    const double d2 = d2_[s] == kInf ? 1.0 : d2_[s];
    p_[0][s] = usable ? q_.weights[s] * d2 : 0.0;
    p_[1][s] = usable ? q_.areas[s] * d2 : 0.0;
  }
  void SumBlock(int b) {
    for (int base = 0; base < 2; ++base) {
      double sum = 0;
      for (int s = b * kSeedBlock; s < BlockEnd(b); ++s) sum += p_[base][s];
      block_sum_[base][b] = sum;
    }
  }
  int DrawInBlock(int base, int b, double target) const {
    int last_positive = -1;
    double running = 0;
    for (int s = b * kSeedBlock; s < BlockEnd(b); ++s) {
      if (!(p_[base][s] > 0)) continue;
      running += p_[base][s];
      last_positive = s;
      if (running > target) break;
    }
    return last_positive;
  }

  const Quadrature& q_;
  std::vector<double> d2_;  // squared distance to the nearest knot so far
  std::vector<char> excluded_;
  std::vector<double> p_[2];
  std::vector<double> block_sum_[2];
  std::vector<Eigen::Vector3d> block_lo_, block_hi_;  // bounding boxes
  std::vector<double> block_max_d2_;  // an upper bound of d2 in the block
};

// k-means++ seeding of the new knots on the quadrature points: each new
// knot is a point (pushed onto S^2) drawn with probability proportional to
// its weight times its squared distance to the nearest knot so far (`d2`:
// to the fixed knots at first), among the points whose projection is at
// least min_separation from every knot; by area where those points carry
// no density.
StatusOr<Eigen::MatrixX3d> SeedNewKnots(const Quadrature& q,
                                        std::vector<double> d2,
                                        const PointKdTree& fixed_tree,
                                        int new_knots, double separation_d2,
                                        std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Eigen::MatrixX3d knots(new_knots, 3);
  SeedSampler sampler(q, std::move(d2));
  auto far_enough = [&](const Eigen::Vector3d& t, int placed) {
    if (fixed_tree.Nearest(t, separation_d2).index >= 0) return false;
    for (int j = 0; j < placed; ++j) {
      if ((knots.row(j).transpose() - t).squaredNorm() < separation_d2) {
        return false;
      }
    }
    return true;
  };
  for (int k = 0; k < new_knots; ++k) {
    Eigen::Vector3d t;
    bool found = false;
    for (int base = 0; base < 2 && !found; ++base) {
      while (!found) {
        const int s = sampler.Draw(base, &rng);
        if (s < 0) break;
        t = q.points[s].normalized();
        found = far_enough(t, k);
        if (!found) sampler.Exclude(s);
      }
    }
    if (!found) {
      return UnsupportedError(
          "cannot place " + std::to_string(new_knots) +
          " new knots at least min_separation apart from the others and "
          "each other");
    }
    knots.row(k) = t.transpose();
    sampler.Update(&t);
  }
  return knots;
}

// The quadrature of `density` for `num_knots` knots, its resolution from
// CvtOptions::samples_per_knot and bins_per_knot, spatially sorted; an error
// if the density's triangles do not cover the sphere or its mass is 0.
StatusOr<Quadrature> BuildKnotQuadrature(const SphericalDensity& density,
                                         int num_knots,
                                         const CvtOptions& options) {
  const double wanted =
      static_cast<double>(options.samples_per_knot) * num_knots;
  int m = 1;
  while (m < options.max_subdivision &&
         static_cast<double>(density.faces.rows()) * m * m < wanted) {
    ++m;
  }
  Quadrature q = BuildQuadrature(density, m);
  double area = 0, mass = 0;
  for (int s = 0; s < q.size(); ++s) {
    area += q.areas[s];
    mass += q.weights[s];
  }
  if (std::abs(area - 4 * kPi) > 1e-3 * 4 * kPi) {
    return InvalidArgumentError(
        "density triangles cover an area of " + std::to_string(area) +
        " sr instead of 4 pi: not a valid spherical parameterization");
  }
  if (!(mass > 0)) {
    return InvalidInputError("density integrates to 0 over the sphere");
  }
  const double bins = static_cast<double>(options.bins_per_knot) * num_knots;
  if (options.bins_per_knot > 0 && q.size() > 2 * bins) {
    q = Aggregate(q, static_cast<int>(bins));
  }
  SortSpatially(&q);
  return q;
}

// Squared distance of every sample to its nearest fixed knot (infinite
// without fixed knots): fixed knots never move, so this is computed once.
std::vector<double> FixedDistances(const Quadrature& q,
                                   const PointKdTree& fixed_tree) {
  std::vector<double> fixed_d2(q.size(), kInf);
  if (fixed_tree.size() > 0) {
    tbb::parallel_for(tbb::blocked_range<int>(0, q.size()), [&](const auto& r) {
      // Consecutive points are close (Morton order): the previous point's
      // nearest knot bounds the search.
      int previous = -1;
      for (int s = r.begin(); s < r.end(); ++s) {
        const PointKdTree::Neighbor n =
            fixed_tree.NearestNear(q.points[s], previous);
        fixed_d2[s] = n.squared_distance;
        previous = n.index;
      }
    });
  }
  return fixed_d2;
}

// Lloyd step: each free knot to the projected centroid of its cell, in
// order, unless that would bring it within min_separation of a knot in its
// current position (then it stays; E still does not increase). Returns
// whether a knot moved; the largest move in `*largest_move`.
bool LloydStep(const Assignment& assignment, const PointKdTree& fixed_tree,
               double separation_d2, Eigen::MatrixX3d* free_knots,
               double* largest_move) {
  const int new_knots = static_cast<int>(free_knots->rows());
  bool moved = false;
  for (int k = 0; k < new_knots; ++k) {
    const Eigen::Vector3d& moment = assignment.moment[k];
    if (!(assignment.mass[k] > 0) || moment.squaredNorm() == 0) continue;
    const Eigen::Vector3d target = moment.normalized();
    if (fixed_tree.Nearest(target, separation_d2).index >= 0) continue;
    bool too_close = false;
    for (int j = 0; j < new_knots && !too_close; ++j) {
      too_close =
          j != k && (free_knots->row(j).transpose() - target).squaredNorm() <
                        separation_d2;
    }
    if (too_close) continue;
    const double move = (free_knots->row(k).transpose() - target).norm();
    moved = moved || move > 0;
    *largest_move = std::max(*largest_move, move);
    free_knots->row(k) = target.transpose();
  }
  return moved;
}

}  // namespace

StatusOr<Eigen::VectorXd> DensityFromValues(const Eigen::VectorXd& values,
                                            double alpha) {
  if (!(alpha > 0) || !std::isfinite(alpha)) {
    return InvalidArgumentError("density exponent alpha must be > 0");
  }
  if (values.size() == 0 || !values.allFinite() || values.minCoeff() < 0 ||
      !(values.maxCoeff() > 0)) {
    return InvalidArgumentError(
        "density values must be finite, >= 0 and not all 0");
  }
  return Eigen::VectorXd(
      (values / values.maxCoeff()).array().pow(alpha).matrix());
}

StatusOr<Eigen::VectorXd> PullBackDensity(const Eigen::VectorXd& values,
                                          const Eigen::VectorXd& area_ratio) {
  if (area_ratio.size() != values.size() || !area_ratio.allFinite() ||
      !(area_ratio.size() == 0 || area_ratio.minCoeff() > 0)) {
    return InvalidArgumentError(
        "area ratios must be finite, > 0 and one per density value");
  }
  return DensityFromValues(values.cwiseProduct(area_ratio.cwiseAbs2()).eval(),
                           1.0);
}

KnotSeparation MinimumKnotSeparation(const Eigen::MatrixX3d& knots) {
  KnotSeparation result;
  result.angle = kInf;
  const PointKdTree tree(knots);
  double best = kInf;
  for (int i = 0; i < knots.rows(); ++i) {
    const PointKdTree::Neighbor n =
        tree.Nearest(knots.row(i).transpose(), kInf, i);
    if (n.index < 0) continue;
    const int a = std::min(i, n.index), b = std::max(i, n.index);
    if (n.squared_distance < best ||
        (n.squared_distance == best &&
         std::make_pair(a, b) < std::make_pair(result.first, result.second))) {
      best = n.squared_distance;
      result.first = a;
      result.second = b;
    }
  }
  if (result.first >= 0) result.angle = AngleFromChord(std::sqrt(best));
  return result;
}

StatusOr<KnotPlacement> PlaceKnots(const SphericalDensity& density,
                                   const Eigen::MatrixX3d& fixed_knots,
                                   int new_knots, const CvtOptions& options) {
  SDCB_RETURN_IF_ERROR(ValidateOptions(options, new_knots));
  SDCB_RETURN_IF_ERROR(ValidateDensity(density));
  const int num_fixed = static_cast<int>(fixed_knots.rows());
  if (!AllUnitRows(fixed_knots)) {
    return InvalidArgumentError("fixed knots must be unit vectors");
  }
  if (num_fixed + new_knots == 0) {
    return InvalidArgumentError("no knots: no fixed knots and none to place");
  }
  const KnotSeparation fixed_separation = MinimumKnotSeparation(fixed_knots);
  if (fixed_separation.angle < options.min_separation) {
    return InvalidArgumentError(
        "fixed knots " + std::to_string(fixed_separation.first) + " and " +
        std::to_string(fixed_separation.second) +
        " are closer than the minimum separation");
  }
  const double chord = ChordFromAngle(options.min_separation);
  const double separation_d2 = chord * chord;

  SDCB_ASSIGN_OR_RETURN(
      const Quadrature q,
      BuildKnotQuadrature(density, num_fixed + new_knots, options));

  const PointKdTree fixed_tree(fixed_knots);
  const std::vector<double> fixed_d2 = FixedDistances(q, fixed_tree);
  SDCB_ASSIGN_OR_RETURN(Eigen::MatrixX3d free_knots,
                        SeedNewKnots(q, fixed_d2, fixed_tree, new_knots,
                                     separation_d2, options.seed));

  KnotPlacement result;
  result.num_fixed = num_fixed;
  result.quadrature_samples = q.size();
  FixedCapture capture;
  capture.margin.assign(q.size(), -1.0);
  capture.travel_at.assign(q.size(), 0.0);
  // About one knot spacing: points farther than that beyond their fixed
  // knot are left alone until the free knots have travelled as far.
  capture.enabled = options.skip_settled_points;
  capture.window =
      capture.enabled ? std::sqrt(4 * kPi / (num_fixed + new_knots)) : 0.0;
  for (int iteration = 0;; ++iteration) {
    const Assignment assignment = Assign(q, fixed_d2, free_knots, &capture);
    result.energy_history.push_back(assignment.energy);
    if (iteration > 0) {
      const double previous = result.energy_history[iteration - 1];
      if (previous - assignment.energy <=
          options.relative_energy_tolerance * previous) {
        result.converged = true;
        break;
      }
    }
    if (new_knots == 0) {
      result.converged = true;
      break;
    }
    if (iteration == options.max_iterations) break;
    double largest_move = 0;
    const bool moved = LloydStep(assignment, fixed_tree, separation_d2,
                                 &free_knots, &largest_move);
    capture.travel += largest_move;
    result.iterations = iteration + 1;
    if (!moved) {
      result.energy_history.push_back(assignment.energy);
      result.converged = true;
      break;
    }
  }
  result.initial_energy = result.energy_history.front();
  result.final_energy = result.energy_history.back();
  result.knots.resize(num_fixed + new_knots, 3);
  result.knots << fixed_knots, free_knots;
  result.min_separation = MinimumKnotSeparation(result.knots).angle;
  return result;
}

}  // namespace sdcb
