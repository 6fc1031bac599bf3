// A closed genus-0 surface with a thin part of known proportions: the unit
// sphere with a round-tipped finger of radius r and length `length` along
// +z (a capsule from z = 0; the two radius profiles joined by a smooth
// maximum, so the base is filleted), a surface of revolution triangulated
// in rings of edges about h long, zipped by angle; oriented outward.
// bench/thin_part_bench.cpp fits it for growing length / r.
#ifndef SDCB_TESTS_TESTING_FINGER_MESH_H_
#define SDCB_TESTS_TESTING_FINGER_MESH_H_

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::testing {

// The radius of the surface of revolution at height z: a smooth maximum
// (12-norm) of the unit sphere's and the capsule's radii. The capsule
// starts at z = 0 and ends at `top`.
inline double FingerRadius(double z, double r, double top) {
  const double sphere = std::abs(z) < 1 ? std::sqrt(1 - z * z) : 0.0;
  double capsule = 0;
  if (z >= 0 && z <= top) {
    const double d = z - (top - r);
    capsule = d <= 0 ? r : std::sqrt(std::max(0.0, r * r - d * d));
  }
  return std::pow(std::pow(sphere, 12) + std::pow(capsule, 12), 1.0 / 12);
}

inline TriangleMesh FingerMesh(double r, double length, double h) {
  const double top = std::sqrt(1 - r * r) + length;
  // The profile (z, radius) from the south pole to the tip, by arc length.
  const int dense = 400000;
  std::vector<double> zs(dense + 1), rs(dense + 1), s(dense + 1, 0.0);
  for (int i = 0; i <= dense; ++i) {
    zs[i] = -1 + (top + 1) * i / dense;
    rs[i] = FingerRadius(zs[i], r, top);
    if (i > 0)
      s[i] = s[i - 1] + std::hypot(zs[i] - zs[i - 1], rs[i] - rs[i - 1]);
  }
  const int rings = std::max(4, static_cast<int>(std::lround(s[dense] / h)));
  std::vector<Eigen::Vector3d> v = {{0, 0, -1}};
  std::vector<std::vector<int>> ring_vertices;
  std::vector<std::vector<double>> ring_angles;
  int at = 0;
  for (int k = 1; k < rings; ++k) {
    const double target = s[dense] * k / rings;
    while (s[at + 1] < target) ++at;
    const double t = (target - s[at]) / (s[at + 1] - s[at]);
    const double z = zs[at] + t * (zs[at + 1] - zs[at]);
    const double radius = rs[at] + t * (rs[at + 1] - rs[at]);
    const int n =
        std::max(3, static_cast<int>(std::lround(2 * kPi * radius / h)));
    const double offset = 0.5 * (k % 2);
    std::vector<int> ids;
    std::vector<double> angles;
    for (int j = 0; j < n; ++j) {
      const double a = 2 * kPi * (j + offset) / n;
      ids.push_back(static_cast<int>(v.size()));
      angles.push_back(a);
      v.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
    }
    ring_vertices.push_back(ids);
    ring_angles.push_back(angles);
  }
  const int tip = static_cast<int>(v.size());
  v.emplace_back(0, 0, top);
  std::vector<Eigen::Vector3i> f;
  const std::vector<int>& first = ring_vertices.front();
  const int n0 = static_cast<int>(first.size());
  for (int j = 0; j < n0; ++j) f.emplace_back(0, first[(j + 1) % n0], first[j]);
  // Consecutive rings zipped by angle: the next triangle advances the ring
  // whose next vertex comes first.
  for (size_t k = 0; k + 1 < ring_vertices.size(); ++k) {
    const std::vector<int>& a = ring_vertices[k];
    const std::vector<int>& b = ring_vertices[k + 1];
    const int na = static_cast<int>(a.size()), nb = static_cast<int>(b.size());
    auto angle = [](const std::vector<double>& angles, int i) {
      const int n = static_cast<int>(angles.size());
      return angles[i % n] + 2 * kPi * (i / n);
    };
    int i = 0, j = 0;
    while (i < na || j < nb) {
      if (j >= nb || (i < na && angle(ring_angles[k], i + 1) <=
                                    angle(ring_angles[k + 1], j + 1))) {
        f.emplace_back(a[i % na], a[(i + 1) % na], b[j % nb]);
        ++i;
      } else {
        f.emplace_back(a[i % na], b[(j + 1) % nb], b[j % nb]);
        ++j;
      }
    }
  }
  const std::vector<int>& last = ring_vertices.back();
  const int nl = static_cast<int>(last.size());
  for (int j = 0; j < nl; ++j) f.emplace_back(tip, last[j], last[(j + 1) % nl]);
  TriangleMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (size_t i = 0; i < v.size(); ++i) mesh.vertices.row(i) = v[i];
  mesh.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i) mesh.faces.row(i) = f[i];
  return mesh;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_FINGER_MESH_H_
