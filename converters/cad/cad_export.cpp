#include "sdcb/converters/cad/cad_export.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "sdcb/core/common/stopwatch.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {
namespace {

// The fit's share of the progress; the solid's stages share the rest.
constexpr double kFitShare = 0.7;

// The network in the input's coordinates (the transform is a scale and a
// translation, under which B-spline poles map like points).
CadNetwork ToInput(CadNetwork network, const NormalizingTransform& transform) {
  const auto map = [&](std::vector<Eigen::Vector3d>* points) {
    Eigen::MatrixX3d p(static_cast<Eigen::Index>(points->size()), 3);
    for (size_t q = 0; q < points->size(); ++q) p.row(q) = (*points)[q];
    p = transform.ToInput(p);
    for (size_t q = 0; q < points->size(); ++q) (*points)[q] = p.row(q);
  };
  for (BSplineFace& face : network.faces) map(&face.poles);
  for (CadEdge& edge : network.edges) map(&edge.poles);
  return network;
}

}  // namespace

namespace {

// A part's network fitted within the options and moved to the input's
// coordinates; `label` ("" or "part N: ") starts its messages.
StatusOr<CadNetwork> FitPartNetwork(const SplineModel& model,
                                    const CadExportOptions& options,
                                    const std::string& label,
                                    const ProgressCallback& progress) {
  SDCB_ASSIGN_OR_RETURN(const SphericalSpline spline, SurfaceFromModel(model));
  char message[400];
  // Across a fold the spline's normal turns over: no smooth face follows
  // it. The fit measured the folds.
  const double folded = model.statistics.final_result.folded_area_percent;
  if (folded > 0.0 && options.network.smoothness_degrees < 180.0) {
    std::snprintf(message, sizeof(message),
                  "the surface folds over %.4g %% of its area (as its fit "
                  "measured), and no smooth face follows a fold "
                  "(--smoothness-degrees 180 exports it anyway); nothing "
                  "written",
                  folded);
    return InvalidInputError(label + message);
  }
  CadNetworkOptions network_options = options.network;
  network_options.length_unit = 1.0;  // the normalized frame
  network_options.progress = progress;
  SDCB_ASSIGN_OR_RETURN(CadNetwork fit, FitCadNetwork(spline, network_options));
  const CadNetworkOptions& o = network_options;
  if (!fit.within_tolerance) {
    std::snprintf(message, sizeof(message),
                  "%d faces with %d control points reach a max distance of "
                  "%.4g%% to the spline and a max normal jump of %.3g deg, "
                  "not the tolerance %.4g%% and %.3g deg (%s); nothing "
                  "written",
                  static_cast<int>(fit.faces.size()), fit.control_points,
                  fit.max_distance_percent, fit.max_normal_jump_degrees,
                  o.tolerance_percent, o.smoothness_degrees,
                  fit.stop_reason.c_str());
    return InvalidInputError(label + message);
  }
  return ToInput(std::move(fit), model.transform);
}

StatusOr<CadExportReport> WriteCadParts(
    const std::vector<const SplineModel*>& parts,
    const CadExportOptions& options, const std::string& path) {
  const Stopwatch start;
  const auto progress = [&](const std::string& stage, double fraction) {
    if (options.progress) options.progress(stage, fraction);
  };
  const double n = static_cast<double>(parts.size());
  std::vector<CadNetwork> fits;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string label =
        parts.size() == 1 ? "" : "part " + std::to_string(i + 1) + ": ";
    SDCB_ASSIGN_OR_RETURN(
        CadNetwork fit,
        FitPartNetwork(*parts[i], options, label,
                       [&](const std::string& stage, double fraction) {
                         progress(stage, kFitShare * (i + fraction) / n);
                       }));
    fits.push_back(std::move(fit));
  }
  SDCB_ASSIGN_OR_RETURN(
      const CadSolidReport solid,
      WriteCadSolids(fits, options.format, path,
                     [&](const std::string& stage, double fraction) {
                       progress(stage,
                                kFitShare + (1.0 - kFitShare) * fraction);
                     }));

