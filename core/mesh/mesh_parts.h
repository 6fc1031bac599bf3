// A mesh's parts (its connected components of triangles) and whether sdcb
// can fit each: a part must be manifold, consistently oriented, genus 0,
// with area and without degenerate triangles; closed, or open with one or
// more boundary loops (core/mesh/hole_filling.h closes it for the fit).
#ifndef SDCB_CORE_MESH_MESH_PARTS_H_
#define SDCB_CORE_MESH_MESH_PARTS_H_

#include <string>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

// SplitIntoParts' limit on the number of parts unless told otherwise
// (`--max-parts`).
constexpr int kDefaultMaxParts = 1000;

// The most triangles a vertex of a fittable part may have. A fan of more
// needles (a CAD tessellation's cone apex or disk centre) maps to a sphere
// region no spline of a bounded size follows (a double cone of 5,000
// triangles per apex: 247 s, then a folded surface); CGAL's meshes have at
// most 44.
constexpr int kMaxVertexTriangles = 1000;

struct MeshPart {
  // The part's triangles and the vertices they use: vertices in ascending
  // order of their input index, faces in input order. A mesh of one part
  // without unreferenced vertices is its own part, unchanged.
  TriangleMesh mesh;
  std::vector<int> input_vertices;  // per part vertex, its input row
  std::vector<int> input_faces;     // per part face, its input row
};

// What `sdcb check` reports per part and what the fit decides from.
struct PartReport {
  int number = 0;  // 1-based, in the order of the parts' first triangles
  MeshTopologyReport topology;  // of the part alone (components == 1)
  bool closed = false;          // no boundary edges
  // In the input's units squared; +infinity when the sum overflows.
  double area = 0.0;
  int max_vertex_triangles = 0;  // the most triangles around one vertex
  // Empty when sdcb can fit the part; else one sentence naming it, e.g.
  // "part 1 (428 triangles) has genus 2 and 3 boundary loops; sdcb fits
  // genus-0 parts". The first problem of: coordinates too large or too
  // small for doubles (the fit's own tests, ComputeNormalizingTransform and
  // AreaScaleToUnitSphere, fail: the bounding box or area overflows, or the
  // area of non-degenerate triangles underflows to 0), no area, not
  // manifold, not consistently oriented, genus > 0, degenerate triangles.
  std::string problem;
  bool fittable() const { return problem.empty(); }
};

// Splits `mesh` into parts (triangles connected through shared vertices),
// in the order of their first triangle; vertices no triangle uses belong to
// no part. kInvalidInput for indices out of range; kUnsupported with one
// sentence ("mesh has 10,000 parts, more than --max-parts 1000") when there
// are more than `max_parts` parts (max_parts <= 0: no limit), decided by a
// union-find before any part is built, so that memory stays O(#V + #F).
StatusOr<std::vector<MeshPart>> SplitIntoParts(const TriangleMesh& mesh,
                                               int max_parts);

// The report of one part (`number` 1-based, used in the problem sentence).
// kInvalidInput only for face indices out of range.
StatusOr<PartReport> ReportPart(const MeshPart& part, int number);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_MESH_PARTS_H_
