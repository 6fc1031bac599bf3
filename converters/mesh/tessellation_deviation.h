// How far a tessellation is from the surface it was made of, measured
// independently of the tessellator's own certificate (docs/EXPORT.md):
//   - surface -> mesh: `samples_per_face` random points of each face's
//     domain triangle (fixed seed), mapped by the surface, to the mesh
//     (CGAL's AABB tree, core/mesh/mesh_distance.h);
//   - mesh -> surface: the centroid of each flat face to the surface, by
//     Gauss-Newton foot-point iterations from the face's domain centroid
//     (finite-difference Jacobian); a local foot point, so an upper bound of
//     the true distance.
// Both are sampled maxima, not bounds of the distance over the whole faces.
#ifndef SDCB_CONVERTERS_MESH_TESSELLATION_DEVIATION_H_
#define SDCB_CONVERTERS_MESH_TESSELLATION_DEVIATION_H_

#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"

namespace sdcb {

struct TessellationDeviation {
  // Largest distances, in the surface's units; infinite surface -> mesh
  // when the tessellation has no usable triangle.
  double surface_to_mesh = 0.0;
  double mesh_to_surface = 0.0;
};

// `samples_per_face` >= 0 (0: surface -> mesh is not measured). Deterministic
// for any thread count.
TessellationDeviation MeasureTessellationDeviation(
    const SurfaceSampler& surface, const Tessellation& tessellation,
    int samples_per_face);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_MESH_TESSELLATION_DEVIATION_H_
