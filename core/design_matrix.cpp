#include "core/design_matrix.h"

#include <vector>

namespace sdcb {

DesignMatrix BuildDesignMatrix(const DcbBasis& basis,
                               const Eigen::MatrixX3d& points,
                               const DesignMatrixOptions& options) {
  const Eigen::Index rows = points.rows();
  // Each row is computed independently into its own slot; assembly below is
  // sequential, so the bytes do not depend on scheduling.
  std::vector<std::vector<BasisValue>> row_values(rows);
  basis.ParallelForEachPoint(points, [&](Eigen::Index r) {
    const Eigen::Vector3d p = points.row(r).transpose();
    if (options.normalized) {
      basis.NormalizedValues(p, &row_values[r]);
    } else {
      basis.NonzeroValues(p, &row_values[r]);
    }
  });
  DesignMatrix a(rows, basis.size());
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

}  // namespace sdcb
