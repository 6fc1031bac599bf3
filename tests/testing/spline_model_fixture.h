// Hand-built SplineModels for the format tests: configurations found by the
// brute-force oracle (testing/brute_force_configurations.h), not by
// core/spline/delaunay_configurations.
#ifndef SDCB_TESTS_TESTING_SPLINE_MODEL_FIXTURE_H_
#define SDCB_TESTS_TESTING_SPLINE_MODEL_FIXTURE_H_

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/sphere/unit_vector_grid.h"
#include "sdcb/core/spline/spline_model.h"
#include "testing/brute_force_configurations.h"

namespace sdcb::testing {

// `n` random unit vectors (fixed seed), in general position with
// probability 1.
inline Eigen::MatrixX3d RandomUnitVectors(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Eigen::MatrixX3d out(n, 3);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d v(gauss(rng), gauss(rng), gauss(rng));
    out.row(i) = v.normalized().transpose();
  }
  return out;
}

// A valid model whose numbers exercise bit-exactness: control points include
// -0.0, denormals, the largest and smallest normal doubles.
inline SplineModel MakeTestModel(int degree = 1, int num_knots = 7,
                                 int num_parameters = 5, unsigned seed = 7) {
  SplineModel m;
  m.degree = degree;
  m.knots = RandomUnitVectors(num_knots, seed);
  m.configurations = BruteForceConfigurations(m.knots, degree);
  const int sets = static_cast<int>(m.configurations.sets.size());
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  m.control_points.resize(sets, 3);
  for (int i = 0; i < sets; ++i) {
    for (int c = 0; c < 3; ++c) m.control_points(i, c) = uniform(rng);
  }
  const double special[] = {-0.0,
                            std::numeric_limits<double>::denorm_min(),
                            -2.5e-310,
                            std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::lowest(),
                            std::numeric_limits<double>::min(),
                            1e-300,
                            0.1};
  int s = 0;
  for (int i = 0; i < sets && s < 8; ++i) {
    for (int c = 0; c < 3 && s < 8; ++c) m.control_points(i, c) = special[s++];
  }
  m.transform.scale = 0.1 + 1e-17;
  m.transform.translation = Eigen::Vector3d(-1.5, 1e-320, 3.0 / 7.0);
  FitStatistics& st = m.statistics;
  for (int r = 0; r < 3; ++r) {
    st.rounds.push_back({r, 100 * (r + 1), 90 * (r + 1), 1.0 / (r + 3),
                         2.0 / 3.0 + r, 0.5 / (r + 3), 1.0 / 3.0 + r,
                         0.1 * r + std::numeric_limits<double>::denorm_min()});
  }
  st.final_result = st.rounds.back();
  st.options = {degree, 0.05, 0.45, 100, 0.3, 7,      10,   5000, 0.2,  4.0,
                12.5,   -0.0, 3.0,  5,   12,  100000, true, 2.5,  70000};
  st.error_measure = ErrorMeasure::kDenseTwoSided;
  st.reached_target = true;
  m.source.num_vertices = num_parameters > 0 ? num_parameters : 1234;
  m.source.num_faces = 2 * m.source.num_vertices - 4;
  m.source.hash = 0xfedcba9876543210ULL;
  m.source.file_name = "meshes/bunny \xc3\xa9.off";
  if (num_parameters > 0) {
    m.parameters = RandomUnitVectors(num_parameters, seed + 2);
  }
  return m;
}

// MakeTestModel's model with its knots moved onto the `bits`-bit octahedral
// grid, as a fit with FitOptions::knot_grid_bits makes them (recorded in
// its options), configurations recomputed, control points in
// [-0.6, 0.6]^3 (quantizable). Coarse grids can make random knots meet.
inline SplineModel MakeGridTestModel(int degree, int num_knots, int bits,
                                     unsigned seed = 7) {
  SplineModel m = MakeTestModel(degree, num_knots, 0, seed);
  for (Eigen::Index i = 0; i < m.knots.rows(); ++i) {
    const Eigen::Vector3d k = m.knots.row(i);
    m.knots.row(i) = DecodeUnitVector(EncodeUnitVector(k, bits), bits);
  }
  m.configurations = BruteForceConfigurations(m.knots, degree);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  m.control_points.resize(
      static_cast<Eigen::Index>(m.configurations.sets.size()), 3);
  for (Eigen::Index i = 0; i < m.control_points.rows(); ++i) {
    for (int c = 0; c < 3; ++c) m.control_points(i, c) = u(rng);
  }
  m.statistics.options.knot_grid_bits = bits;
  return m;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_SPLINE_MODEL_FIXTURE_H_
