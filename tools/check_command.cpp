// sdcb check MESH [--json FILE] [--repair] [--max-parts N] [--max-file-mb N]
//                 [--max-memory-mb N]: can sdcb fit every part of this mesh?
#include <climits>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "sdcb/core/mesh/mesh_parts.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/mesh/self_intersections.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {

namespace {

// What check found beyond the whole mesh's topology: the parts (empty when
// there are none or too many), whether every part can be fitted and, if
// not, the sentence saying why.
struct PartsVerdict {
  std::vector<MeshPart> meshes;
  std::vector<PartReport> parts;
  bool split = false;  // false: more parts than --max-parts
  bool ok = false;
  std::string problem;
};

StatusOr<PartsVerdict> JudgeParts(const TriangleMesh& mesh, int max_parts) {
  PartsVerdict verdict;
  StatusOr<std::vector<MeshPart>> parts = SplitIntoParts(mesh, max_parts);
  if (!parts.ok()) {
    if (parts.status().code() != StatusCode::kUnsupported) {
      return parts.status();
    }
    verdict.problem = parts.status().message();
    return verdict;
  }
  verdict.split = true;
  verdict.meshes = std::move(parts).value();
  for (size_t i = 0; i < verdict.meshes.size(); ++i) {
    SDCB_ASSIGN_OR_RETURN(
        PartReport report,
        ReportPart(verdict.meshes[i], static_cast<int>(i) + 1));
    if (verdict.problem.empty()) verdict.problem = report.problem;
    verdict.parts.push_back(std::move(report));
  }
  if (verdict.parts.empty()) verdict.problem = "mesh has no triangles";
  verdict.ok = verdict.problem.empty();
  return verdict;
}

std::string PartLine(const PartReport& p) {
  const MeshTopologyReport& t = p.topology;
  std::string line = "part " + std::to_string(p.number) + ": " +
                     std::to_string(t.faces) +
                     (t.faces == 1 ? " triangle, " : " triangles, ") +
                     std::to_string(t.vertices) +
                     (t.vertices == 1 ? " vertex, " : " vertices, ");
  line += p.closed ? "closed"
                   : "open (" + std::to_string(t.boundary_loops) +
                         (t.boundary_loops == 1 ? " boundary loop)"
                                                : " boundary loops)");
  line += ", genus " + std::to_string(t.genus);
  line += p.fittable() ? ", fittable" : ", not fittable";
  return line;
}

}  // namespace

int RunCheck(const std::vector<std::string>& argv) {
  const Args args(argv, Concat({"json", "max-parts"}, kMeshValueOptions),
                  Concat({"quiet"}, kMeshFlagOptions));
  args.RequirePositionals(
      1, "MESH (usage: sdcb check MESH [--json FILE] [--max-parts N])");
  const std::string& path = args.positionals()[0];
  const int max_parts = args.GetInt("max-parts", kDefaultMaxParts, 0, INT_MAX);
  const Status outputs = PrepareOutputs({args.Get("json")});
  if (!outputs.ok()) return ReportError(outputs);

  MeshIntakeNotes notes;
  StatusOr<TriangleMesh> mesh = ReadMeshToFit(args, path, &notes);
  if (!mesh.ok()) return ReportError(mesh.status());
  const MeshReadInfo& read_info = notes.read;
  StatusOr<MeshTopologyReport> report = AnalyzeMeshTopology(*mesh);
  if (!report.ok()) return ReportError(report.status().WithPrefix(path));
  const MeshTopologyReport& r = *report;
  StatusOr<PartsVerdict> verdict = JudgeParts(*mesh, max_parts);
  if (!verdict.ok()) return ReportError(verdict.status().WithPrefix(path));
  const bool ok = verdict->ok;
  const std::string problem = WithSeamHint(verdict->problem, notes.seams);
  // Self-intersections are tested within each part, on meshes whose parts
  // can all be fitted (in a soup, touching pieces would count); -1 when not
  // tested.
  std::string skipped_because = "not every part can be fitted (see the parts)";
  const long long self_intersections =
      ok ? WarnAboutSelfIntersections(
               path, PartsSelfIntersections(verdict->meshes, r.faces),
               &skipped_because)
         : -1;
  const long long turn_backs = CountTurnBackEdges(*mesh);
  if (ok && turn_backs > 0) {
    std::cerr << "sdcb: " << path
              << ": warning: " << TurnBackEdgesText(turn_backs)
              << ": a smooth surface that follows it faces against some of "
                 "them, which a fit measures as folds\n";
  }

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
    j["turn_back_edges"] = turn_backs;
    j["repaired"] = args.Has("repair");
    j["seam_vertices_merged"] = notes.seams.merged_vertices;
    j["seam_vertices_left_apart"] = notes.seams.declined_vertices;
    if (verdict->split) {
      nlohmann::ordered_json parts = nlohmann::ordered_json::array();
      for (const PartReport& p : verdict->parts) {
        nlohmann::ordered_json part;
        part["number"] = p.number;
        part["triangles"] = p.topology.faces;
        part["vertices"] = p.topology.vertices;
        part["closed"] = p.closed;
        part["boundary_loops"] = p.topology.boundary_loops;
        part["genus"] = p.topology.genus;
        part["manifold"] = p.topology.non_manifold_edges == 0 &&
                           p.topology.non_manifold_vertices == 0;
        part["fittable"] = p.fittable();
        part["problem"] = p.problem;
        parts.push_back(std::move(part));
      }
      j["parts"] = std::move(parts);
    } else {
      j["parts"] = nullptr;  // more than --max-parts: `problem` says so
    }
    j["ok"] = ok;
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
    if (notes.seams.merged_vertices > 0) {
      row("vertices merged at seams", notes.seams.merged_vertices);
    }
    if (self_intersections >= 0) {
      row("self-intersecting pairs", self_intersections);
    } else {
      std::printf("  %-30s %12s\n", "self-intersecting pairs", "not tested");
    }
    row("edges turning back", turn_backs);
    if (verdict->split) {
      row("parts", static_cast<long long>(verdict->parts.size()));
      for (const PartReport& p : verdict->parts) {
        std::printf("  %s\n", PartLine(p).c_str());
      }
    } else {
      std::printf("  %-30s %12s\n", "parts", "not listed");
    }
    std::printf("  %-30s %12s\n", "ok (every part fittable)",
                ok ? "yes" : "no");
    std::fflush(stdout);
  }
  if (!ok) {
    std::cerr << "sdcb: " << path << ": " << problem << "\n";
    return kExitBadInput;
  }
  return kExitOk;
}

}  // namespace sdcb::cli
