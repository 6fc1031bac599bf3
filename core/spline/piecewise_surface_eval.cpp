// PiecewiseSurface's evaluation: positions, normals and shapes from the
// region polynomials, one point at a time or in batches sorted by cell.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/piecewise_surface_cells.h"
#include "sdcb/core/spline/simplex_spline.h"

namespace sdcb {
namespace {

constexpr Eigen::Index kChunk = Eigen::Index{1} << 18;  // ByLeaf

// The region's four polynomials (N_x, N_y, N_z, I; coefficients c[4 m + d])
// at (s, t): values and, up to Order, derivatives in s and t.
template <int K, int Order>
struct RegionJet {
  static constexpr int kSize = PolynomialSize(K);
  double v[4] = {0, 0, 0, 0};
  double vs[4] = {0, 0, 0, 0}, vt[4] = {0, 0, 0, 0};
  double vss[4] = {0, 0, 0, 0}, vst[4] = {0, 0, 0, 0}, vtt[4] = {0, 0, 0, 0};

  RegionJet(const double* c, double s, double t) {
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
    Add(c, mono, v);
    if constexpr (Order >= 1) {
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
    if constexpr (Order >= 2) {
      double dss[kSize], dst[kSize], dtt[kSize];
      for (int n = 0; n <= K; ++n)
        for (int j = 0; j <= n; ++j) {
          const int i = n - j, m = MonomialIndex(i, j);
          dss[m] = i > 1 ? i * (i - 1) * sp[i - 2] * tp[j] : 0.0;
          dst[m] = i > 0 && j > 0 ? i * j * sp[i - 1] * tp[j - 1] : 0.0;
          dtt[m] = j > 1 ? j * (j - 1) * sp[i] * tp[j - 2] : 0.0;
        }
      Add(c, dss, vss);
      Add(c, dst, vst);
      Add(c, dtt, vtt);
    }
  }
  static void Add(const double* c, const double* mono, double* out) {
    for (int m = 0; m < kSize; ++m)
      for (int d = 0; d < 4; ++d) out[d] += c[4 * m + d] * mono[m];
  }

  // The raw form's denominator |x|^K (the raw basis extended homogeneously
  // of degree 0) at x = o + s e1 + t e2, in place of I.
  void UseRawDenominator(const Eigen::Vector3d& o, const Eigen::Vector3d& e1,
                         const Eigen::Vector3d& e2, double s, double t) {
    const Eigen::Vector3d x = o + s * e1 + t * e2;
    const double r2 = x.squaredNorm();
    const double rk = std::pow(r2, 0.5 * K);
    const double xs = x.dot(e1), xt = x.dot(e2);
    v[3] = rk;
    vs[3] = K * rk / r2 * xs;
    vt[3] = K * rk / r2 * xt;
    // d2 |x|^K = K |x|^(K-2) (e_a . e_b) + K (K - 2) |x|^(K-4) (x.e_a)(x.e_b).
    const double a = K * rk / r2, b = K * (K - 2) * rk / (r2 * r2);
    vss[3] = a * e1.dot(e1) + b * xs * xs;
    vst[3] = a * e1.dot(e2) + b * xs * xt;
    vtt[3] = a * e2.dot(e2) + b * xt * xt;
  }
};

}  // namespace

template <int K>
void PiecewiseSurface::EvalDegree(const Eigen::Vector3d& p,
                                  Eigen::Vector3d* position,
                                  Eigen::Vector3d* normal) const {
  double s, t;
  const Leaf& leaf = *leaves_[Locate(p, &s, &t)];
  const double* c = leaf.slow ? nullptr : Region(leaf, p);
  if (c == nullptr) {
    // The same position with or without the normal.
    *position = spline_.Evaluate(p.normalized());
    if (normal != nullptr) {
      *normal =
          spline_.EvaluateDifferential(p.normalized(), JetOrder::kGradient)
              .normal;
    }
    return;
  }
  const auto finish = [&](auto& jet) {
    if (spline_.basis_form() == BasisForm::kRaw) {
      jet.UseRawDenominator(leaf.origin, leaf.e1, leaf.e2, s, t);
    }
    const double inv = 1.0 / jet.v[3];
    *position = Eigen::Vector3d(jet.v[0], jet.v[1], jet.v[2]) * inv;
    if (normal == nullptr) return;
    Eigen::Vector3d fs, ft;
    for (int d = 0; d < 3; ++d) {
      fs[d] = (jet.vs[d] - (*position)[d] * jet.vs[3]) * inv;
      ft[d] = (jet.vt[d] - (*position)[d] * jet.vt[3]) * inv;
    }
    const Eigen::Vector3d cross = fs.cross(ft);
    const double len = cross.norm();
    *normal = len > 0 ? Eigen::Vector3d(cross / len) : Eigen::Vector3d::Zero();
  };
  if (normal == nullptr) {
    RegionJet<K, 0> jet(c, s, t);
    finish(jet);
  } else {
    RegionJet<K, 1> jet(c, s, t);
    finish(jet);
  }
}

template <int K>
SurfaceShape PiecewiseSurface::ShapeDegree(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d u = p.normalized();
  double s, t;
  const Leaf& leaf = *leaves_[Locate(p, &s, &t)];
  const double* c = leaf.slow ? nullptr : Region(leaf, p);
  if (c == nullptr) return spline_.EvaluateShape(u);
  RegionJet<K, 2> jet(c, s, t);
  if (spline_.basis_form() == BasisForm::kRaw) {
    jet.UseRawDenominator(leaf.origin, leaf.e1, leaf.e2, s, t);
  }
  // F = N / D in the cell's chart (s, t), by the quotient rule.
  const double inv = 1.0 / jet.v[3];
  Eigen::Vector3d f, fs, ft, fss, fst, ftt;
  for (int d = 0; d < 3; ++d) f[d] = jet.v[d] * inv;
  for (int d = 0; d < 3; ++d) {
    fs[d] = (jet.vs[d] - f[d] * jet.vs[3]) * inv;
    ft[d] = (jet.vt[d] - f[d] * jet.vt[3]) * inv;
  }
  for (int d = 0; d < 3; ++d) {
    fss[d] = (jet.vss[d] - 2 * fs[d] * jet.vs[3] - f[d] * jet.vss[3]) * inv;
    fst[d] = (jet.vst[d] - fs[d] * jet.vt[3] - ft[d] * jet.vs[3] -
              f[d] * jet.vst[3]) *
             inv;
    ftt[d] = (jet.vtt[d] - 2 * ft[d] * jet.vt[3] - f[d] * jet.vtt[3]) * inv;
  }
  // The chart of SurfacePoint, phi(u, v) = F(u0 + u e_u + v e_v), is the
  // cell's composed with the central projection y -> y / (y . axis) onto
  // the cube face; its Jacobian J at u0 gives phi's first derivatives, and
  // its second ones up to tangential terms (which the shape ignores).
  Eigen::Vector3d e_u, e_v;
  TangentFrame(u, &e_u, &e_v);
  const double w = u.dot(leaf.axis);
  const auto projected = [&](const Eigen::Vector3d& e) -> Eigen::Vector2d {
    const Eigen::Vector3d dy = (e * w - u * e.dot(leaf.axis)) / (w * w);
    return Eigen::Vector2d(dy.dot(leaf.e1) / leaf.e1.squaredNorm(),
                           dy.dot(leaf.e2) / leaf.e2.squaredNorm());
  };
  const Eigen::Vector2d ju = projected(e_u), jv = projected(e_v);
  const Eigen::Vector3d du = fs * ju[0] + ft * ju[1];
  const Eigen::Vector3d dv = fs * jv[0] + ft * jv[1];
  const auto second = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return Eigen::Vector3d(fss * a[0] * b[0] +
                           fst * (a[0] * b[1] + a[1] * b[0]) +
                           ftt * a[1] * b[1]);
  };
  return ShapeFromDerivatives(f, du, dv, second(ju, ju), second(ju, jv),
                              second(jv, jv));
}

void PiecewiseSurface::Eval(const Eigen::Vector3d& p, Eigen::Vector3d* position,
                            Eigen::Vector3d* normal) const {
  WithDegree(spline_.degree(), [&](auto k) {
    EvalDegree<decltype(k)::value>(p, position, normal);
  });
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

SurfaceShape PiecewiseSurface::EvaluateShape(const Eigen::Vector3d& p) const {
  return WithDegree(spline_.degree(),
                    [&](auto k) { return ShapeDegree<decltype(k)::value>(p); });
}

template <typename EvaluateRow, typename FinishChunk>
void PiecewiseSurface::ByLeaf(const Eigen::MatrixX3d& directions, int width,
                              const EvaluateRow& evaluate,
                              const FinishChunk& finish) const {
  const Eigen::Index rows = directions.rows();
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
  // Leaf by leaf (stable), so that a leaf's regions stay in cache and the
  // regions it lacks are built in one visit; in chunks of up to kChunk rows
  // of that order, whose directions are copied together (x, y, z side by
  // side). The buffers are reused from call to call (fresh pages cost more
  // than the evaluation of a small batch).
  std::unique_ptr<Scratch> scratch;
  {
    std::lock_guard<std::mutex> lock(scratch_mutex_);
    if (!scratch_.empty()) {
      scratch = std::move(scratch_.back());
      scratch_.pop_back();
    }
  }
  if (!scratch) scratch = std::make_unique<Scratch>();
  std::vector<uint32_t>& leaf_of = scratch->leaf_of;
  std::vector<uint32_t>& start = scratch->start;
  std::vector<uint32_t>& order = scratch->order;
  std::vector<double>& sorted = scratch->sorted;
  std::vector<double>& results = scratch->results;
  if (static_cast<Eigen::Index>(leaf_of.size()) < rows) {
    leaf_of.resize(rows);
    order.resize(rows);
  }
  parallel(rows, 4096, [&](Eigen::Index r) {
    double s, t;
    leaf_of[r] =
        static_cast<uint32_t>(Locate(directions.row(r).transpose(), &s, &t));
  });
  start.assign(leaves_.size() + 1, 0);
  for (Eigen::Index r = 0; r < rows; ++r) ++start[leaf_of[r] + 1];
  for (size_t l = 0; l < leaves_.size(); ++l) start[l + 1] += start[l];
  for (Eigen::Index r = 0; r < rows; ++r) {
    order[start[leaf_of[r]]++] = static_cast<uint32_t>(r);
  }
  const Eigen::Index chunk = std::min(kChunk, rows);
  if (static_cast<Eigen::Index>(sorted.size()) < 3 * chunk) {
    sorted.resize(3 * chunk);
  }
  if (static_cast<Eigen::Index>(results.size()) < width * chunk) {
    results.resize(width * chunk);
  }
  for (Eigen::Index begin = 0; begin < rows; begin += kChunk) {
    const Eigen::Index n = std::min(kChunk, rows - begin);
    const uint32_t* rows_of = order.data() + begin;
    parallel(n, 4096, [&](Eigen::Index o) {
      for (int d = 0; d < 3; ++d) sorted[3 * o + d] = directions(rows_of[o], d);
    });
    parallel(n, 256, [&](Eigen::Index o) {
      evaluate(
          o, rows_of[o],
          Eigen::Vector3d(sorted[3 * o], sorted[3 * o + 1], sorted[3 * o + 2]),
          results.data() + width * o);
    });
    finish(n, rows_of, results.data());
  }
  std::lock_guard<std::mutex> lock(scratch_mutex_);
  scratch_.push_back(std::move(scratch));
}

void PiecewiseSurface::EvaluateMany(const Eigen::MatrixX3d& directions,
                                    Eigen::MatrixX3d* positions,
                                    Eigen::MatrixX3d* normals) const {
  const Eigen::Index rows = directions.rows();
  positions->resize(rows, 3);
  if (normals) normals->resize(rows, 3);
  if (rows < 64) {
    for (Eigen::Index r = 0; r < rows; ++r) {
      Eigen::Vector3d x, n;
      Eval(directions.row(r).transpose(), &x, normals ? &n : nullptr);
      positions->row(r) = x.transpose();
      if (normals) normals->row(r) = n.transpose();
    }
    return;
  }
  const int width = normals ? 6 : 3;
  ByLeaf(
      directions, width,
      [&](Eigen::Index, Eigen::Index, const Eigen::Vector3d& p, double* out) {
        Eigen::Vector3d x, n;
        Eval(p, &x, normals ? &n : nullptr);
        for (int d = 0; d < 3; ++d) out[d] = x[d];
        if (normals) {
          for (int d = 0; d < 3; ++d) out[3 + d] = n[d];
        }
      },
      [&](Eigen::Index n, const uint32_t* rows_of, const double* results) {
        // Back to the rows, block of rows by block (counting sort by r >>
        // kBlockBits): the writes of a block stay in cache.
        constexpr int kBlockBits = 12;
        const Eigen::Index blocks = ((rows - 1) >> kBlockBits) + 1;
        thread_local std::vector<uint32_t> kept_start, kept_by_block;
        // This thread's (the parallel loop below runs on others).
        std::vector<uint32_t>& start = kept_start;
        std::vector<uint32_t>& by_block = kept_by_block;
        start.assign(blocks + 1, 0);
        by_block.resize(n);
        for (Eigen::Index o = 0; o < n; ++o) {
          ++start[(rows_of[o] >> kBlockBits) + 1];
        }
        for (Eigen::Index b = 0; b < blocks; ++b) start[b + 1] += start[b];
        for (Eigen::Index o = 0; o < n; ++o) {
          by_block[start[rows_of[o] >> kBlockBits]++] =
              static_cast<uint32_t>(o);
        }
        tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 4096),
                          [&](const tbb::blocked_range<Eigen::Index>& range) {
                            for (Eigen::Index i = range.begin();
                                 i < range.end(); ++i) {
                              const uint32_t o = by_block[i];
                              const double* in = results + width * o;
                              const Eigen::Index r = rows_of[o];
                              for (int d = 0; d < 3; ++d)
                                (*positions)(r, d) = in[d];
                              if (normals) {
                                for (int d = 0; d < 3; ++d)
                                  (*normals)(r, d) = in[3 + d];
                              }
                            }
                          });
      });
}

