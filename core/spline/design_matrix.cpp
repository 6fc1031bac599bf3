#include "sdcb/core/spline/design_matrix.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

namespace {

// Packs per-row (column, value) lists into a row-major sparse matrix.
DesignMatrix Assemble(const std::vector<std::vector<BasisValue>>& row_values,
                      int cols) {
  const Eigen::Index rows = static_cast<Eigen::Index>(row_values.size());
  DesignMatrix a(rows, cols);
  Eigen::Index at = 0;
  for (Eigen::Index r = 0; r < rows; ++r) {
    a.outerIndexPtr()[r] = static_cast<int>(at);
    at += static_cast<Eigen::Index>(row_values[r].size());
  }
  a.outerIndexPtr()[rows] = static_cast<int>(at);
  a.resizeNonZeros(at);
  // Each row into its own slots: in parallel, the same bytes.
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, rows, 1024),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      for (Eigen::Index r = range.begin(); r < range.end();
                           ++r) {
                        Eigen::Index k = a.outerIndexPtr()[r];
                        for (const BasisValue& v : row_values[r]) {
                          a.innerIndexPtr()[k] = v.index;
                          a.valuePtr()[k] = v.value;
                          ++k;
                        }
                      }
                    });
  return a;
}

}  // namespace

DesignMatrix BuildDesignMatrix(const DcbBasis& basis,
                               const Eigen::MatrixX3d& points,
                               const DesignMatrixOptions& options) {
  // Each row is computed independently, in the basis's locality order (as
  // ParallelForEachPoint), by chunks of consecutive rows of that order whose
  // values share one buffer (one allocation per chunk, not per row); rows
  // are then packed in row order, so the bytes do not depend on scheduling.
  constexpr Eigen::Index kChunk = 128;
  const Eigen::Index n = points.rows();
  const std::vector<Eigen::Index> order = basis.LocalityOrder(points);
  const Eigen::Index chunks = (n + kChunk - 1) / kChunk;
  std::vector<std::vector<BasisValue>> chunk_values(chunks);
  std::vector<int> row_chunk(n), row_start(n), row_count(n);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, chunks, 1),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      thread_local std::vector<BasisValue> row;
                      for (Eigen::Index c = range.begin(); c < range.end();
                           ++c) {
                        std::vector<BasisValue>& values = chunk_values[c];
                        for (Eigen::Index o = c * kChunk;
                             o < std::min(n, (c + 1) * kChunk); ++o) {
                          const Eigen::Index r = order[o];
                          const Eigen::Vector3d p = points.row(r).transpose();
                          if (options.normalized) {
                            basis.NormalizedValues(p, &row);
                          } else {
                            basis.NonzeroValues(p, &row);
                          }
                          row_chunk[r] = static_cast<int>(c);
                          row_start[r] = static_cast<int>(values.size());
                          row_count[r] = static_cast<int>(row.size());
                          values.insert(values.end(), row.begin(), row.end());
                        }
                      }
                    });
  DesignMatrix a(n, basis.size());
  Eigen::Index at = 0;
  for (Eigen::Index r = 0; r < n; ++r) {
    a.outerIndexPtr()[r] = static_cast<int>(at);
    at += row_count[r];
  }
  a.outerIndexPtr()[n] = static_cast<int>(at);
  a.resizeNonZeros(at);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 1024),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      for (Eigen::Index r = range.begin(); r < range.end();
                           ++r) {
                        const BasisValue* v =
                            chunk_values[row_chunk[r]].data() + row_start[r];
                        Eigen::Index k = a.outerIndexPtr()[r];
                        for (int j = 0; j < row_count[r]; ++j, ++k) {
                          a.innerIndexPtr()[k] = v[j].index;
                          a.valuePtr()[k] = v[j].value;
                        }
                      }
                    });
  return a;
}

DesignMatrix BuildRawDesignMatrix(const DcbBasis& basis,
                                  const Eigen::MatrixX3d& points,
                                  const DesignMatrix* previous,
                                  const std::vector<int>* previous_columns) {
  if (previous == nullptr || previous_columns == nullptr) {
    return BuildDesignMatrix(basis, points, {/*normalized=*/false});
  }
  std::vector<std::vector<BasisValue>> row_values(points.rows());
  basis.ParallelForEachPoint(points, [&](Eigen::Index r) {
    const Eigen::Vector3d p = points.row(r).transpose();
    thread_local std::vector<int> candidates;
    basis.Candidates(p, &candidates);
    const int begin = previous->outerIndexPtr()[r];
    const int end = previous->outerIndexPtr()[r + 1];
    const int* cols = previous->innerIndexPtr();
    std::vector<BasisValue>& out = row_values[r];
    for (int i : candidates) {
      const int old = (*previous_columns)[i];
      double v;
      if (old >= 0) {
        const int* hit = std::lower_bound(cols + begin, cols + end, old);
        v = (hit != cols + end && *hit == old)
                ? previous->valuePtr()[hit - cols]
                : 0.0;
      } else {
        v = basis.Value(i, p);
      }
      if (v != 0.0) out.push_back({i, v});
    }
  });
  return Assemble(row_values, basis.size());
}

