#include "sdcb/core/spline/model.h"

#include <cmath>
#include <string>
#include <utility>

namespace sdcb {

Model SinglePartModel(SplineModel spline) {
  Model model;
  model.source = spline.source;
  model.parts.emplace_back();
  model.parts.back().spline = std::move(spline);
  return model;
}

Status ValidateModel(const Model& model) {
  if (model.parts.empty()) return InvalidArgumentError("model has no parts");
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const ModelPart& part = model.parts[i];
    Status s = ValidateSplineModel(part.spline);
    for (size_t t = 0; s.ok() && t < part.trims.size(); ++t) {
      s = ValidateTrimLoop(part.trims[t]);
    }
    if (!s.ok()) {
      return InvalidArgumentError("part " + std::to_string(i + 1) + ": " +
                                  s.message());
    }
  }
  return Status::Ok();
}

}  // namespace sdcb
