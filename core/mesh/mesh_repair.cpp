#include "sdcb/core/mesh/mesh_repair.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <iterator>
#include <vector>

#include "sdcb/core/mesh/cgal_mesh.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/mesh/vertex_welding.h"

namespace sdcb {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Point = CgalKernel::Point_3;
using Polygon = std::vector<std::size_t>;

int CountDegenerateFaces(const CgalMesh& mesh) {
  int n = 0;
  for (CgalMesh::Face_index f : mesh.faces()) {
    n += PMP::is_degenerate_triangle_face(f, mesh);
  }
  return n;
}

// Fills the holes within the options' size; returns their number.
int FillSmallHoles(const MeshRepairOptions& options, CgalMesh* mesh,
                   MeshRepairReport* report) {
  CGAL::Bbox_3 all;
  for (CgalMesh::Vertex_index v : mesh->vertices())
    all += mesh->point(v).bbox();
  const double largest_side =
      std::max({all.xmax() - all.xmin(), all.ymax() - all.ymin(),
                all.zmax() - all.zmin()});
  std::vector<CgalMesh::Halfedge_index> holes;
  PMP::extract_boundary_cycles(*mesh, std::back_inserter(holes));
  int filled = 0;
  for (CgalMesh::Halfedge_index h : holes) {
    int edges = 0;
    CGAL::Bbox_3 box;
    for (CgalMesh::Halfedge_index e : CGAL::halfedges_around_face(h, *mesh)) {
      box += mesh->point(mesh->target(e)).bbox();
      if (++edges > options.max_hole_edges) break;
    }
    const double span =
        std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(),
                  box.zmax() - box.zmin()});
    if (edges > options.max_hole_edges ||
        span > options.max_hole_percent / 100.0 * largest_side) {
      continue;
    }
    // Triangulated and refined, not faired: the fill stays the flat-ish
    // patch --repair always made.
    CgalHoleFillOptions fill;
    fill.refine = true;
    int faces = 0, vertices = 0;
    if (!FillCgalHole(h, fill, mesh, &faces, &vertices)) continue;
    ++filled;
    report->added_faces += faces;
    report->added_vertices += vertices;
  }
  return filled;
}

StatusOr<TriangleMesh> Repair(const TriangleMesh& mesh,
                              const MeshRepairOptions& options,
                              MeshRepairReport* r) {
  // 1. Equal positions become one vertex (numbered in order of first
  // appearance, as CGAL's merge_duplicate_points_in_polygon_soup does).
  const WeldedMesh welded = WeldEqualPositions(mesh);
  r->merged_vertices = welded.merged_vertices();
  std::vector<Point> points;
  points.reserve(welded.mesh.num_vertices());
  for (int v = 0; v < welded.mesh.num_vertices(); ++v) {
    points.emplace_back(welded.mesh.vertices(v, 0), welded.mesh.vertices(v, 1),
                        welded.mesh.vertices(v, 2));
  }
  std::vector<Polygon> polygons(welded.mesh.num_faces());
  for (int f = 0; f < welded.mesh.num_faces(); ++f) {
    polygons[f] = {static_cast<std::size_t>(welded.mesh.faces(f, 0)),
                   static_cast<std::size_t>(welded.mesh.faces(f, 1)),
                   static_cast<std::size_t>(welded.mesh.faces(f, 2))};
  }
  // 2. Faces using a vertex twice; repeated faces (one copy stays), then
  // back-to-back pairs (both go: together they enclose nothing).
  const size_t before = polygons.size();
  polygons.erase(std::remove_if(polygons.begin(), polygons.end(),
                                [](const Polygon& p) {
                                  return p[0] == p[1] || p[1] == p[2] ||
                                         p[0] == p[2];
                                }),
                 polygons.end());
  r->dropped_degenerate_faces = static_cast<int>(before - polygons.size());
  r->dropped_duplicate_faces =
      static_cast<int>(PMP::merge_duplicate_polygons_in_polygon_soup(
          points, polygons,
          CGAL::parameters::erase_all_duplicates(false)
              .require_same_orientation(true)));
  r->dropped_duplicate_faces +=
      static_cast<int>(PMP::merge_duplicate_polygons_in_polygon_soup(
          points, polygons,
          CGAL::parameters::erase_all_duplicates(true).require_same_orientation(
              false)));
  if (polygons.empty()) {
    return UnsupportedError(
        "cannot be repaired into a closed genus-0 mesh: no faces are left");
  }
  // 3. Consistent orientation (may split vertices where the surface is
  // pinched; the check at the end then reports it).
  const std::vector<Polygon> unoriented = polygons;
  PMP::orient_polygon_soup(points, polygons);
  for (size_t i = 0; i < polygons.size() && i < unoriented.size(); ++i) {
    r->reoriented_faces += polygons[i] != unoriented[i];
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    return UnsupportedError(
        "cannot be repaired into a closed genus-0 mesh: its faces cannot be "
        "oriented consistently");
  }
  CgalMesh surface;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, surface);
  // 4. Small holes; 5. zero-area triangles (also those a filling made).
  r->filled_holes = FillSmallHoles(options, &surface, r);
  const int degenerate = CountDegenerateFaces(surface);
  if (degenerate > 0) {
    PMP::remove_degenerate_faces(surface);
    r->dropped_degenerate_faces += degenerate - CountDegenerateFaces(surface);
  }
  // 6. Outward orientation of a closed surface; unreferenced vertices.
  if (CGAL::is_closed(surface) && !PMP::is_outward_oriented(surface)) {
    PMP::reverse_face_orientations(surface);
    // The input's faces that step 3 did not flip are flipped now.
    r->reoriented_faces =
        static_cast<int>(polygons.size()) - r->reoriented_faces;
  }
  for (CgalMesh::Vertex_index v : surface.vertices()) {
    if (surface.is_isolated(v)) {
      surface.remove_vertex(v);
      ++r->dropped_unreferenced_vertices;
    }
  }
  TriangleMesh repaired = FromCgalMesh(surface);
  SDCB_ASSIGN_OR_RETURN(const MeshTopologyReport topology,
                        AnalyzeMeshTopology(repaired));
  if (!topology.ok) {
    std::string why = "after repair, " + DescribeTopologyProblem(topology);
    if (topology.boundary_loops > 0) {
      char percent[32];
      std::snprintf(percent, sizeof percent, "%g", options.max_hole_percent);
      why += " (holes of more than " + std::to_string(options.max_hole_edges) +
             " edges or " + percent + "% of the bounding box stay open)";
    }
    return UnsupportedError(why);
  }
  return repaired;
}

}  // namespace