template <typename Store>
void PiecewiseSurface::ShapesByLeaf(const Eigen::MatrixX3d& directions,
                                    const Store& store) const {
  if (directions.rows() < 64) {
    for (Eigen::Index r = 0; r < directions.rows(); ++r) {
      store(r, EvaluateShape(directions.row(r).transpose()));
    }
    return;
  }
  ByLeaf(
      directions, 0,
      [&](Eigen::Index, Eigen::Index r, const Eigen::Vector3d& p, double*) {
        store(r, EvaluateShape(p));
      },
      [](Eigen::Index, const uint32_t*, const double*) {});
}

void PiecewiseSurface::EvaluateShapeMany(
    const Eigen::MatrixX3d& directions,
    std::vector<SurfaceShape>* shapes) const {
  shapes->resize(directions.rows());
  ShapesByLeaf(directions, [&](Eigen::Index r, const SurfaceShape& shape) {
    (*shapes)[r] = shape;
  });
}

void PiecewiseSurface::EvaluateCurvatureMany(const Eigen::MatrixX3d& directions,
                                             Eigen::VectorXd* gaussian,
                                             Eigen::VectorXd* mean) const {
  gaussian->resize(directions.rows());
  mean->resize(directions.rows());
  ShapesByLeaf(directions, [&](Eigen::Index r, const SurfaceShape& shape) {
    (*gaussian)[r] = shape.gaussian_curvature;
    (*mean)[r] = shape.mean_curvature;
  });
}

}  // namespace sdcb
