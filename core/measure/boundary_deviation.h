// The distance between a trimmed spline's boundary and the boundary of the
// open mesh part it was fitted to, both ways (docs/PARTS.md):
//
// - the spline's boundary is the image of its trims: F along the
//   great-circle arc between consecutive points of each trim loop (what the
//   export tessellates as boundary edges);
// - the part's boundary is its loops' polylines, point i of loop l the mesh
//   vertex whose sphere parameter is trims[l] row i.
//
// Each arc is sampled at its two ends and evenly between them, at least
// `min_samples_per_edge` points and no farther apart than `max_step`
// radians (or than the trims' length over 250,000: a boundary of any
// length takes at most that many samples plus the edges' ends), and the
// mesh edge it stands for at as many points. Surface ->
// mesh: the distance of every F sample to the part's boundary segments;
// mesh -> surface: the distance of every point of the part's boundary to the
// polyline through the F samples (its chords, as the export's boundary
// edges). Both by CGAL's AABB tree over the segments. Percent of
// `length_unit`.
#ifndef SDCB_CORE_MEASURE_BOUNDARY_DEVIATION_H_
#define SDCB_CORE_MEASURE_BOUNDARY_DEVIATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/sphere/trim_region.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

struct BoundaryDeviation {
  double surface_to_mesh_max_percent = 0.0;
  double mesh_to_surface_max_percent = 0.0;
  int64_t samples = 0;  // on each side
  // The two-sided Hausdorff distance between the boundaries, as sampled.
  double max_percent() const {
    return surface_to_mesh_max_percent > mesh_to_surface_max_percent
               ? surface_to_mesh_max_percent
               : mesh_to_surface_max_percent;
  }
};

// kInvalidArgument when `loops` does not match `trims` (a loop per trim
// loop, a row per point), `length_unit` is not positive, `max_step` not
// positive or `min_samples_per_edge` < 2; kInvalidInput when the surface is
// undefined at a sample. Deterministic.
StatusOr<BoundaryDeviation> MeasureBoundaryDeviation(
    const SphericalSpline& surface, const std::vector<TrimLoop>& trims,
    const std::vector<Eigen::MatrixX3d>& loops, double length_unit,
    double max_step, int min_samples_per_edge = 4);

// The same distance against a mesh's boundary that does not come with the
// trims' correspondence (`sdcb compare` against any mesh): its boundary
// edges, rows (a, b) of `vertices`, in any order. The trims are sampled as
// above (at least 4 points per arc); the mesh's side at every edge's ends and
// evenly between them, no farther apart than `mesh_step` (in the unit of
// `vertices`; or than the edges' length over 250,000). kInvalidArgument for a
// step or unit not positive, an edge out of range or a trim loop of fewer than
// 2 points.
StatusOr<BoundaryDeviation> MeasureBoundaryDeviation(
    const SphericalSpline& surface, const std::vector<TrimLoop>& trims,
    const Eigen::MatrixX3d& vertices, const Eigen::MatrixX2i& edges,
    double length_unit, double max_step, double mesh_step);

}  // namespace sdcb

#endif  // SDCB_CORE_MEASURE_BOUNDARY_DEVIATION_H_