bool MeshRepairReport::changed() const {
  return merged_vertices > 0 || dropped_degenerate_faces > 0 ||
         dropped_duplicate_faces > 0 || reoriented_faces > 0 ||
         filled_holes > 0 || dropped_unreferenced_vertices > 0;
}

std::string MeshRepairReport::Describe() const {
  // "N thing(s)" with the right plural, or nothing for zero.
  auto count = [](int n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
  };
  // "a, b and c".
  auto join = [](const std::vector<std::string>& items) {
    std::string out;
    for (size_t i = 0; i < items.size(); ++i) {
      if (i > 0) out += i + 1 == items.size() ? " and " : ", ";
      out += items[i];
    }
    return out;
  };
  std::vector<std::string> parts, dropped;
  if (merged_vertices > 0) {
    parts.push_back("merged " + count(merged_vertices, "duplicate vertex",
                                      "duplicate vertices"));
  }
  if (dropped_degenerate_faces > 0) {
    dropped.push_back(
        count(dropped_degenerate_faces, "degenerate face", "degenerate faces"));
  }
  if (dropped_duplicate_faces > 0) {
    dropped.push_back(
        count(dropped_duplicate_faces, "duplicate face", "duplicate faces"));
  }
  if (dropped_unreferenced_vertices > 0) {
    dropped.push_back(count(dropped_unreferenced_vertices,
                            "unreferenced vertex", "unreferenced vertices"));
  }
  if (!dropped.empty()) parts.push_back("dropped " + join(dropped));
  if (filled_holes > 0) {
    parts.push_back("filled " + count(filled_holes, "hole", "holes") +
                    " with " + count(added_faces, "triangle", "triangles"));
  }
  if (reoriented_faces > 0) {
    parts.push_back("reoriented " + count(reoriented_faces, "face", "faces"));
  }
  return parts.empty() ? "nothing to repair" : join(parts);
}

StatusOr<TriangleMesh> RepairMesh(const TriangleMesh& mesh,
                                  const MeshRepairOptions& options,
                                  MeshRepairReport* report) {
  SDCB_RETURN_IF_ERROR(CheckFaceIndices(mesh));
  MeshRepairReport local;
  MeshRepairReport* r = report != nullptr ? report : &local;
  *r = MeshRepairReport();
  try {
    return Repair(mesh, options, r);
  } catch (const std::exception& e) {
    // CGAL reports violated preconditions by exceptions, over several lines.
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    return UnsupportedError(
        "cannot be repaired into a closed genus-0 mesh: the repair failed (" +
        what + ")");
  }
}

}  // namespace sdcb
