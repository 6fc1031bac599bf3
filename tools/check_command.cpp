// sdcb check MESH [--json FILE] [--repair] [--max-file-mb N]
//                 [--max-memory-mb N]: is this mesh something sdcb can fit?
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {

int RunCheck(const std::vector<std::string>& argv) {
  const Args args(argv, Concat({"json"}, kMeshValueOptions),
                  Concat({"quiet"}, kMeshFlagOptions));
  args.RequirePositionals(1, "MESH (usage: sdcb check MESH [--json FILE])");
  const std::string& path = args.positionals()[0];
  const Status outputs = PrepareOutputs({args.Get("json")});
  if (!outputs.ok()) return ReportError(outputs);

  MeshReadInfo read_info;
  StatusOr<TriangleMesh> mesh =
      ReadMesh(path, &read_info, MeshReadLimitsFromArgs(args));
  if (!mesh.ok()) return ReportError(mesh.status());
  const Status repaired = RepairIfAsked(args, path, &*mesh);
  if (!repaired.ok()) return ReportError(repaired);
  StatusOr<MeshTopologyReport> report = AnalyzeMeshTopology(*mesh);
  if (!report.ok()) return ReportError(report.status().WithPrefix(path));
  const MeshTopologyReport& r = *report;
  const std::string problem = DescribeTopologyProblem(r);
  // Self-intersections are tested on meshes that are otherwise fine (in a
  // soup or an open mesh, touching pieces would count); -1 when not tested.
  std::string skipped_because =
      "the mesh is not a closed genus-0 manifold (see the other counts)";
  const long long self_intersections =
      r.ok ? WarnAboutSelfIntersections(path, *mesh, &skipped_because) : -1;

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
    if (self_intersections >= 0) {
      j["self_intersections"] = self_intersections;
    } else {
      j["self_intersections"] = nullptr;
      j["self_intersections_skipped"] = skipped_because;
    }
    j["repaired"] = args.Has("repair");
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
    if (self_intersections >= 0) {
      row("self-intersecting pairs", self_intersections);
    } else {
      std::printf("  %-30s %12s\n", "self-intersecting pairs", "not tested");
    }
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
