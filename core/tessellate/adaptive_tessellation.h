// Adaptive tessellation of a surface over S^2 (a spherical DCB-spline, or any
// SurfaceSampler): the domain triangulation (sphere_triangulation.h) is
// refined by longest-edge bisection until every face is certified:
//   - chordal: the largest distance from the surface patch over the face to
//     the mesh near it, sampled on the face's barycentric lattice of order
//     `lattice` (interior and edge points, not edge midpoints alone), is at
//     most (1 - 4 / (3 lattice^2)) * tolerance. The distance is to the flat
//     image triangle, or, for a point the parameterization shears beyond
//     the face's edges (by at most a quarter of its smallest height), to
//     the nearest of the triangles across them. Faces whose lattice image
//     is stretched, or whose sampled distance is above 0.7 of the
//     threshold, are sampled again at 3 times the order, sheared ones (a
//     point measured against a neighbour) at order 36 (for a surface
//     quadratic over an affinely mapped face the lattice misses at most
//     4 / (3 lattice^2) of the true maximum; where the curvature changes
//     within a face it misses more). Faces sampled above 0.8 of the
//     threshold are then hill-climbed from their largest sample (lattice
//     directions, halving steps) to the local maximum around it, which
//     the lattice can miss by several percent even at order 36.
//   - angular: the angle between the flat triangle's normal and the
//     surface normal at every sample and corner is at most `angle_degrees`,
//     checked only on faces whose image is larger than the tolerance (on
//     smaller faces a normal error is invisible, and at a fold of the
//     surface, where the normal flips, no face would ever pass).
// Then, if `optimize`, two optimizations of that refinement are run and the
// one with fewer faces is kept, both judged by an error predicted from the
// corners' points and normals (exact for a surface quadratic over the face):
//   - a remesher: edges measured in the metric of the second fundamental
//     form (Q_ab = (n_b - n_a) . (p_b - p_a) = d^T H d), split when long,
//     collapsed when short, flipped and relaxed toward metric-equilateral
//     faces (elongated along flat directions), then greedy collapses
//     (cheapest first), flips and vertex moves within the certificate;
//   - local collapses (shortest edges first), flips and vertex moves of the
//     bisection pattern, aiming lower.
// Each then certifies every face again and splits those that fail, so the
// prediction never decides what is shipped; faces such splits turn over
// against the surface normals (a thin, sheared face's new vertex beyond its
// opposite corner) are unfolded by edge flips and certified again.
// Then, if `simplify`, the certified simplification: greedy collapses of
// vertices (half-edge collapses into the three neighbours of lowest predicted
// error, else the full collapse of the edge to its domain midpoint), each
// made only if every face it makes passes the certificate above, the faces
// around whose certificate used the replaced faces still pass, the domain
// faces stay positively oriented and no face turns over against the
// surface normals. Collapses whose surroundings do not overlap are
// certified together in waves, until no vertex around a change is left to
// try. Where no half-edge collapse passes, the full collapse is tried with
// the merged vertex at the edge's midpoint and at the best (by prediction)
// of two other places. Then, if `relocate`, a few rounds: certified vertex
// moves (toward the vertex's faces weighted by their distance, or toward
// its ring's centroid), each made only if all its faces pass and their
// largest distance goes down, and collapses again around the moved
// vertices (the moves spread what is left of the tolerance, so that more
// collapses pass). Last, if `verify`, every face is certified again, those
// sampled above 0.7 of the threshold on the order-36 lattice with the
// climb: moves and collapses search for places where the certificate
// passes and find some where the coarser lattice reads short (the bunny at
// 0.01 %: 0.010011 % measured without this verification, 0.009813 % with
// it). Faces that fail are split. This brings the count toward the
// asymptotic optimum (optimal_triangle_count.h).
//
// The result is closed, manifold, genus 0 and consistently oriented by
// construction (no T-junctions): it is a triangulation of the sphere mapped
// by the surface. Vertices lie on the surface; normals are the surface's
// analytic normals. Deterministic for any thread count.
#ifndef SDCB_CORE_TESSELLATE_ADAPTIVE_TESSELLATION_H_
#define SDCB_CORE_TESSELLATE_ADAPTIVE_TESSELLATION_H_

#include <Eigen/Core>
#include <cstdint>

#include "sdcb/core/common/status.h"
#include "sdcb/core/tessellate/surface_sampler.h"

namespace sdcb {

struct TessellationOptions {
  // Largest distance between mesh and surface, in the surface's units; > 0.
  double tolerance = 1e-3;
  // Largest angle between a face's normal and the surface normals over it,
  // degrees, in (0, 180]; 180 disables the angular test.
  double angle_degrees = 20.0;
  // Order m of the barycentric sample lattice per face, 2..16:
  // (m + 1)(m + 2) / 2 - 3 samples per face.
  int lattice = 6;
  // Hill-climb from the largest sample of each face near the threshold
  // (see above); off only to measure what it catches.
  bool ascend = true;
  // Certified vertex moves between the simplification's collapses (see
  // above): 3.5-4.5 % fewer faces at 0.01 % on the bunny and the bear,
  // for 2.2-2.6 times the tessellation time.
  bool relocate = true;
  // The final verification on the order-36 lattice of the faces near the
  // threshold (see above); off only to measure what it catches.
  bool verify = true;
  // Remesh / collapse, flip and move after refinement (see above).
  bool optimize = true;
  // Certified simplification at the end (see above); with optimize = false
  // it simplifies the bisection pattern.
  bool simplify = true;
  // Faces whose shortest domain edge is below this angle (radians) are not
  // split further; they count as uncertified if they still fail.
  double min_edge_radians = 1e-7;
  // Fail with kInvalidInput rather than produce more faces than this.
  int64_t max_faces = 20'000'000;
};

struct Tessellation {
  Eigen::MatrixX3d directions;  // #V by 3 domain points (unit vectors)
  Eigen::MatrixX3d positions;   // #V by 3 surface points
  Eigen::MatrixX3d normals;     // #V by 3 analytic unit normals
  Eigen::MatrixX3i faces;       // #F by 3, counter-clockwise on the domain
  // Largest sampled distance over all faces (the certificate, scaled back
  // by 1 / (1 - 4 / (3 m^2))) and the largest normal angle, degrees, over
  // the faces the angular test applies to.
  double certified_distance = 0.0;
  double max_normal_angle_degrees = 0.0;
  int uncertified_faces = 0;  // failed but too small to split
  int64_t evaluations = 0;    // surface points sampled
};

// Tessellates `surface` adaptively (see above). kInvalidArgument for bad
// options; kInvalidInput when more than max_faces faces would be needed.
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
