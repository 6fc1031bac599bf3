// A subdivided icosahedron projected onto the unit sphere: the reference
// spherical mesh for tests and benchmarks (uniform, well-shaped triangles).
#ifndef SDCB_CORE_MESH_ICOSPHERE_H_
#define SDCB_CORE_MESH_ICOSPHERE_H_

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

// Returns the icosahedron with every triangle split into 4 `subdivisions`
// times, new vertices pushed onto the unit sphere. 10 * 4^s + 2 vertices and
// 20 * 4^s faces (s = 6: 40962 vertices), all vertices unit vectors, faces
// counter-clockwise seen from outside. `subdivisions` must be in [0, 9].
TriangleMesh MakeIcosphere(int subdivisions);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_ICOSPHERE_H_
