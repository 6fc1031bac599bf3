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
#ifndef SDCB_CORE_SPLINE_MODEL_H_
#define SDCB_CORE_SPLINE_MODEL_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/sphere/trim_region.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

struct ModelPart {
  // UTF-8, may be "" (a mesh file's parts have no names; glTF's do).
  std::string name;
  SplineModel spline;
  // Empty for a closed part: the whole sphere is kept.
  std::vector<TrimLoop> trims;

  bool trimmed() const { return !trims.empty(); }
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

// ValidateSplineModel for every part, and: at least one part; every trim
// loop has at least 3 finite unit rows and no two consecutive rows equal or
// antipodal. kInvalidArgument naming the part ("part 2: ...", parts counted
// from 1 as everywhere users see them) and the problem.
Status ValidateModel(const Model& model);

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_MODEL_H_
