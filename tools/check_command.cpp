// sdcb check MESH [--json FILE]: is this mesh something sdcb can fit?
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/io/mesh_reader.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {

int RunCheck(const std::vector<std::string>& argv) {
  const Args args(argv, {"json"}, {"quiet"});
  args.RequirePositionals(1, "MESH (usage: sdcb check MESH [--json FILE])");
  const std::string& path = args.positionals()[0];

  MeshReadInfo read_info;
  StatusOr<TriangleMesh> mesh = ReadMesh(path, &read_info);
  if (!mesh.ok()) return ReportError(mesh.status());
  StatusOr<MeshTopologyReport> report = AnalyzeMeshTopology(*mesh);
  if (!report.ok()) return ReportError(report.status().WithPrefix(path));
  const MeshTopologyReport& r = *report;
  const std::string problem = DescribeTopologyProblem(r);

  if (args.Has("json")) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["vertices"] = r.vertices;
    j["faces"] = r.faces;
    j["polygons_triangulated"] = read_info.triangulated_polygons;
    j["edges"] = r.edges;
    j["boundary_edges"] = r.boundary_edges;
    j["boundary_loops"] = r.boundary_loops;
    j["non_manifold_edges"] = r.non_manifold_edges;
    j["non_manifold_vertices"] = r.non_manifold_vertices;
    j["inconsistently_oriented_edges"] = r.inconsistently_oriented_edges;
    j["components"] = r.components;
    j["euler_characteristic"] = r.euler_characteristic;
    j["genus"] = r.genus;
    j["degenerate_faces"] = r.degenerate_faces;
    j["duplicate_vertices"] = r.duplicate_vertices;
    j["unreferenced_vertices"] = r.unreferenced_vertices;
    j["ok"] = r.ok;
    j["problem"] = problem;
    const Status written = WriteTextOutput(args.Get("json"), j.dump(2) + "\n");
    if (!written.ok()) return ReportError(written);
  }
  if (!args.Has("quiet") && args.Get("json") != "-") {
    std::printf("%s\n", path.c_str());
    auto row = [](const char* name, long long value) {
      std::printf("  %-30s %12lld\n", name, value);
    };
    row("vertices", r.vertices);
    row("faces (triangles)", r.faces);
    if (read_info.triangulated_polygons > 0) {
      row("polygons triangulated", read_info.triangulated_polygons);
    }
    row("edges", r.edges);
    row("boundary edges", r.boundary_edges);
    row("boundary loops", r.boundary_loops);
    row("non-manifold edges", r.non_manifold_edges);
    row("non-manifold vertices", r.non_manifold_vertices);
    row("inconsistently oriented edges", r.inconsistently_oriented_edges);
    row("connected components", r.components);
    row("Euler characteristic", r.euler_characteristic);
    row("genus", r.genus);
    row("degenerate faces", r.degenerate_faces);
    row("duplicate vertices", r.duplicate_vertices);
    row("unreferenced vertices", r.unreferenced_vertices);
    std::printf("  %-30s %12s\n", "ok (closed genus-0 manifold)",
                r.ok ? "yes" : "no");
    std::fflush(stdout);
  }
  if (!r.ok) {
    std::cerr << "sdcb: " << path << ": " << problem << "\n";
    return kExitBadInput;
  }
  return kExitOk;
}

}  // namespace sdcb::cli
