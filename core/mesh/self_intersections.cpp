#include "sdcb/core/mesh/self_intersections.h"

#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/box_intersection_d.h>

#include <string>
#include <vector>

#include "sdcb/core/mesh/cgal_mesh.h"

namespace sdcb {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

// Thrown by the counting callback once the budget of box pairs is spent.
struct TooManyPairs {};

// Counts pairs of overlapping triangle bounding boxes, up to `budget`.
bool BoxPairsWithin(const TriangleMesh& mesh, int64_t budget) {
  using Box = CGAL::Box_intersection_d::Box_with_handle_d<
      double, 3, const int*, CGAL::Box_intersection_d::ID_EXPLICIT>;
  std::vector<Box> boxes;
  std::vector<int> ids(mesh.num_faces());
  boxes.reserve(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    ids[f] = f;
    CGAL::Bbox_3 box;
    for (int k = 0; k < 3; ++k) {
      const auto p = mesh.vertices.row(mesh.faces(f, k));
      box += CGAL::Bbox_3(p.x(), p.y(), p.z(), p.x(), p.y(), p.z());
    }
    boxes.emplace_back(box, &ids[f]);
  }
  int64_t pairs = 0;
  try {
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(),
                                  [&](const Box&, const Box&) {
                                    if (++pairs > budget) throw TooManyPairs();
                                  });
  } catch (const TooManyPairs&) {
    return false;
  }
  return true;
}

// Counts what it is given instead of storing it.
struct CountingOutput {
  int64_t* count;
  CountingOutput& operator*() { return *this; }
  CountingOutput& operator++() { return *this; }
  CountingOutput operator++(int) { return *this; }
  template <typename Pair>
  CountingOutput& operator=(const Pair& pair) {
    if (pair.first != pair.second) ++*count;  // (f, f): f is degenerate
    return *this;
  }
};

}  // namespace

StatusOr<SelfIntersectionReport> FindSelfIntersections(
    const TriangleMesh& mesh, const SelfIntersectionOptions& options) {
  SDCB_RETURN_IF_ERROR(CheckFaceIndices(mesh));
  SelfIntersectionReport report;
  CgalMesh surface;
  if (!ToCgalMesh(mesh, &surface)) {
    report.skipped_because =
        "the mesh is not an oriented manifold (see the topology report)";
    return report;
  }
  const int64_t budget =
      options.max_pairs_per_face * mesh.num_faces() + options.max_extra_pairs;
  if (!BoxPairsWithin(mesh, budget)) {
    report.skipped_because =
        "more than " + std::to_string(budget) +
        " pairs of triangles overlap in their bounding boxes (a fan of very "
        "many triangles around one vertex?)";
    return report;
  }
  PMP::self_intersections(surface, CountingOutput{&report.intersecting_pairs});
  report.checked = true;
  return report;
}

}  // namespace sdcb
