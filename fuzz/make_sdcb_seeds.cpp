// Writes small valid .sdcb models (degrees 0..3, a few knots, with and
// without sphere parameters; format version 3's grid knots and predicted
// control points, version 2's quantized ones; version 4's models of two
// named parts with trim loops, and kept parts) into the directory given as the
// argument: the seeds of corpus/sdcb. The models come from the tests' fixture,
// whose configurations are found by brute force.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/spline_model_fixture.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_sdcb_seeds DIR\n");
    return 2;
  }
  const struct {
    int degree, knots, parameters;
  } models[] = {{0, 8, 0}, {1, 6, 3}, {1, 8, 0}, {2, 8, 2}, {3, 9, 0}};
  for (const auto& m : models) {
    const auto bytes = sdcb::SerializeSdcb(
        sdcb::testing::MakeTestModel(m.degree, m.knots, m.parameters));
    if (!bytes.ok()) {
      std::fprintf(stderr, "%s\n", bytes.status().message().c_str());
      return 1;
    }
    const std::string path = std::string(argv[1]) + "/degree" +
                             std::to_string(m.degree) + "_knots" +
                             std::to_string(m.knots) + ".sdcb";
    std::ofstream(path, std::ios::binary) << *bytes;
    std::printf("%s: %zu bytes\n", path.c_str(), bytes->size());
  }
  // Format version 3: knots on a grid (QKNT), control points predicted and
  // range-coded (PCTL); and version 2's quantized chunk (QCTL).
  const struct {
    const char* name;
    int degree, knots, quantize_bits, format_version;
  } quantized[] = {{"v3_grid_knots_degree2", 2, 9, 0, 3},
                   {"v3_grid_knots_pctl_degree1", 1, 8, 12, 3},
                   {"v3_grid_knots_pctl_degree3", 3, 9, 20, 3},
                   {"v2_qctl_degree2", 2, 8, 10, 2}};
  for (const auto& q : quantized) {
    sdcb::SdcbWriteOptions options;
    options.quantize_bits = q.quantize_bits;
    options.format_version = q.format_version;
    const auto bytes = sdcb::SerializeSdcb(
        sdcb::testing::MakeGridTestModel(q.degree, q.knots, 16), options);
    if (!bytes.ok()) {
      std::fprintf(stderr, "%s\n", bytes.status().message().c_str());
      return 1;
    }
    const std::string path = std::string(argv[1]) + "/" + q.name + ".sdcb";
    std::ofstream(path, std::ios::binary) << *bytes;
    std::printf("%s: %zu bytes\n", path.c_str(), bytes->size());
  }
  // Format version 4: two parts, named, the second with two trim loops (a
  // square around +z and a triangle); lossless, and quantized on the grid.
  const double h = std::sqrt(0.5);
  sdcb::TrimLoop square, triangle;
  square.points.resize(4, 3);
  square.points << h, 0, h, 0, h, h, -h, 0, h, 0, -h, h;
  triangle.points.resize(3, 3);
  triangle.points << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  for (const int quantize_bits : {0, 12}) {
    sdcb::Model model;
    model.parts.resize(2);
    model.parts[0].name = "body";
    model.parts[0].spline = sdcb::testing::MakeGridTestModel(1, 8, 16, 3);
    model.parts[1].name = "lid \xc3\xa9";
    model.parts[1].spline = sdcb::testing::MakeGridTestModel(2, 8, 12, 5);
    model.parts[1].trims = {square, triangle};
    model.source = model.parts[0].spline.source;
    model.source.file_name = "two parts.obj";
    sdcb::SdcbWriteOptions options;
    options.quantize_bits = quantize_bits;
    const auto bytes = sdcb::SerializeSdcbModel(model, options);
    if (!bytes.ok()) {
      std::fprintf(stderr, "%s\n", bytes.status().message().c_str());
      return 1;
    }
    const std::string path = std::string(argv[1]) + "/v4_two_parts_trimmed" +
                             (quantize_bits ? "_pctl" : "") + ".sdcb";
    std::ofstream(path, std::ios::binary) << *bytes;
    std::printf("%s: %zu bytes\n", path.c_str(), bytes->size());
  }
  // Format version 4 with kept parts: a fitted part, a kept non-manifold
  // fan of three triangles on one edge (doubles: 24-byte vertices) and a
  // kept tetrahedron of float coordinates (12-byte vertices).
  {
    sdcb::Model model;
    model.parts.resize(3);
    model.parts[0].spline = sdcb::testing::MakeGridTestModel(1, 8, 16, 3);
    sdcb::KeptMesh fan;
    fan.mesh.vertices.resize(5, 3);
    fan.mesh.vertices << 0, 0, 0, 1, 0, 0, 0.1, 1, 0, 0.3, -0.7, 0.2, 0.5, 0.1,
        0.9;
    fan.mesh.faces.resize(3, 3);
    fan.mesh.faces << 0, 1, 2, 1, 0, 3, 0, 1, 4;
    fan.reason =
        "part 2 (3 triangles) is not manifold (1 edge with more than two "
        "triangles); sdcb fits manifold parts";
    model.parts[1].kept = fan;
    model.parts[2].name = "tetra";
    sdcb::KeptMesh tetra;
    tetra.mesh.vertices.resize(4, 3);
    tetra.mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
    tetra.mesh.faces.resize(4, 3);
    tetra.mesh.faces << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
    tetra.reason = "part 3: the fit failed";
    model.parts[2].kept = tetra;
    model.source = model.parts[0].spline.source;
    model.source.file_name = "kept parts.obj";
    const auto bytes =
        sdcb::SerializeSdcbModel(model, sdcb::SdcbWriteOptions());
    if (!bytes.ok()) {
      std::fprintf(stderr, "%s\n", bytes.status().message().c_str());
      return 1;
    }
    const std::string path = std::string(argv[1]) + "/v4_kept_parts.sdcb";
    std::ofstream(path, std::ios::binary) << *bytes;
    std::printf("%s: %zu bytes\n", path.c_str(), bytes->size());
  }
  return 0;
}
