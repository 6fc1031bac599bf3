// Prints the size of a mesh compressed by Draco (what a user would otherwise
// ship instead of a .sdcb model): positions quantized to 14 bits (default
// 14 here, as the comparison in docs/FORMAT.md), connectivity by Draco's
// default (edgebreaker), at draco_encoder's default compression level 7
// (encoding speed 3) and at its best, level 10 (speed 0). Not run by CI.
// Usage: draco_size_bench MESH [QUANTIZATION_BITS]
// Output: one line "draco MESH: V vertices, F faces, qp Q: cl7 N bytes, cl10
// N bytes" (bench/format_sizes.sh reads it).
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "sdcb/io/mesh_reader.h"

namespace {

// The mesh as a Draco mesh, point i = vertex i (no merging of vertices that
// share a position: the same mesh the fit reads).
std::unique_ptr<draco::Mesh> ToDraco(const sdcb::TriangleMesh& m) {
  auto mesh = std::make_unique<draco::Mesh>();
  mesh->set_num_points(static_cast<uint32_t>(m.num_vertices()));
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3,
                draco::DT_FLOAT32, false, 3 * sizeof(float), 0);
  const int id = mesh->AddAttribute(position, /*identity_mapping=*/true,
                                    static_cast<uint32_t>(m.num_vertices()));
  for (int v = 0; v < m.num_vertices(); ++v) {
    const float xyz[3] = {static_cast<float>(m.vertices(v, 0)),
                          static_cast<float>(m.vertices(v, 1)),
                          static_cast<float>(m.vertices(v, 2))};
    mesh->attribute(id)->SetAttributeValue(draco::AttributeValueIndex(v), xyz);
  }
  for (int f = 0; f < m.num_faces(); ++f) {
    mesh->AddFace({draco::PointIndex(m.faces(f, 0)),
                   draco::PointIndex(m.faces(f, 1)),
                   draco::PointIndex(m.faces(f, 2))});
  }
  return mesh;
}

long EncodedBytes(const draco::Mesh& mesh, int bits, int speed) {
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, bits);
  encoder.SetSpeedOptions(speed, speed);
  draco::EncoderBuffer buffer;
  const draco::Status s = encoder.EncodeMeshToBuffer(mesh, &buffer);
  if (!s.ok()) {
    std::fprintf(stderr, "draco: %s\n", s.error_msg());
    std::exit(1);
  }
  return static_cast<long>(buffer.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: draco_size_bench MESH [QUANTIZATION_BITS]\n");
    return 2;
  }
  const std::string path = argv[1];
  const int bits = argc > 2 ? std::atoi(argv[2]) : 14;
  sdcb::StatusOr<sdcb::TriangleMesh> mesh = sdcb::ReadMesh(path);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
    return 1;
  }
  const std::unique_ptr<draco::Mesh> d = ToDraco(*mesh);
  std::printf(
      "draco %s: %d vertices, %d faces, qp %d: cl7 %ld bytes, cl10 %ld "
      "bytes\n",
      path.c_str(), mesh->num_vertices(), mesh->num_faces(), bits,
      EncodedBytes(*d, bits, 3), EncodedBytes(*d, bits, 0));
  return 0;
}
