// Knot sets with exact degeneracies (co-circular quadruples, great circles,
// symmetric polyhedra), shared by the configuration and basis tests.
#ifndef SDCB_TESTS_TESTING_SPECIAL_KNOTS_H_
#define SDCB_TESTS_TESTING_SPECIAL_KNOTS_H_

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "sdcb/core/common/constants.h"

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
    const double a = 2 * kPi * i / m;
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
    const double theta = kPi * r / (rings + 1);
    for (int j = 0; j < per_ring; ++j) {
      const double a = 2 * kPi * j / per_ring;
      rows.emplace_back(std::sin(theta) * std::cos(a),
                        std::sin(theta) * std::sin(a), std::cos(theta));
    }
  }
  rows.emplace_back(0, 0, 1);
  rows.emplace_back(0, 0, -1);
  return FromRows(rows);
}

// Latitude rings at the latitudes `latitudes_deg` (none 0), `per_ring` knots
// each, ring r rotated by r * sqrt(2) rad: every ring is co-circular (many
// co-circular quadruples), but no three knots lie on a great circle (a ring
// is not a great circle, and the irrational rotations keep knots of
// different rings from lining up through the origin).
inline Eigen::MatrixX3d StaggeredRings(const std::vector<double>& latitudes_deg,
                                       int per_ring) {
  std::vector<Eigen::Vector3d> rows;
  for (size_t r = 0; r < latitudes_deg.size(); ++r) {
    const double lat = latitudes_deg[r] * kPi / 180;
    const double offset = std::sqrt(2.0) * static_cast<double>(r + 1);
    for (int j = 0; j < per_ring; ++j) {
      const double a = offset + 2 * kPi * j / per_ring;
      rows.emplace_back(std::cos(lat) * std::cos(a),
                        std::cos(lat) * std::sin(a), std::sin(lat));
    }
  }
  return FromRows(rows);
}

// `n` random knots (seed) plus a copy of knot 0 rotated by `separation` rad
// about a random axis: two knots `separation` apart, the rest generic.
inline Eigen::MatrixX3d RandomWithClosePair(int n, double separation,
                                            unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Vector3d> rows;
  for (int i = 0; i < n; ++i) {
    rows.emplace_back(normal(rng), normal(rng), normal(rng));
    rows.back().normalize();
  }
  Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
  axis = axis.cross(rows[0]).normalized();  // orthogonal to knot 0
  rows.push_back(std::cos(separation) * rows[0] + std::sin(separation) * axis);
  return FromRows(rows);
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_SPECIAL_KNOTS_H_
