#include "sdcb/core/mesh/mesh_parts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "sdcb/core/common/union_find.h"
#include "sdcb/core/param/parameterization_distortion.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {
namespace {

// 10000 -> "10,000".
std::string GroupDigits(long long n) {
  std::string digits = std::to_string(n < 0 ? -n : n);
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) {
    digits.insert(static_cast<size_t>(i), ",");
  }
  return (n < 0 ? "-" : "") + digits;
}

std::string Count(int n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

// The sentence of PartReport::problem; `too_large`: the part's bounding box
// or area overflows a double.
std::string DescribePartProblem(const PartReport& report, bool too_large) {
  const MeshTopologyReport& t = report.topology;
  const std::string part = "part " + std::to_string(report.number) + " (" +
                           Count(t.faces, "triangle", "triangles") + ")";
  if (t.faces == 0) return part + " has no triangles";
  if (too_large) {
    return part +
           " has coordinates too large for doubles (its area or bounding "
           "box overflows); sdcb fits parts whose area and bounding box are "
           "finite";
  }
  if (report.area == 0.0 && t.degenerate_faces < t.faces) {
    return part +
           " has coordinates too small for doubles (its area underflows to "
           "0); sdcb fits parts with area";
  }
  if (report.area == 0.0) {
    return part + " has no area; sdcb fits parts with area";
  }
  if (t.non_manifold_edges > 0 || t.non_manifold_vertices > 0) {
    std::string what;
    if (t.non_manifold_edges > 0) {
      what = Count(t.non_manifold_edges, "edge", "edges") +
             " with three or more triangles";
    }
    if (t.non_manifold_vertices > 0) {
      if (!what.empty()) what += ", ";
      what += Count(t.non_manifold_vertices, "vertex", "vertices") +
              " where several sheets meet";
    }
    return part + " is not manifold (" + what + "); sdcb fits manifold parts";
  }
  if (t.inconsistently_oriented_edges > 0) {
    return part + " is not consistently oriented (" +
           Count(t.inconsistently_oriented_edges, "edge is", "edges are") +
           " used twice in the same direction); sdcb fits consistently "
           "oriented parts";
  }
  if (t.boundary_loops == 0 && t.vertices - t.unreferenced_vertices < 4) {
    return part +
           " is two triangles back to back (a closed surface of 3 vertices, "
           "no volume); sdcb fits closed parts of at least 4 vertices";
  }
  if (t.genus != 0) {
    std::string loops;
    if (t.boundary_loops > 0) {
      loops =
          " and " + Count(t.boundary_loops, "boundary loop", "boundary loops");
    }
    return part + " has genus " + std::to_string(t.genus) + loops +
           "; sdcb fits genus-0 parts";
  }
  if (report.max_vertex_triangles > kMaxVertexTriangles) {
    return part + " has a vertex of " +
           GroupDigits(report.max_vertex_triangles) +
           " triangles (a fan of needles); sdcb fits parts whose vertices "
           "have at most " +
           GroupDigits(kMaxVertexTriangles) +
           " triangles: remesh the fan first";
  }
  if (t.degenerate_faces > 0) {
    return part + " has " +
           Count(t.degenerate_faces, "degenerate (zero-area) triangle",
                 "degenerate (zero-area) triangles") +
           "; sdcb fits parts without degenerate triangles";
  }
  return "";
}

}  // namespace

StatusOr<std::vector<MeshPart>> SplitIntoParts(const TriangleMesh& mesh,
                                               int max_parts) {
  SDCB_RETURN_IF_ERROR(CheckFaceIndices(mesh));
  const int nv = mesh.num_vertices();
  const int nf = mesh.num_faces();
  UnionFind sets(nv);
  for (int f = 0; f < nf; ++f) {
    sets.Union(mesh.faces(f, 0), mesh.faces(f, 1));
    sets.Union(mesh.faces(f, 0), mesh.faces(f, 2));
  }
  // Part numbers in the order of the parts' first triangles.
  std::vector<int> part_of_root(nv, -1);
  std::vector<int> face_part(nf);
  int parts = 0;
  for (int f = 0; f < nf; ++f) {
    int& part = part_of_root[sets.Find(mesh.faces(f, 0))];
    if (part < 0) part = parts++;
    face_part[f] = part;
  }
  if (max_parts > 0 && parts > max_parts) {
    return UnsupportedError("mesh has " + GroupDigits(parts) +
                            " parts, more than --max-parts " +
                            std::to_string(max_parts));
  }

  std::vector<int> vertex_part(nv, -1), local(nv, -1);
  std::vector<int> vertex_count(parts, 0), face_count(parts, 0);
  for (int v = 0; v < nv; ++v) {
    vertex_part[v] = part_of_root[sets.Find(v)];  // -1: unreferenced
    if (vertex_part[v] >= 0) local[v] = vertex_count[vertex_part[v]]++;
  }
  for (int f = 0; f < nf; ++f) ++face_count[face_part[f]];

  std::vector<MeshPart> result(parts);
  for (int p = 0; p < parts; ++p) {
    result[p].mesh.vertices.resize(vertex_count[p], 3);
    result[p].mesh.faces.resize(face_count[p], 3);
    result[p].input_vertices.reserve(vertex_count[p]);
    result[p].input_faces.reserve(face_count[p]);
  }
  for (int v = 0; v < nv; ++v) {
    if (vertex_part[v] < 0) continue;
    MeshPart& part = result[vertex_part[v]];
    part.mesh.vertices.row(local[v]) = mesh.vertices.row(v);
    part.input_vertices.push_back(v);
  }
  for (int f = 0; f < nf; ++f) {
    MeshPart& part = result[face_part[f]];
    const int row = static_cast<int>(part.input_faces.size());
    for (int k = 0; k < 3; ++k) {
      part.mesh.faces(row, k) = local[mesh.faces(f, k)];
    }
    part.input_faces.push_back(f);
  }
  return result;
}

StatusOr<PartReport> ReportPart(const MeshPart& part, int number) {
  PartReport report;
  report.number = number;
  SDCB_ASSIGN_OR_RETURN(report.topology, AnalyzeMeshTopology(part.mesh));
  report.closed = report.topology.boundary_edges == 0;
  std::vector<int> triangles(part.mesh.num_vertices(), 0);
  for (Eigen::Index f = 0; f < part.mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) ++triangles[part.mesh.faces(f, k)];
  }
  for (const int n : triangles) {
    report.max_vertex_triangles = std::max(report.max_vertex_triangles, n);
  }
  // The fit's own tests of the coordinates, by the fit's functions: the
  // parameterization's area scale (a total area > 0 and finite) and the
  // normalized frame (a finite bounding box of more than one point).
  report.area = VertexAreas(part.mesh).sum();
  const bool area_usable = AreaScaleToUnitSphere(part.mesh).ok();
  if (!area_usable && report.area != 0.0) {
    report.area = std::numeric_limits<double>::infinity();  // overflowed
  }
  const bool too_large =
      (!area_usable && report.area != 0.0) ||
      (area_usable && !ComputeNormalizingTransform(part.mesh).ok());
  report.problem = DescribePartProblem(report, too_large);
  return report;
}

}  // namespace sdcb
