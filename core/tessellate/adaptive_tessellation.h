// Adaptive tessellation of a surface over S^2 (a spherical DCB-spline, or any
// SurfaceSampler) within a distance tolerance, in three steps:
//   1. samples (core/tessellate/surface_samples.h): a pattern of the domain
//      refined until its faces are a small fraction of the tolerance, the
//      surface evaluated at its vertices in batches;
//   2. simplification (core/tessellate/sampled_simplification.h): the
//      pattern coarsened by half-edge collapses and edge flips, each made
//      only if every face it makes passes the sampled certificate
//      (core/tessellate/sampled_certificate.h) at a share of the tolerance:
//      the distance from every sample inside the face to the mesh near it,
//      orientation and normal angle;
//   3. verification (core/tessellate/face_verification.h): every face
//      measured on a lattice of fresh points between its samples; faces
//      above the tolerance are split and measured again.
// The reported distance is the largest over the samples and the lattices: a
// sampled maximum, not a bound (docs/EXPORT.md measures it against an
// independent dense measurement).
//
// The result is closed, manifold, genus 0 and consistently oriented by
// construction (no T-junctions): it is a triangulation of the sphere mapped
// by the surface. Vertices lie on the surface; normals are the surface's
// analytic normals. Deterministic for any thread count. From a pattern with
// feature arcs (TessellationOptions::initial_pattern) the vertices on the
// creases are split per side (Tessellation::normals): closed in positions,
// cut along the creases in indices. With trims (TessellationOptions::trims)
// the result is the kept region only: open, its boundary the trims. Only
// the kept region is refined and verified (faces outside are split only
// where a kept face shares an edge with them); the certified distance and
// the uncertified faces are the kept faces'.
#ifndef SDCB_CORE_TESSELLATE_ADAPTIVE_TESSELLATION_H_
#define SDCB_CORE_TESSELLATE_ADAPTIVE_TESSELLATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdcb/core/common/progress.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/sphere/trim_region.h"
#include "sdcb/core/tessellate/sphere_triangulation.h"

namespace sdcb {

struct TessellationOptions {
  // Largest distance between mesh and surface, in the surface's units; > 0.
  double tolerance = 1e-3;
  // Largest angle between a face's normal and the surface normals over it,
  // degrees, in (0, 180]; 180 disables the angular test. Tested only on
  // faces whose image is larger than the tolerance (on smaller faces a
  // normal error is invisible, and at a fold of the surface no face would
  // pass).
  double angle_degrees = 20.0;
  // Order of the verification lattice per face, 2..16:
  // (m + 1)(m + 2) / 2 - 3 fresh points per face.
  int lattice = 6;
  // Faces whose shortest domain edge is below this angle (radians) are not
  // split further; they count as uncertified if they still fail.
  double min_edge_radians = 1e-7;
  // Fail with kInvalidInput rather than take more dense samples than this
  // (step 1; about 150 bytes each while they are taken, a few times that
  // through the later steps) ...
  int64_t max_samples = 8'000'000;
  // ... or produce more faces than this.
  int64_t max_faces = 4'000'000;
  // A pattern to start from instead of the icosphere: with feature arcs
  // (core/tessellate/feature_pattern.h) the result keeps every arc as a
  // chain of edges, and its faces lie on one side of every crease. Must
  // outlive the call.
  const SphereTriangulation* initial_pattern = nullptr;
  // Trim loops (core/sphere/trim_region.h; empty: the whole sphere): only
  // the region they keep is tessellated. The pattern starts from
  // TrimmedPattern (core/tessellate/trim_pattern.h) and the result keeps the
  // faces on the kept side, so its boundary (edges with one face) is the
  // trim loops mapped by the surface, one boundary loop per trim loop, and
  // no face crosses a trim. Not with an initial_pattern yet.
  std::vector<TrimLoop> trims;
  // Called with the stage ("samples", "simplify", "verify") and the
  // fraction of the whole tessellation done (an estimate that never goes
  // back: the stages hold [0, 0.2), [0.2, 0.9) and [0.9, 1]).
  ProgressCallback progress;
};

struct Tessellation {
  Eigen::MatrixX3d directions;  // #V by 3 domain points (unit vectors)
  Eigen::MatrixX3d positions;   // #V by 3 surface points
  // #V by 3 analytic unit normals. With feature arcs (creases), a vertex
  // on one appears once per side of it (same direction and position), with
  // the mean of that side's face normals, weighted by their angles.
  Eigen::MatrixX3d normals;
  Eigen::MatrixX3i faces;  // #F by 3, counter-clockwise on the domain
  // Largest sampled distance over all faces (samples and verification
  // lattices) and the largest normal angle, degrees, over the faces the
  // angular test applies to (at their lattice points and corners).
  double certified_distance = 0.0;
  double max_normal_angle_degrees = 0.0;
  int uncertified_faces = 0;  // failed but too small to split
  int64_t evaluations = 0;    // surface points sampled
  int64_t samples = 0;        // of them, the dense samples of step 1
  // Wall seconds of the three steps.
  struct Seconds {
    double samples = 0.0, simplify = 0.0, verify = 0.0;
  } seconds;
};

// Tessellates `surface` adaptively (see above). kInvalidArgument for bad
// options; kInvalidInput when more than max_samples samples or max_faces
// faces would be needed (a surface that bends or tears faster than its
// domain can be refined, or a tolerance too small for the budget).
StatusOr<Tessellation> TessellateAdaptively(const SurfaceSampler& surface,
                                            const TessellationOptions& options);

// The icosahedron subdivided `subdivisions` times (10 * 4^s + 2 vertices,
// core/mesh/icosphere.h) mapped by the surface: a semi-regular mesh.
// `subdivisions` in 0..9.
Tessellation TessellateUniformly(const SurfaceSampler& surface,
                                 int subdivisions);

// The subdivision level whose vertex count 10 * 4^s + 2 is closest to
// `vertices` (in log scale), clamped to 0..9.
int UniformLevelForVertices(int64_t vertices);

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_ADAPTIVE_TESSELLATION_H_
