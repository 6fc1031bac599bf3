// Greedy simplification of the samples' pattern into a coarse tessellation
// within a threshold (core/tessellate/sampled_certificate.h decides every
// change). Passes at rising thresholds (a fraction of the final threshold
// each), so the cheapest collapses are made first everywhere, as a greedy
// queue would, without one:
//   - per vertex v (in the order of its cheapest target's estimate), the
//     half-edge collapses of v into the two neighbours w whose surface
//     points lie closest to the planes of v's faces (the change a collapse
//     makes to the faces that keep their other corners) are certified, and
//     the one of lower largest distance that passes is made;
//   - then edge flips that lower the larger distance of their two faces.
// Candidates are certified in batches of consecutive queue items, in
// parallel, against the pattern before the batch, and made in queue order;
// a change whose old faces' corners a change made earlier in the batch
// touched is certified again first. The result does not depend on the
// thread count.
#ifndef SDCB_CORE_TESSELLATE_SAMPLED_SIMPLIFICATION_H_
#define SDCB_CORE_TESSELLATE_SAMPLED_SIMPLIFICATION_H_

#include <functional>

#include "sdcb/core/tessellate/sampled_certificate.h"

namespace sdcb {

struct SimplificationOptions {
  // The final threshold (surface units); every face ends within it.
  double threshold = 1e-3;
  // If not null, the changes of the passes near the final threshold are
  // also measured on each new face's lattice of order `lattice` (points
  // between the samples): what the final verification measures.
  const SurfaceSampler* lattice_surface = nullptr;
  int lattice = 6;
  // Called after each pass with the pass index, the number of passes and
  // the number of faces.
  std::function<void(int pass, int passes, int faces)> progress;
};

// Simplifies faces->pattern() in place.
void SimplifySampledFaces(const SimplificationOptions& options,
                          SampledFaces* faces);

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_SAMPLED_SIMPLIFICATION_H_
