// What a `.sdcb` file holds: one or more parts, each a spherical DCB-spline
// (SplineModel, in the part's own normalized frame) and, for a part whose
// mesh was open, the trim loops that keep the region the mesh covered.
//
// A part is one connected component of the input's triangles. A closed
// genus-0 part keeps the whole sphere. An open genus-0 part (b >= 1
// boundary loops) was fitted with its holes filled; its trims are the images
// of its boundary loops on the sphere (the spline's domain), and only the
// region they bound is the part's surface: errors, folds and exports count
// that region only.
//
// A part sdcb did not fit (ModelFitOptions::keep_unfittable: genus > 0, not
// manifold, a fit that failed or missed folded) is kept: its input triangles,
// exactly, and the one sentence saying why. Exports to meshes and glTF pass
// it through as it was; STEP / IGES and cages refuse it.
#ifndef SDCB_CORE_SPLINE_MODEL_H_
#define SDCB_CORE_SPLINE_MODEL_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/sphere/trim_region.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// A part kept as the input had it.
struct KeptMesh {
  // The part's triangles and the vertices they use, in the input's
  // coordinates (MeshPart::mesh: vertices in ascending input order, faces in
  // input order); at least one face.
  TriangleMesh mesh;
  // One sentence, e.g. "part 2 (96 triangles) has genus 1; sdcb fits
  // genus-0 parts" (PartReport::problem, or the fit's error or shortfall).
  std::string reason;
};

struct ModelPart {
  // UTF-8, may be "" (a mesh file's parts have no names; glTF's do).
  std::string name;
  // A fitted part's spline; default (empty) for a kept part.
  SplineModel spline;
  // Empty for a closed part: the whole sphere is kept. Empty when kept.
  std::vector<TrimLoop> trims;
  // Set for a kept part (not fitted): then `spline` and `trims` are empty.
  std::optional<KeptMesh> kept;

  bool trimmed() const { return !trims.empty(); }
  bool fitted() const { return !kept.has_value(); }
};

struct Model {
  // In the order of the parts' first triangles in the input.
  std::vector<ModelPart> parts;
  // The whole input mesh (each part's spline.source is the part's own).
  SourceMeshInfo source;
  // For a glTF input, the asset to write back around the parts: opaque
  // bytes here, a GLB of the input without its fitted primitives' geometry
  // (converters/gltf/gltf_asset.h). Empty for other inputs.
  std::string asset;
};

// A model of one closed part: the spline, no trims, its source.
Model SinglePartModel(SplineModel spline);

// ValidateSplineModel for every fitted part, and: at least one part; every
// trim loop has at least 3 finite unit rows and no two consecutive rows equal
// or antipodal; a kept part has no trims, at least one face, finite
// coordinates and face indices in range. kInvalidArgument naming the part
// ("part 2: ...", parts counted from 1 as everywhere users see them) and the
// problem.
Status ValidateModel(const Model& model);

// ValidateModel's checks of one part, its message without "part i: ".
Status ValidateModelPart(const ModelPart& part);

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_MODEL_H_
