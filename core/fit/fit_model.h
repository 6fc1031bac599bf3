// Fits a mesh of one or more parts (core/mesh/mesh_parts.h) into a Model
// (core/spline/model.h): each part on its own, in its own normalized frame,
// a closed genus-0 part by FitSphericalSpline, an open one with its holes
// filled (core/mesh/hole_filling.h) and trimmed at its boundary loops. The
// parts are fitted in parallel; every part's result depends on that part
// alone, so the model is the same for any thread count. With
// ModelFitOptions::keep_unfittable a part sdcb cannot fit is kept as its
// input triangles (ModelPart::kept) instead of refusing the mesh.
#ifndef SDCB_CORE_FIT_FIT_MODEL_H_
#define SDCB_CORE_FIT_FIT_MODEL_H_

#include <functional>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/fit_options.h"
#include "sdcb/core/fit/fit_result.h"
#include "sdcb/core/mesh/mesh_parts.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/model.h"

namespace sdcb {

struct ModelFitOptions {
  FitOptions fit;  // for every part; fit.progress only with a single part
  // More parts than this are refused before any is fitted (<= 0: no limit).
  int max_parts = kDefaultMaxParts;
  // With several parts: called once per part fitted, with the number of
  // parts done and the total (from the thread that fitted it, serialized).
  std::function<void(int done, int total)> part_done;
  // Keep, rather than refuse the mesh for, a part that cannot be fitted: one
  // whose PartReport has a problem (kept with that sentence), one whose fit
  // fails with an error (but kInvalidArgument, options out of range, which
  // fails the whole fit), and one whose fit misses its target with a folded
  // surface (kept with the fit's sentence, "part 3: ..."). A model whose
  // parts are all kept is still a model.
  bool keep_unfittable = false;
};

struct PartFit {
  PartReport report;        // the part's intake (PartReport::number 1-based)
  int fill_faces = 0;       // triangles added to close its holes
  double fill_seconds = 0;  // filling them
  FitResult fit;            // its model and trims are the model part's too
  // A kept part (ModelPart::kept holds its triangles): why, as there; `fit`
  // is then empty, or the fit that missed.
  std::string kept_reason;
  bool kept() const { return !kept_reason.empty(); }
};

struct ModelFit {
  Model model;                  // parts in the mesh's order
  std::vector<PartFit> parts;   // one per model part
  bool reached_target() const;  // every fitted part reached its target
};

// A mesh's parts, each fittable, with their reports.
struct PartsIntake {
  std::vector<MeshPart> parts;
  std::vector<PartReport> reports;
};

// Splits `mesh` into parts (at most `max_parts`) and checks each: a part
// sdcb cannot fit refuses the whole mesh with kUnsupported and the part's
// sentence (PartReport::problem), unless `keep_unfittable` (then its report
// carries the sentence and FitModel keeps the part).
StatusOr<PartsIntake> TakeInParts(const TriangleMesh& mesh, int max_parts,
                                  bool keep_unfittable = false);

// Fits the parts of `intake` (TakeInParts of `mesh`).
StatusOr<ModelFit> FitModel(const TriangleMesh& mesh, const PartsIntake& intake,
                            const ModelFitOptions& options);

// TakeInParts, then FitModel: splits `mesh` into parts, checks each (a part
// sdcb cannot fit refuses the whole mesh with kUnsupported and the part's
// sentence, before any fit runs, unless options.keep_unfittable), and fits
// them. A mesh of one closed part
// without unreferenced vertices is fitted exactly as FitSphericalSpline(mesh,
// options.fit).
StatusOr<ModelFit> FitModel(const TriangleMesh& mesh,
                            const ModelFitOptions& options);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FIT_MODEL_H_
