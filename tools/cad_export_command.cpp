// sdcb export MODEL.sdcb -o OUT.{step,stp,igs,iges} [--tolerance PCT]
//   [--angle DEG] [--max-patches N] [--json FILE] [--quiet]
//
// The surface as bicubic B-spline patches sewn into one solid
// (converters/cad_patches.h, converters/cad_file.h; docs/CAD.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "sdcb/converters/cad_file.h"
#include "sdcb/converters/cad_patches.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace sdcb::cli {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

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

bool IsCadExtension(const std::string& ext) {
  return ext == ".step" || ext == ".stp" || ext == ".igs" || ext == ".iges";
}

int RunCadExport(const Args& args, const std::string& ext) {
  const Clock::time_point start = Clock::now();
  // OpenCASCADE's writers print statistics on stdout; the command line owns
  // the process, so it silences them.
  SilenceOpenCascadeMessages();
  for (const char* mesh_only :
       {"uniform", "qp", "cl", "colors", "mesh", "measure-samples", "draco",
        "meshopt", "no-optimize", "no-simplify", "no-relocate"}) {
    if (args.Has(mesh_only)) {
      throw UsageError{std::string("--") + mesh_only + " does not apply to a " +
                       ext + " output"};
    }
  }
  const std::string model_path = args.positionals()[0];
  const std::string output = args.Get("output");
  const std::string json_path = args.Get("json");
  CadPatchOptions options;
  options.tolerance_percent =
      args.GetDouble("tolerance", options.tolerance_percent, 1e-6, 50.0);
  options.angle_degrees =
      args.GetDouble("angle", options.angle_degrees, 1e-3, 180.0);
  options.max_patches =
      args.GetInt("max-patches", options.max_patches, 96, 2000000);
  const bool quiet = args.Has("quiet") || json_path == "-";
  const CadFormat format =
      (ext == ".igs" || ext == ".iges") ? CadFormat::kIges : CadFormat::kStep;

  const Status prepared = PrepareOutputs({output, json_path});
  if (!prepared.ok()) return ReportError(prepared);
  StatusOr<SplineModel> model = ReadSdcbFile(model_path);
  if (!model.ok()) return ReportError(model.status());
  StatusOr<SphericalSpline> spline = SurfaceFromModel(*model);
  if (!spline.ok()) return ReportError(spline.status().WithPrefix(model_path));

  ProgressBar progress("sdcb export", quiet);
  options.progress = progress.Callback();
  Clock::time_point t0 = Clock::now();
  StatusOr<CadPatchSet> fit = FitCadPatches(*spline, options);
  progress.Finish();
  if (!fit.ok()) return ReportError(fit.status().WithPrefix(model_path));
  const double fit_seconds = Since(t0);
  if (!fit->within_tolerance) {
    char message[400];
    std::snprintf(message, sizeof(message),
                  "%d patches reach a max distance of %.4g%% to the spline "
                  "and normals within %.3g deg, not the tolerance %.4g%% "
                  "and %.3g deg (%s); nothing written",
                  static_cast<int>(fit->patches.size()),
                  fit->max_deviation_percent, fit->max_normal_deviation_degrees,
                  options.tolerance_percent, options.angle_degrees,
                  fit->stop_reason.c_str());
    return ReportError(InvalidInputError(model_path + ": " + message));
  }

  t0 = Clock::now();
  StatusOr<CadSolidReport> solid =
      WriteCadSolid(ToInput(fit->patches, model->transform), fit->layout.faces,
                    format, output);
  if (!solid.ok()) return ReportError(solid.status());
  const double write_seconds = Since(t0);

  nlohmann::ordered_json j;
  j["model"] = model_path;
  j["output"] = output;
  j["format"] = format == CadFormat::kStep ? "step" : "iges";
  j["unit"] = "mm";
  j["patches"] = fit->patches.size();
  j["tolerance_percent"] = options.tolerance_percent;
  j["angle_degrees"] = options.angle_degrees;
  j["max_deviation_percent"] = fit->max_deviation_percent;
  j["rms_deviation_percent"] = fit->rms_deviation_percent;
  j["measured_points"] = fit->measured_points;
  j["max_normal_jump_degrees"] = fit->max_normal_jump_degrees;
  j["volume"] = solid->volume;
  j["area"] = solid->area;
  j["valid"] = solid->valid;
  j["normal_deviation_degrees"] = fit->max_normal_deviation_degrees;
  j["rounds"] = fit->rounds;
  j["max_patches"] = options.max_patches;
  j["patch_max_deviation_percent"] = fit->patch_max_percent;
  j["fine_patches"] = fit->fine_faces;
  j["seconds"] = {
      {"fit", fit->fit_seconds},       {"measure", fit->measure_seconds},
      {"patches", fit_seconds},        {"build", solid->seconds.build},
      {"check", solid->seconds.check}, {"translate", solid->seconds.translate},
      {"write", write_seconds},        {"total", Since(start)}};
  if (!json_path.empty()) {
    const Status s = WriteTextOutput(json_path, j.dump(2) + "\n");
    if (!s.ok()) {
      // Nothing left behind: the file goes with its report.
      std::error_code ignored;
      std::filesystem::remove(output, ignored);
      return ReportError(s);
    }
  }
  if (!quiet) {
    std::printf(
        "%s -> %s: %d bicubic patches, one closed solid (volume %.6g mm^3)\n"
        "  max distance to the spline %.4g%% (tolerance %.4g%%), max normal "
        "jump %.3g deg  %.2f s\n",
        model_path.c_str(), output.c_str(),
        static_cast<int>(fit->patches.size()), solid->volume,
        fit->max_deviation_percent, options.tolerance_percent,
        fit->max_normal_jump_degrees, Since(start));
  }
  return kExitOk;
}

}  // namespace sdcb::cli
