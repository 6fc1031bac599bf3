// The true distance between a spherical spline surface and a triangle mesh,
// measured where nothing was fitted, both ways (docs/FITTING.md, "The error
// is the distance between the two surfaces"):
//
// - surface -> mesh: at the vertices of a lattice of level L inside every
//   Delaunay triangle of the spline's knots (so every basis support is
//   sampled, whatever the mesh), L chosen for at least
//   DeviationOptions::min_surface_samples samples; the distance of F(p) to
//   the mesh by CGAL's AABB tree (core/mesh/mesh_distance.h). Each sample
//   stands for a third of the surface area of its lattice triangles' images.
// - mesh -> surface: at every mesh vertex and, with
//   DeviationOptions::mesh_samples, at the vertices of the mesh split into
//   pieces of about that spacing (SplitToEdgeLength), the closest point of
//   the spline:
//   the closest point y of the lattice's image (an AABB tree over it) gives
//   the sphere point p_y of the same barycentric coordinates, and
//   |x - F(p_y)| is a distance to a point of the spline. When that is
//   more than 1 % farther than |x - y| (and, with
//   DeviationOptions::search_all_vertices false, at least the mesh ->
//   surface rms of these first distances), Gauss-Newton steps on the exact
//   spline improve it. Every spline point found bounds the true distance from
//   above, so each sample's distance can only be pessimistic, never
//   flattering (tested: within 1 % of brute force). Area-weighted over the
//   mesh (a third of each incident piece's area per sample). At the
//   vertices alone the half misses the inside of large triangles, and its
//   maximum and rms can then read low (blobby's fit: 0.239 % at its 2,027
//   vertices, 0.367 % inside a triangle): mesh_samples measures there.
//   The distance to the spline changes no faster than the point moves, so
//   inside a piece it is at most the largest of its corners' plus how far
//   its points can be from the nearest corner (CoveringRadius): that bounds
//   the true maximum over the whole mesh from above. Pieces whose bound
//   exceeds the largest distance found by over 1 % are halved, their new
//   points measured, the largest bounds first, until none is left (or
//   max(10,000, mesh_samples / 5) points were added): the maximum found is
//   then within 1 % of an upper bound of the true one. Where the distance
//   is near its maximum over much of the mesh (a coarse polyhedron of a
//   sphere: a maximum inside every face) those points run out first, and
//   the bound stays looser (reported either way).
// - folds: a surface sample is folded when the spline's normal there (du x
//   dv, oriented as the sphere) points away from the mesh's normal at the
//   closest point (negative dot product with the closest triangle's normal,
//   and with those of its neighbours when the closest point is on an edge or
//   a vertex: at a crease the mesh has no single normal); the folded area is
//   the area those samples stand for. The lattice image's normal screens the
//   samples; only suspects are evaluated with derivatives.
//
// The spline is evaluated through its polynomials (PiecewiseSurface, which
// agrees with SphericalSpline to ~1e-13 relative and is several times faster
// per point once a region is built) when there are many points to evaluate
// per control point (the closest-point searches of a dense measurement),
// else through its basis (a round's lattice alone).
//
// Distances are in percent of DeviationOptions::length_unit (the largest
// side of the mesh's bounding box, in the frame of both objects).
#ifndef SDCB_CORE_MEASURE_SURFACE_DEVIATION_H_
#define SDCB_CORE_MEASURE_SURFACE_DEVIATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/sphere/trim_region.h"
#include "sdcb/core/spline/design_matrix.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

