#include "sdcb/core/fit/fit_model.h"

#include <tbb/parallel_for.h>

#include <cstdio>
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

// Why a fitted part is kept instead (keep_unfittable): its fit missed the
// target with a folded surface. "" to keep the fit.
std::string FoldedMissReason(const PartFit& part) {
  const FitResult& fit = part.fit;
  const double folded = fit.model.statistics.final_result.folded_area_percent;
  if (fit.reached_target() || !(folded > 0)) return "";
  char percent[32];
  std::snprintf(percent, sizeof percent, "%.3g", folded);
  return "part " + std::to_string(part.report.number) +
         ": the fit missed its targets with a surface folded over " + percent +
         " % of its area (" + fit.shortfall + ")";
}

}  // namespace

bool ModelFit::reached_target() const {
  for (const PartFit& p : parts) {
    if (!p.kept() && !p.fit.reached_target()) return false;
  }
  return true;
}

StatusOr<PartsIntake> TakeInParts(const TriangleMesh& mesh, int max_parts,
                                  bool keep_unfittable) {
  PartsIntake intake;
  SDCB_ASSIGN_OR_RETURN(intake.parts, SplitIntoParts(mesh, max_parts));
  intake.reports.reserve(intake.parts.size());
  for (size_t i = 0; i < intake.parts.size(); ++i) {
    SDCB_ASSIGN_OR_RETURN(PartReport report,
                          ReportPart(intake.parts[i], static_cast<int>(i) + 1));
    if (!report.fittable() && !keep_unfittable) {
      return UnsupportedError(report.problem);
    }
    intake.reports.push_back(std::move(report));
  }
  return intake;
}

StatusOr<ModelFit> FitModel(const TriangleMesh& mesh,
                            const ModelFitOptions& options) {
  SDCB_ASSIGN_OR_RETURN(
      const PartsIntake intake,
      TakeInParts(mesh, options.max_parts, options.keep_unfittable));
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
    if (reports[i].fittable()) {
      fits[i].emplace(FitPart(parts[i], reports[i], part_options));
    } else {  // kept (TakeInParts refused it otherwise)
      PartFit kept;
      kept.report = reports[i];
      kept.kept_reason = reports[i].problem;
      fits[i].emplace(std::move(kept));
    }
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
  for (size_t i = 0; i < parts.size(); ++i) {
    StatusOr<PartFit>& fit = *fits[i];
    // Options out of range are the caller's to fix, not a part's to keep.
    if (!fit.ok() && (!options.keep_unfittable ||
                      fit.status().code() == StatusCode::kInvalidArgument)) {
      return fit.status();
    }
    PartFit part;
    if (fit.ok()) {
      part = std::move(fit).value();
    } else {
      part.report = reports[i];
      // A closed part's error is the fit's own (unprefixed, as for a mesh
      // of one part); a kept part's reason names the part.
      const std::string name = "part " + std::to_string(reports[i].number);
      const std::string& message = fit.status().message();
      part.kept_reason =
          message.rfind(name + ": ", 0) == 0 ? message : name + ": " + message;
    }
    if (options.keep_unfittable && !part.kept()) {
      part.kept_reason = FoldedMissReason(part);
    }
    ModelPart model_part;
    if (part.kept()) {
      model_part.kept = KeptMesh{parts[i].mesh, part.kept_reason};
    } else {
      model_part.spline = part.fit.model;
      model_part.trims = part.fit.trims;
    }
    out.model.parts.push_back(std::move(model_part));
    out.parts.push_back(std::move(part));
  }
  return out;
}

}  // namespace sdcb
