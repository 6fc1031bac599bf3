// The tessellator's last step: every face is measured once more, on fresh
// surface points between the samples it was certified with (the face's
// barycentric lattice of order `lattice`, mapped by the surface in one
// batch), against the same rule (core/tessellate/sampled_certificate.h:
// distance to the mesh near the face; orientation and normal angle where
// the angular test applies), and the mesh's side: the distance from the
// flat triangle's lattice points to the surface (to S at the domain point
// of the same weights, or nearer, by a closest-point search from there,
// core/measure/closest_surface_points.h, where that is above the
// threshold). Faces above `threshold` either way are split at the
// domain midpoint of their longest image edge (with the face across it),
// their samples redistributed, and the faces this made are measured the
// same way, until every face passes or is too small to split; a face
// outside the angle only (by at most 90 degrees) is split for it at most
// eight times down its lineage, then left with its measured angle
// (VerificationResult::max_angle). Each
// face's distance is then the largest at its samples and its lattice, both
// ways: a sampled maximum, not a bound.
#ifndef SDCB_CORE_TESSELLATE_FACE_VERIFICATION_H_
#define SDCB_CORE_TESSELLATE_FACE_VERIFICATION_H_

#include <cstdint>
#include <functional>

#include "sdcb/core/common/status.h"
#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/tessellate/sampled_certificate.h"

namespace sdcb {

struct VerificationOptions {
  double threshold = 1e-3;  // surface units
  int lattice = 6;          // order, 2..16
  // Faces whose shortest domain edge is below this (radians) are not split.
  double min_edge_radians = 1e-7;
  // kInvalidInput rather than more faces than this.
  int64_t max_faces = 20'000'000;
  // The pattern's feature arcs are trims (core/tessellate/trim_pattern.h):
  // only faces of the kept region (KeptFaceSlots) are measured, split and
  // counted in the result.
  bool kept_region_only = false;
  // Called after each round with the faces measured and the faces split.
  std::function<void(int64_t measured, int64_t split)> progress;
};

struct VerificationResult {
  double max_distance = 0.0;  // over every face: samples and lattice
  // Largest angle between a face's normal and the surface normals at its
  // lattice points and corners, radians, over the faces the angular test
  // applies to.
  double max_angle = 0.0;
  int uncertified_faces = 0;  // failed but too small to split
  int64_t evaluations = 0;
  int64_t splits = 0;
};

// Verifies every face of faces->pattern() and splits those that fail.
Status VerifyFaces(const SurfaceSampler& surface,
                   const VerificationOptions& options, SampledFaces* faces,
                   VerificationResult* result);

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_FACE_VERIFICATION_H_
