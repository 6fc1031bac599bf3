#include "sdcb/core/fit/fit_model.h"

#include <tbb/parallel_for.h>

#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "sdcb/core/common/stopwatch.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/hole_filling.h"

namespace sdcb {
namespace {

// Fits one fittable part: closed as it is, open with its holes filled.
StatusOr<PartFit> FitPart(const MeshPart& part, PartReport report,
                          const FitOptions& options) {
  PartFit out;
  out.report = std::move(report);
  const std::string name = "part " + std::to_string(out.report.number);
  if (out.report.closed) {
    SDCB_ASSIGN_OR_RETURN(out.fit, FitSphericalSpline(part.mesh, options));
    return out;
  }
  const Stopwatch fill_clock;
  StatusOr<FilledMesh> filled = FillHoles(part.mesh);
  if (!filled.ok()) return filled.status().WithPrefix(name);
  out.fill_seconds = fill_clock.Seconds();
  out.fill_faces = filled->mesh.num_faces() - filled->input_faces;
  StatusOr<FitResult> fit = FitSphericalSpline(*filled, options);
  if (!fit.ok()) return fit.status().WithPrefix(name);
  out.fit = std::move(fit).value();
  return out;
}

}  // namespace

bool ModelFit::reached_target() const {
  for (const PartFit& p : parts) {
    if (!p.fit.reached_target()) return false;
  }
  return true;
}

StatusOr<PartsIntake> TakeInParts(const TriangleMesh& mesh, int max_parts) {
  PartsIntake intake;
  SDCB_ASSIGN_OR_RETURN(intake.parts, SplitIntoParts(mesh, max_parts));
  intake.reports.reserve(intake.parts.size());
  for (size_t i = 0; i < intake.parts.size(); ++i) {
    SDCB_ASSIGN_OR_RETURN(PartReport report,
                          ReportPart(intake.parts[i], static_cast<int>(i) + 1));
    if (!report.fittable()) return UnsupportedError(report.problem);
    intake.reports.push_back(std::move(report));
  }
  return intake;
}

StatusOr<ModelFit> FitModel(const TriangleMesh& mesh,
                            const ModelFitOptions& options) {
  SDCB_ASSIGN_OR_RETURN(const PartsIntake intake,
                        TakeInParts(mesh, options.max_parts));
  return FitModel(mesh, intake, options);
}

StatusOr<ModelFit> FitModel(const TriangleMesh& mesh, const PartsIntake& intake,
                            const ModelFitOptions& options) {
  const std::vector<MeshPart>& parts = intake.parts;
  const std::vector<PartReport>& reports = intake.reports;
  FitOptions part_options = options.fit;
  if (parts.size() > 1) part_options.progress = nullptr;

  std::vector<std::optional<StatusOr<PartFit>>> fits(parts.size());
  std::mutex done_mutex;
  int done = 0;
  const int total = static_cast<int>(parts.size());
  const auto fit_part = [&](size_t i) {
    fits[i].emplace(FitPart(parts[i], reports[i], part_options));
    if (total > 1 && options.part_done) {
      const std::lock_guard<std::mutex> lock(done_mutex);
      options.part_done(++done, total);
    }
  };
  if (total == 1) {
    fit_part(0);
  } else {
    tbb::parallel_for(size_t{0}, parts.size(), fit_part);
  }

  ModelFit out;
  out.model.source.num_vertices = mesh.num_vertices();
  out.model.source.num_faces = mesh.num_faces();
  out.model.source.hash = HashTriangleMesh(mesh);
  for (std::optional<StatusOr<PartFit>>& fit : fits) {
    SDCB_RETURN_IF_ERROR(fit->status());
    PartFit& part = **fit;
    ModelPart model_part;
    model_part.spline = part.fit.model;
    model_part.trims = part.fit.trims;
    out.model.parts.push_back(std::move(model_part));
    out.parts.push_back(std::move(part));
  }
  return out;
}

}  // namespace sdcb
