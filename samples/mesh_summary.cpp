// Sample: read a mesh with the installed sdcb package and print its topology.
//   mesh_summary MESH
#include <sdcb/core/mesh/mesh_topology.h>
#include <sdcb/io/mesh/mesh_reader.h>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: mesh_summary MESH\n");
    return 2;
  }
  sdcb::StatusOr<sdcb::TriangleMesh> mesh = sdcb::ReadMesh(argv[1]);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
    return 1;
  }
  sdcb::StatusOr<sdcb::MeshTopologyReport> report =
      sdcb::AnalyzeMeshTopology(*mesh);
  if (!report.ok()) {
    std::fprintf(stderr, "%s\n", report.status().message().c_str());
    return 1;
  }
  std::printf("%s: %d vertices, %d faces, genus %d, %s\n", argv[1],
              report->vertices, report->faces, report->genus,
              report->ok ? "ok" : "not a closed genus-0 mesh");
  return report->ok ? 0 : 1;
}
