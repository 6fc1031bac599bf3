#include "sdcb/core/spline/model.h"

#include <cmath>
#include <string>
#include <utility>

namespace sdcb {
namespace {

Status ValidateKept(const ModelPart& part) {
  const TriangleMesh& mesh = part.kept->mesh;
  if (!part.trims.empty()) return InvalidArgumentError("a kept part has trims");
  if (mesh.num_faces() == 0) return InvalidArgumentError("kept with no faces");
  if (part.kept->reason.empty()) {
    return InvalidArgumentError("kept without a reason");
  }
  if (!mesh.vertices.allFinite()) {
    return InvalidArgumentError("a kept vertex is not finite");
  }
  return CheckFaceIndices(mesh);
}

}  // namespace

Model SinglePartModel(SplineModel spline) {
  Model model;
  model.source = spline.source;
  model.parts.emplace_back();
  model.parts.back().spline = std::move(spline);
  return model;
}

Status ValidateModelPart(const ModelPart& part) {
  if (part.kept) return ValidateKept(part);
  Status s = ValidateSplineModel(part.spline);
  for (size_t t = 0; s.ok() && t < part.trims.size(); ++t) {
    s = ValidateTrimLoop(part.trims[t]);
  }
  return s;
}

Status ValidateModel(const Model& model) {
  if (model.parts.empty()) return InvalidArgumentError("model has no parts");
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const Status s = ValidateModelPart(model.parts[i]);
    if (!s.ok()) {
      return InvalidArgumentError("part " + std::to_string(i + 1) + ": " +
                                  s.message());
    }
  }
  return Status::Ok();
}

}  // namespace sdcb
