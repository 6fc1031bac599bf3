// Dense samples of a surface over S^2 for the tessellator: a triangulation
// of the domain (core/tessellate/sphere_triangulation.h) refined until each
// of its faces is small against the tolerance, with the surface point and
// unit normal at every vertex. The tessellator's coarse faces are certified
// against these samples (core/tessellate/sampled_certificate.h), so the
// pattern is refined from the same quantities a final face must respect,
// only a few times finer:
//   - chordal: the error of the flat triangle predicted from its corners,
//     max |Q_ab| / 6 with Q_ab = (n_b - n_a) . (p_b - p_a) = d^T H d (exact
//     bound for a surface quadratic over the face), at most
//     `error_fraction` of the tolerance;
//   - size: no image edge longer than `length_factor` * sqrt(tolerance *
//     surface diameter) (a shape smaller than the samples' spacing cannot
//     hide between them on flat parts);
//   - angular (if angle_degrees < 180), on faces with an image edge longer
//     than `angle_length_factor` * tolerance (the final faces' angular test
//     applies to faces larger than the tolerance only): corner normals
//     within angle_degrees / `angle_divisions` of each other.
// A face that fails is bisected at the domain midpoint of its longest
// domain edge, after the face across that edge if its longest edge is
// longer (longest-edge propagation: the pattern stays conforming and its
// angles bounded); each round of splits is one batch of surface
// evaluations. The result is renumbered along a Morton curve of the
// directions (vertices) and by first corner (faces), so that neighbours
// sit close in memory.
#ifndef SDCB_CORE_TESSELLATE_SURFACE_SAMPLES_H_
#define SDCB_CORE_TESSELLATE_SURFACE_SAMPLES_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/tessellate/sphere_triangulation.h"

namespace sdcb {

struct SurfaceSampleOptions {
  // The tessellation's tolerance, in the surface's units; > 0.
  double tolerance = 1e-3;
  // The final faces' normal tolerance, degrees; 180: no angular criterion.
  double angle_degrees = 180.0;
  double error_fraction = 1.0 / 16.0;
  double length_factor = 0.5;
  double angle_divisions = 2.0;
  double angle_length_factor = 0.25;
  // > 1: the refinement first stops where every face passes criteria
  // `coarse_scale` times looser (errors times it, lengths and angles times
  // its square root, angles at most angle_degrees) and keeps that pattern
  // (SurfaceSamples::coarse_faces) before it goes on to the dense one.
  double coarse_scale = 0.0;
  // The icosphere level the refinement starts from ...
  int initial_level = 3;
  // ... or this pattern (core/tessellate/feature_pattern.h), whose feature
  // arcs the refinement keeps as chains of edges.
  const SphereTriangulation* initial_pattern = nullptr;
  // The initial pattern's feature arcs are trims (core/tessellate/
  // trim_pattern.h): only faces of the kept region (KeptFaceSlots) are
  // refined; the others are split only where a kept face shares an edge.
  bool kept_region_only = false;
  // Edges shorter than this on the domain (radians) are not split.
  double min_edge_radians = 1e-7;
  // kInvalidInput rather than more vertices than this.
  int64_t max_vertices = 10'000'000;
  // Called after each round of splits with the number of vertices so far.
  std::function<void(int64_t vertices)> progress;
};

struct SurfaceSamples {
  SphereTriangulation pattern;
  // Per vertex of the pattern: the surface point and unit normal (zero
  // where the surface is singular).
  std::vector<Eigen::Vector3d> positions, normals;
  // Diameter of the sampled surface (largest side of the samples' box).
  double size = 0.0;
  int64_t evaluations = 0;
  // With SurfaceSampleOptions::coarse_scale: the coarser pattern's faces (a
  // triangulation of the sphere by some of the pattern's vertices), and per
  // vertex the coarse face whose domain triangle holds it (-1 for the
  // coarse pattern's own vertices).
  std::vector<SphereTriangulation::Face> coarse_faces;
  std::vector<int> coarse_face_of;
};

// Refines the icosphere of `initial_level` until every face passes (see
// above). kInvalidInput past max_vertices.
StatusOr<SurfaceSamples> SampleSurface(const SurfaceSampler& surface,
                                       const SurfaceSampleOptions& options);

// Evaluates the pattern's vertices first .. num_vertices() - 1 into
// samples->positions / normals (one batch).
void EvaluateNewVertices(const SurfaceSampler& surface, int first,
                         SurfaceSamples* samples);

// The predicted error of a flat triangle over a surface patch from its
// corners' points and unit normals: max |Q_ab| / 6 (see above).
double PredictedFlatError(const Eigen::Vector3d& pa, const Eigen::Vector3d& pb,
                          const Eigen::Vector3d& pc, const Eigen::Vector3d& na,
                          const Eigen::Vector3d& nb, const Eigen::Vector3d& nc);

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_SURFACE_SAMPLES_H_