  // Several parts: counts add up, distances and angles take the largest
  // (each in percent of its own part's largest side).
  const CadNetworkOptions& o = options.network;
  CadExportReport r;
  r.format = options.format == CadFormat::kStep ? "step" : "iges";
  r.layout = fits[0].layout.name();
  r.tolerance_percent = o.tolerance_percent;
  r.smoothness_degrees = o.smoothness_degrees;
  r.max_faces = o.max_faces;
  r.stop_reason = fits[0].stop_reason;
  r.solids = static_cast<int>(fits.size());
  for (const CadNetwork& fit : fits) {
    r.faces += static_cast<int>(fit.faces.size());
    r.crease_edges += fit.crease_edges;
    r.control_points += fit.control_points;
    r.max_distance_percent =
        std::max(r.max_distance_percent, fit.max_distance_percent);
    r.rms_distance_percent =
        std::max(r.rms_distance_percent, fit.rms_distance_percent);
    r.measured_points += fit.measured_points;
    r.max_normal_angle_degrees =
        std::max(r.max_normal_angle_degrees, fit.max_normal_angle_degrees);
    r.max_normal_jump_degrees =
        std::max(r.max_normal_jump_degrees, fit.max_normal_jump_degrees);
    r.jump_points += fit.jump_points;
    r.face_max_distance_percent.insert(r.face_max_distance_percent.end(),
                                       fit.face_max_distance_percent.begin(),
                                       fit.face_max_distance_percent.end());
    r.rounds = std::max(r.rounds, fit.rounds);
    r.seconds.fit += fit.fit_seconds;
    r.seconds.measure += fit.measure_seconds;
  }
  r.volume = solid.volume;
  r.area = solid.area;
  r.valid = solid.valid;
  r.bytes = solid.bytes;
  r.seconds.build = solid.seconds.build;
  r.seconds.check = solid.seconds.check;
  r.seconds.translate = solid.seconds.translate;
  r.seconds.write = solid.seconds.write;
  r.seconds.total = start.Seconds();
  progress("done", 1.0);
  return r;
}

}  // namespace

StatusOr<CadExportReport> WriteCadExport(const SplineModel& model,
                                         const CadExportOptions& options,
                                         const std::string& path) {
  return WriteCadParts({&model}, options, path);
}

Status CheckCadParts(const Model& model, CadFormat format) {
  if (model.parts.empty())
    return InvalidArgumentError("the model has no parts");
  const char* name = format == CadFormat::kStep ? "STEP" : "IGES";
  for (size_t i = 0; i < model.parts.size(); ++i) {
    if (model.parts[i].kept) {
      return InvalidInputError(
          "part " + std::to_string(i + 1) +
          " was kept as a mesh, not fitted; " + name +
          " holds fitted parts only (OBJ, PLY, STL and glTF pass it through)");
    }
    const size_t loops = model.parts[i].trims.size();
    if (loops == 0) continue;
    return InvalidInputError(
        "part " + std::to_string(i + 1) + " is open (" + std::to_string(loops) +
        (loops == 1 ? " trim loop" : " trim loops") + "); " + name +
        " of open parts is not supported yet");
  }
  return Status::Ok();
}

StatusOr<CadExportReport> WriteCadExport(const Model& model,
                                         const CadExportOptions& options,
                                         const std::string& path) {
  SDCB_RETURN_IF_ERROR(CheckCadParts(model, options.format));
  std::vector<const SplineModel*> parts;
  for (const ModelPart& part : model.parts) parts.push_back(&part.spline);
  return WriteCadParts(parts, options, path);
}

nlohmann::ordered_json CadExportReportToJson(const CadExportReport& r) {
  nlohmann::ordered_json j;
  j["format"] = r.format;
  j["unit"] = "mm";
  if (r.solids > 1) j["solids"] = r.solids;
  j["faces"] = r.faces;
  j["layout"] = r.layout;
  j["crease_edges"] = r.crease_edges;
  j["control_points"] = r.control_points;
  j["bytes"] = r.bytes;
  j["tolerance_percent"] = r.tolerance_percent;
  j["smoothness_degrees"] = r.smoothness_degrees;
  j["max_faces"] = r.max_faces;
  j["max_distance_percent"] = r.max_distance_percent;
  j["rms_distance_percent"] = r.rms_distance_percent;
  j["measured_points"] = r.measured_points;
  j["max_normal_angle_degrees"] = r.max_normal_angle_degrees;
  j["max_normal_jump_degrees"] = r.max_normal_jump_degrees;
  j["jump_points"] = r.jump_points;
  j["volume"] = r.volume;
  j["area"] = r.area;
  j["valid"] = r.valid;
  j["rounds"] = r.rounds;
  j["stop_reason"] = r.stop_reason;
  j["face_max_distance_percent"] = r.face_max_distance_percent;
  j["seconds"] = {{"fit", r.seconds.fit},
                  {"measure", r.seconds.measure},
                  {"build", r.seconds.build},
                  {"check", r.seconds.check},
                  {"translate", r.seconds.translate},
                  {"write", r.seconds.write},
                  {"total", r.seconds.total}};
  return j;
}

}  // namespace sdcb