struct DeviationOptions {
  // The length that is 100 %: the largest side of the mesh's bounding box,
  // in the frame the spline and the mesh share. > 0.
  double length_unit = 1.0;
  // Surface samples at least (lattice vertices over the knot triangles).
  int min_surface_samples = 100000;
  // Gauss-Newton steps of a closest-point search on the spline, when the
  // first spline point found is not already as close as the lattice allows.
  int closest_point_iterations = 4;
  // false: mesh -> surface is |x - candidate| at the given vertex candidates
  // (an upper bound of the distance, no search; needs vertex_candidates).
  bool closest_points = true;
  // false: the closest-point search runs only for vertices at or above the
  // mesh -> surface rms of the first distances (below it a vertex barely
  // moves the rms and cannot hold the maximum). The fit's final
  // measurement: bunny00 searches 3,938 vertices instead of 15,030, rms
  // 0.04662 % instead of 0.04648 %, same maximum; per-vertex distances
  // below the rms stay the (pessimistic) first ones.
  bool search_all_vertices = true;
  // false: the surface -> mesh half only (the mesh -> surface figures stay
  // 0 and the two-sided ones are the surface -> mesh ones until
  // SetMeshToSurface gives the other half).
  bool mesh_to_surface = true;
  // Mesh -> surface samples inside the triangles too: the mesh is split
  // (SplitToEdgeLength) until no edge is longer than the spacing of this
  // many points spread evenly over its area, and measured at the split
  // mesh's vertices, each standing for a third of its pieces' area. So
  // about this many samples on a coarse mesh, and a mesh already finer is
  // measured at its vertices. Where long needles would ask for over 8
  // times as many, the spacing doubles until they do not. 0: at the mesh's
  // vertices only (the rounds' own measurements).
  int64_t mesh_samples = 0;
  // The region of the sphere the surface keeps (an open part's trims,
  // core/spline/model.h); null: the whole sphere. Surface samples outside
  // it are not measured (distance 0, not folded, no area): every surface
  // figure is the kept region's. The mesh is then the part's own triangles,
  // so the mesh -> surface half is too. Must outlive the call.
  const TrimRegion* region = nullptr;
};

struct SurfaceDeviation {
  // Surface -> mesh, area-weighted over the surface.
  double surface_to_mesh_rms_percent = 0.0;
  double surface_to_mesh_max_percent = 0.0;
  // Mesh -> surface, area-weighted over the mesh.
  double mesh_to_surface_rms_percent = 0.0;
  double mesh_to_surface_max_percent = 0.0;
  // sqrt of the mean of the two mean squares; the larger of the two maxima
  // (the two-sided Hausdorff distance, as sampled).
  double rms_percent = 0.0;
  double hausdorff_percent = 0.0;
  // Share of the surface's area whose normal opposes the mesh's, percent.
  double folded_area_percent = 0.0;
  // A trimmed surface: the two-sided distance between its boundary and the
  // part's (core/measure/boundary_deviation.h), percent, set by the fit's
  // measurements (MeasureFitSurface) and `sdcb compare`; -1 when not
  // measured.
  double boundary_percent = -1.0;
  double surface_area = 0.0;  // of the lattice's image, in length units^2
  int64_t surface_samples = 0;
  int64_t mesh_samples = 0;  // the vertices, or the split mesh's
  // Of those, the points added where the bound asked for them.
  int64_t mesh_bound_samples = 0;
  // The longest edge the mesh's triangles were split to
  // (DeviationOptions::mesh_samples), percent; 0 when measured at the
  // vertices only.
  double mesh_sample_spacing_percent = 0.0;
  // An upper bound of the true mesh -> surface maximum over the whole mesh,
  // not just its samples: every sample's distance is one to a point of the
  // spline (never below the true one), and the distance to the spline
  // changes no faster than the point moves, so inside a piece between
  // samples it is at most the largest of its corners' plus the piece's
  // CoveringRadius.
  double mesh_to_surface_max_bound_percent = 0.0;
  int lattice_level = 0;
  // Mesh vertices whose closest point needed Gauss-Newton steps.
  int64_t refined_vertices = 0;
  // Mesh -> surface distance of every mesh vertex, percent (the input's
  // vertices, also when more samples were measured).
  Eigen::VectorXd vertex_distance_percent;
  // Every mesh sample (the vertices first), its distance to the spline
  // (percent) and the mesh area it stands for (length units^2; sums to the
  // mesh's area). Empty where SetMeshToSurface gave the half.
  Eigen::MatrixX3d mesh_sample_points;
  Eigen::VectorXd mesh_sample_distance_percent;
  Eigen::VectorXd mesh_sample_weight;
  // Every surface sample: its sphere point, its distance to the mesh
  // (percent) and whether it is folded.
  Eigen::MatrixX3d surface_sample_points;
  // F at every surface sample (the points measured), and the closest point
  // of the mesh to it with the triangle holding that point.
  Eigen::MatrixX3d surface_sample_positions;
  // The lattice's triangles over the surface samples (rows above): with
  // surface_sample_positions, the measured surface as a triangle mesh.
  Eigen::MatrixX3i surface_sample_triangles;
  Eigen::MatrixX3d surface_sample_mesh_point;
  std::vector<int> surface_sample_mesh_face;
  Eigen::VectorXd surface_sample_distance_percent;
  // The surface area each sample stands for (length units^2; sums to
  // surface_area).
  Eigen::VectorXd surface_sample_weight;
  std::vector<bool> surface_sample_folded;
  // Whether each surface sample lies in DeviationOptions::region (empty:
  // every sample does).
  std::vector<bool> surface_sample_kept;
  // The knot triangle of each surface sample: an index into
  // ComputeDelaunayConfigurations(surface.knots(), 0).sets.
  std::vector<int> surface_sample_knot_triangle;
};

