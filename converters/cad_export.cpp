#include "sdcb/converters/cad_export.h"

#include <algorithm>
#include <cstdio>

#include "sdcb/converters/stopwatch.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {
namespace {

// The fit's share of the progress; the solid's stages share the rest.
constexpr double kFitShare = 0.7;

// The patches in the input's coordinates (the transform is a scale and a
// translation, under which Bezier poles map like points).
std::vector<BicubicPatch> ToInput(const std::vector<BicubicPatch>& patches,
                                  const NormalizingTransform& transform) {
  Eigen::MatrixX3d poles(static_cast<Eigen::Index>(patches.size()) * 16, 3);
  for (size_t p = 0; p < patches.size(); ++p) {
    for (int q = 0; q < 16; ++q) poles.row(p * 16 + q) = patches[p].poles[q];
  }
  poles = transform.ToInput(poles);
  std::vector<BicubicPatch> out(patches.size());
  for (size_t p = 0; p < patches.size(); ++p) {
    for (int q = 0; q < 16; ++q) out[p].poles[q] = poles.row(p * 16 + q);
  }
  return out;
}

}  // namespace

StatusOr<CadExportReport> WriteCadExport(const SplineModel& model,
                                         const CadExportOptions& options,
                                         const std::string& path) {
  const Stopwatch start;
  const auto progress = [&](const std::string& stage, double fraction) {
    if (options.progress) options.progress(stage, fraction);
  };
  SDCB_ASSIGN_OR_RETURN(const SphericalSpline spline, SurfaceFromModel(model));
  CadPatchOptions patch_options = options.patches;
  patch_options.length_unit = 1.0;  // the normalized frame
  patch_options.progress = [&](const std::string& stage, double fraction) {
    progress(stage, kFitShare * fraction);
  };
  SDCB_ASSIGN_OR_RETURN(const CadPatchSet fit,
                        FitCadPatches(spline, patch_options));
  const CadPatchOptions& o = patch_options;
  if (!fit.within_tolerance) {
    char message[400];
    std::snprintf(message, sizeof(message),
                  "%d patches reach a max distance of %.4g%% to the spline "
                  "and normals within %.3g deg, not the tolerance %.4g%% "
                  "and %.3g deg (%s); nothing written",
                  static_cast<int>(fit.patches.size()),
                  fit.max_distance_percent, fit.max_normal_angle_degrees,
                  o.tolerance_percent, o.angle_degrees,
                  fit.stop_reason.c_str());
    return InvalidInputError(message);
  }
  SDCB_ASSIGN_OR_RETURN(
      const CadSolidReport solid,
      WriteCadSolid(ToInput(fit.patches, model.transform), fit.layout.faces,
                    options.format, path,
                    [&](const std::string& stage, double fraction) {
                      progress(stage, kFitShare + (1.0 - kFitShare) * fraction);
                    }));

  CadExportReport r;
  r.format = options.format == CadFormat::kStep ? "step" : "iges";
  r.faces = static_cast<int>(fit.patches.size());
  r.tolerance_percent = o.tolerance_percent;
  r.angle_degrees = o.angle_degrees;
  r.max_faces = o.max_faces;
  r.max_distance_percent = fit.max_distance_percent;
  r.rms_distance_percent = fit.rms_distance_percent;
  r.measured_points = fit.measured_points;
  r.fine_faces = fit.fine_faces;
  r.max_normal_angle_degrees = fit.max_normal_angle_degrees;
  r.max_normal_jump_degrees = fit.max_normal_jump_degrees;
  r.face_max_distance_percent = fit.face_max_distance_percent;
  r.rounds = fit.rounds;
  r.stop_reason = fit.stop_reason;
  r.volume = solid.volume;
  r.area = solid.area;
  r.valid = solid.valid;
  r.bytes = solid.bytes;
  r.seconds.fit = fit.fit_seconds;
  r.seconds.measure = fit.measure_seconds;
  r.seconds.build = solid.seconds.build;
  r.seconds.check = solid.seconds.check;
  r.seconds.translate = solid.seconds.translate;
  r.seconds.write = solid.seconds.write;
  r.seconds.total = start.Seconds();
  progress("done", 1.0);
  return r;
}

nlohmann::ordered_json CadExportReportToJson(const CadExportReport& r) {
  nlohmann::ordered_json j;
  j["format"] = r.format;
  j["unit"] = "mm";
  j["faces"] = r.faces;
  j["bytes"] = r.bytes;
  j["tolerance_percent"] = r.tolerance_percent;
  j["angle_degrees"] = r.angle_degrees;
  j["max_faces"] = r.max_faces;
  j["max_distance_percent"] = r.max_distance_percent;
  j["rms_distance_percent"] = r.rms_distance_percent;
  j["measured_points"] = r.measured_points;
  j["fine_faces"] = r.fine_faces;
  j["max_normal_angle_degrees"] = r.max_normal_angle_degrees;
  j["max_normal_jump_degrees"] = r.max_normal_jump_degrees;
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
