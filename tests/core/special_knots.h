// Knot sets with exact degeneracies (co-circular quadruples, great circles,
// symmetric polyhedra), shared by the configuration and basis tests.
#ifndef SDCB_TESTS_CORE_SPECIAL_KNOTS_H_
#define SDCB_TESTS_CORE_SPECIAL_KNOTS_H_

#include <Eigen/Core>
#include <cmath>
#include <vector>

namespace sdcb::testing {

inline Eigen::MatrixX3d FromRows(const std::vector<Eigen::Vector3d>& rows) {
  Eigen::MatrixX3d m(rows.size(), 3);
  for (size_t i = 0; i < rows.size(); ++i) m.row(i) = rows[i].normalized();
  return m;
}

inline Eigen::MatrixX3d IcosahedronKnots() {
  const double phi = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> rows;
  for (double s : {-1.0, 1.0}) {
    for (double t : {-1.0, 1.0}) {
      rows.emplace_back(0, s, t * phi);
      rows.emplace_back(s, t * phi, 0);
      rows.emplace_back(t * phi, 0, s);
    }
  }
  return FromRows(rows);
}

inline Eigen::MatrixX3d CubeKnots() {
  std::vector<Eigen::Vector3d> rows;
  for (double x : {-1.0, 1.0}) {
    for (double y : {-1.0, 1.0}) {
      for (double z : {-1.0, 1.0}) rows.emplace_back(x, y, z);
    }
  }
  return FromRows(rows);
}

// `m` knots evenly on the equator (exact zeros in z) plus both poles.
inline Eigen::MatrixX3d GreatCirclePlusPoles(int m) {
  std::vector<Eigen::Vector3d> rows;
  for (int i = 0; i < m; ++i) {
    const double a = 2 * M_PI * i / m;
    rows.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  rows.emplace_back(0, 0, 1);
  rows.emplace_back(0, 0, -1);
  return FromRows(rows);
}

// Latitude-longitude grid: rings of co-circular knots, meridians on great
// circles.
inline Eigen::MatrixX3d LatLongGrid(int rings, int per_ring) {
  std::vector<Eigen::Vector3d> rows;
  for (int r = 1; r <= rings; ++r) {
    const double theta = M_PI * r / (rings + 1);
    for (int j = 0; j < per_ring; ++j) {
      const double a = 2 * M_PI * j / per_ring;
      rows.emplace_back(std::sin(theta) * std::cos(a),
                        std::sin(theta) * std::sin(a), std::cos(theta));
    }
  }
  rows.emplace_back(0, 0, 1);
  rows.emplace_back(0, 0, -1);
  return FromRows(rows);
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_CORE_SPECIAL_KNOTS_H_
