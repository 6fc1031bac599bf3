// Are the input's sharp edges sharp in the spline? The spline's normal at 1 %
// of the largest bounding-box side from every feature edge of the mesh
// (core/mesh/feature_curves.h, --feature-angle, default 30), on both of its
// triangles, against the triangle's (tests/testing/feature_normals.h).
// Prints the largest and median angle and the points above 2 degrees.
//
//   feature_normals_bench MODEL.sdcb MESH [SAMPLES] [FEATURE_ANGLE] [OFFSET]
//
// SAMPLES: points of the lattice (default 4,000,000); OFFSET: the distance
// from the edge in percent of the largest side (default 1).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "sdcb/core/mesh/feature_curves.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/feature_normals.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: feature_normals_bench MODEL.sdcb MESH [SAMPLES] "
                 "[FEATURE_ANGLE] [OFFSET_PERCENT]\n");
    return 2;
  }
  const int samples = argc > 3 ? std::atoi(argv[3]) : 4000000;
  const double feature_angle = argc > 4 ? std::atof(argv[4]) : 30.0;
  const double offset = (argc > 5 ? std::atof(argv[5]) : 1.0) / 100.0;
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) {
    std::fprintf(stderr, "%s\n", model.status().message().c_str());
    return 1;
  }
  auto spline = sdcb::SurfaceFromModel(*model);
  auto mesh = sdcb::ReadMesh(argv[2]);
  if (!spline.ok() || !mesh.ok()) {
    std::fprintf(
        stderr, "%s\n",
        (!spline.ok() ? spline.status() : mesh.status()).message().c_str());
    return 1;
  }
  auto features = sdcb::DetectFeatures(*mesh, feature_angle);
  if (!features.ok()) {
    std::fprintf(stderr, "%s\n", features.status().message().c_str());
    return 1;
  }
  // The mesh in the spline's (normalized) frame: largest side 1.
  const Eigen::MatrixX3d vertices =
      model->transform.ToNormalized(mesh->vertices);
  const sdcb::testing::FeatureNormals normals =
      sdcb::testing::MeasureFeatureNormals(*spline, vertices, mesh->faces,
                                           *features, offset, samples);
  const std::vector<double>& angles = normals.angles_degrees;
  if (angles.empty()) {
    std::printf("%s: no feature edge with a point inside its triangles\n",
                argv[2]);
    return 0;
  }
  const long above = std::count_if(angles.begin(), angles.end(),
                                   [](double x) { return x > 2.0; });
  std::printf(
      "%s: %zu feature edges, %zu points at %.3g %% from them: normal angle "
      "max %.3f deg, median %.3f deg, %ld above 2 deg; nearest surface "
      "sample within %.3g %%\n",
      argv[2], features->edges.size(), angles.size(), 100.0 * offset,
      normals.max_degrees, normals.median_degrees, above,
      100.0 * normals.max_sample_gap);
  return 0;
}