DesignMatrix NormalizeRows(const DesignMatrix& raw) {
  DesignMatrix a = raw;
  for (Eigen::Index r = 0; r < a.outerSize(); ++r) {
    double sum = 0.0;
    for (DesignMatrix::InnerIterator it(a, r); it; ++it) sum += it.value();
    for (DesignMatrix::InnerIterator it(a, r); it; ++it) it.valueRef() /= sum;
  }
  return a;
}

DesignMatrix BuildFormDesignMatrix(const DcbBasis& basis,
                                   const Eigen::MatrixX3d& points,
                                   BasisForm form) {
  return BuildDesignMatrix(basis, points,
                           {/*normalized=*/form == BasisForm::kNormalized});
}

namespace {

// The jets of the surface's basis functions b_i = B_i / D at p (unit),
// D = I (normalized) or |x|^k (raw), in the chart frame (e_u, e_v):
// visit(i, du, dv, uu, uv, vv) for every basis function nonzero near p.
template <typename Visit>
void ForEachChartJet(const DcbBasis& basis, const Eigen::Vector3d& p,
                     BasisForm form, JetOrder order, Visit visit) {
  thread_local std::vector<int> candidates;
  thread_local std::vector<ScalarJet> jets;
  basis.Candidates(p, &candidates);
  jets.resize(candidates.size());
  const double k = basis.degree();
  ScalarJet d;
  for (size_t j = 0; j < candidates.size(); ++j) {
    jets[j] = basis.Evaluate(candidates[j], p, order);
    if (form == BasisForm::kNormalized) {
      d.value += jets[j].value;
      d.gradient += jets[j].gradient;
      d.hessian += jets[j].hessian;
    }
  }
  if (form == BasisForm::kRaw) {
    d.value = 1.0;
    d.gradient = k * p;
    d.hessian =
        k * Eigen::Matrix3d::Identity() + k * (k - 2) * p * p.transpose();
  }
  Eigen::Vector3d e_u, e_v;
  TangentFrame(p, &e_u, &e_v);
  const double inv = 1.0 / d.value;
  for (size_t j = 0; j < candidates.size(); ++j) {
    const ScalarJet& b = jets[j];
    if (b.value == 0.0 && b.gradient.isZero(0.0) && b.hessian.isZero(0.0)) {
      continue;
    }
    // Quotient rule for b / D.
    const double q = b.value * inv;
    const Eigen::Vector3d g = (b.gradient - q * d.gradient) * inv;
    const Eigen::Matrix3d h =
        (b.hessian - q * d.hessian - g * d.gradient.transpose() -
         d.gradient * g.transpose()) *
        inv;
    visit(candidates[j], e_u.dot(g), e_v.dot(g), e_u.dot(h * e_u),
          e_u.dot(h * e_v), e_v.dot(h * e_v));
  }
}

}  // namespace

ChartHessianRows BuildChartHessianRows(const DcbBasis& basis,
                                       const Eigen::MatrixX3d& points,
                                       BasisForm form) {
  const Eigen::Index n = points.rows();
  std::vector<std::vector<BasisValue>> uu(n), uv(n), vv(n);
  basis.ParallelForEachPoint(points, [&](Eigen::Index r) {
    ForEachChartJet(
        basis, points.row(r).transpose().normalized(), form, JetOrder::kHessian,
        [&](int i, double, double, double duu, double duv, double dvv) {
          uu[r].push_back({i, duu});
          uv[r].push_back({i, duv});
          vv[r].push_back({i, dvv});
        });
  });
  ChartHessianRows out;
  out.uu = Assemble(uu, basis.size());
  out.uv = Assemble(uv, basis.size());
  out.vv = Assemble(vv, basis.size());
  return out;
}

ChartGradientRows BuildChartGradientRows(const DcbBasis& basis,
                                         const Eigen::MatrixX3d& points,
                                         BasisForm form) {
  const Eigen::Index n = points.rows();
  std::vector<std::vector<BasisValue>> u(n), v(n);
  basis.ParallelForEachPoint(points, [&](Eigen::Index r) {
    ForEachChartJet(basis, points.row(r).transpose().normalized(), form,
                    JetOrder::kGradient,
                    [&](int i, double du, double dv, double, double, double) {
                      u[r].push_back({i, du});
                      v[r].push_back({i, dv});
                    });
  });
  ChartGradientRows out;
  out.u = Assemble(u, basis.size());
  out.v = Assemble(v, basis.size());
  return out;
}

DesignMatrix StackScaledRows(
    const std::vector<std::pair<const DesignMatrix*, const Eigen::VectorXd*>>&
        parts) {
  Eigen::Index rows = 0, nonzeros = 0, cols = 0;
  for (const auto& [m, s] : parts) {
    rows += m->rows();
    nonzeros += m->nonZeros();
    cols = m->cols();
  }
  DesignMatrix out(rows, cols);
  out.resizeNonZeros(nonzeros);
  Eigen::Index at = 0, row = 0;
  for (const auto& [m, s] : parts) {
    for (Eigen::Index r = 0; r < m->rows(); ++r, ++row) {
      out.outerIndexPtr()[row] = static_cast<int>(at);
      const double scale = s != nullptr ? (*s)[r] : 1.0;
      for (DesignMatrix::InnerIterator it(*m, r); it; ++it, ++at) {
        out.innerIndexPtr()[at] = static_cast<int>(it.col());
        out.valuePtr()[at] = scale * it.value();
      }
    }
  }
  out.outerIndexPtr()[row] = static_cast<int>(at);
  return out;
}

}  // namespace sdcb