// Sets the mesh -> surface half of `deviation` to the distances (percent)
// at mesh samples of the given area weights (the maximum over those of
// positive weight), and the two-sided figures from both halves;
// vertex_distance_percent is left empty.
void SetMeshToSurface(const Eigen::VectorXd& distance_percent,
                      const Eigen::VectorXd& weights,
                      SurfaceDeviation* deviation);

// Measures `surface` against `mesh` (both in the same frame).
// `vertex_candidates` (optional, #V by 3): a point of the spline for every
// mesh vertex (e.g. F(u_i) at the fit's parameters), a second candidate for
// the vertex's closest point. kInvalidArgument for bad options or a
// candidate count that does not match; kInvalidInput for a mesh without a
// usable triangle. Deterministic for any thread count.
// `mesh_distance` (optional): the AABB tree of `mesh`, or of a mesh with
// the same surface (the input whose split `mesh` is), when the caller
// measures the same mesh repeatedly (the fit's rounds); built here if null.
StatusOr<SurfaceDeviation> MeasureSurfaceDeviation(
    const SphericalSpline& surface, const TriangleMesh& mesh,
    const DeviationOptions& options = {},
    const Eigen::MatrixX3d* vertex_candidates = nullptr,
    const MeshDistance* mesh_distance = nullptr);

// Measures the surface -> mesh half of `deviation` again for `surface`, a
// spline over the same basis whose control points differ from those
// measured only at the indices `changed`. `lattice_values`: the basis's
// values at the surface samples (BuildFormDesignMatrix of
// core/spline/design_matrix.h at surface_sample_points, the surface's
// form). The lattice blocks of the knot triangles where a changed basis
// function is nonzero at a sample are evaluated again (the values times the
// control points), with their areas, normals, distances and folds, and the
// figures summed anew; the other samples keep theirs, which the change
// cannot move. For a repair that moves a few control points at a time
// (core/fit/fold_repair.h). Needs a measurement with
// DeviationOptions::mesh_to_surface false, the same options and the same
// `mesh_distance` (each sample's search starts from its closest point
// there); the two-sided figures are then the surface -> mesh ones.
// kInvalidArgument for
// a measurement or values that do not fit (`deviation` unchanged);
// kInvalidInput where the surface is undefined (`deviation` then partly
// measured again: not to be used).
Status RemeasureSurfaceToMesh(const SphericalSpline& surface,
                              const MeshDistance& mesh_distance,
                              const DeviationOptions& options,
                              const DesignMatrix& lattice_values,
                              const std::vector<int>& changed,
                              SurfaceDeviation* deviation);

}  // namespace sdcb

#endif  // SDCB_CORE_MEASURE_SURFACE_DEVIATION_H_
