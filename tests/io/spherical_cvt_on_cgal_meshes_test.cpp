// core/spherical_cvt.* on an irregular spherical mesh: CGAL's sphere966.off
// pushed onto the unit sphere after centering (it lives in the io binary
// because it reads a file). Closed-form energies check the quadrature on
// uneven triangles.
#include <gtest/gtest.h>

#include <cmath>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/knots/spherical_cvt.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

SphericalDensity NormalizedSphere966() {
  const auto mesh = ReadMesh(testing::MeshPath("sphere966.off"));
  EXPECT_TRUE(mesh.ok()) << mesh.status().message();
  const Eigen::RowVector3d center = mesh->vertices.colwise().mean();
  const Eigen::MatrixX3d unit =
      (mesh->vertices.rowwise() - center).rowwise().normalized();
  return {unit, mesh->faces, Eigen::VectorXd::Ones(unit.rows())};
}

TEST(SphericalCvtOnCgalMeshesTest, OneKnotEnergyMatchesClosedForm) {
  SphericalDensity density = NormalizedSphere966();
  // One knot t: E = int rho |p - t|^2 = int rho (2 - 2 p.t). For rho = 1
  // that is 8 pi for any t; for rho = 1 + p.t it is 16 pi / 3. The mesh's
  // flat triangles (~7 degrees) make rho slightly non-linear on the sphere.
  const Eigen::RowVector3d t = Eigen::RowVector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::MatrixX3d knot = t;
  auto placed = PlaceKnots(density, knot, 0);
  ASSERT_TRUE(placed.ok()) << placed.status().message();
  EXPECT_NEAR(placed->final_energy, 8 * kPi, 1e-3 * 8 * kPi);
  density.values = (density.sphere_vertices * t.transpose()).array() + 1;
  placed = PlaceKnots(density, knot, 0);
  ASSERT_TRUE(placed.ok());
  EXPECT_NEAR(placed->final_energy, 16 * kPi / 3, 5e-3 * 16 * kPi / 3);
}

TEST(SphericalCvtOnCgalMeshesTest, PlacesKnotsOnAnIrregularMesh) {
  const SphericalDensity density = NormalizedSphere966();
  const auto placed = PlaceKnots(density, Eigen::MatrixX3d(0, 3), 50);
  ASSERT_TRUE(placed.ok()) << placed.status().message();
  const auto& e = placed->energy_history;
  for (size_t i = 1; i < e.size(); ++i) ASSERT_LE(e[i], e[i - 1] * (1 + 1e-12));
  // Within 6% of the hexagonal-quantizer energy 2 G (4 pi)^2 / N.
  const double hexagonal =
      2 * 5 / (36 * std::sqrt(3.0)) * std::pow(4 * kPi, 2) / 50;
  EXPECT_NEAR(placed->final_energy, hexagonal, 0.06 * hexagonal);
}

}  // namespace
}  // namespace sdcb
