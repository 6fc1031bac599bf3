#include "sdcb/core/spline/design_matrix.h"

#include <algorithm>
#include <vector>

namespace sdcb {

namespace {

// Packs per-row (column, value) lists into a row-major sparse matrix.
DesignMatrix Assemble(const std::vector<std::vector<BasisValue>>& row_values,
                      int cols) {
  const Eigen::Index rows = static_cast<Eigen::Index>(row_values.size());
  DesignMatrix a(rows, cols);
  Eigen::Index nonzeros = 0;
  for (const auto& row : row_values) nonzeros += row.size();
  a.resizeNonZeros(nonzeros);
  Eigen::Index at = 0;
  for (Eigen::Index r = 0; r < rows; ++r) {
    a.outerIndexPtr()[r] = static_cast<int>(at);
    for (const BasisValue& v : row_values[r]) {
      a.innerIndexPtr()[at] = v.index;
      a.valuePtr()[at] = v.value;
      ++at;
    }
  }
  a.outerIndexPtr()[rows] = static_cast<int>(at);
  return a;
}

}  // namespace

DesignMatrix BuildDesignMatrix(const DcbBasis& basis,
                               const Eigen::MatrixX3d& points,
                               const DesignMatrixOptions& options) {
  // Each row is computed independently into its own slot; assembly is
  // sequential, so the bytes do not depend on scheduling.
  std::vector<std::vector<BasisValue>> row_values(points.rows());
  basis.ParallelForEachPoint(points, [&](Eigen::Index r) {
    const Eigen::Vector3d p = points.row(r).transpose();
    if (options.normalized) {
      basis.NormalizedValues(p, &row_values[r]);
    } else {
      basis.NonzeroValues(p, &row_values[r]);
    }
  });
  return Assemble(row_values, basis.size());
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

}  // namespace sdcb
