// sdcb cage MODEL.sdcb -o CAGE.{obj,fbx} [--scheme catmark|loop] [--faces N]
//           [--tolerance PCT] [--json FILE] [--quiet]
// A subdivision cage whose limit surface follows the model's surface
// (converters/cage/subdivision_cage.h, docs/CAGE.md): OBJ with OpenSubdiv's
// crease tags, or binary FBX with an edge-crease layer (what Blender reads
// creases from, converters/cage/cage_fbx.h).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "sdcb/converters/cage/cage_fbx.h"
#include "sdcb/converters/cage/subdivision_cage.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/io/common/atomic_file.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace sdcb::cli {

int RunCage(const std::vector<std::string>& argv) {
  const Args args(argv, {"output", "scheme", "faces", "tolerance", "json"},
                  {"quiet"});
  args.RequirePositionals(
      1,
      "MODEL (usage: sdcb cage MODEL.sdcb -o CAGE.{obj,fbx} "
      "[--scheme catmark|loop] [--faces N] "
      "[--tolerance PCT] [--json FILE])");
  const std::string& path = args.positionals()[0];
  const std::string output = args.Get("output");
  if (output.empty()) throw UsageError{"missing -o CAGE.obj or -o CAGE.fbx"};
  const std::string format = LowercaseExtension(output);
  if (format != ".obj" && format != ".fbx") {
    throw UsageError{
        "the cage is written as Wavefront OBJ or binary FBX: -o must name a "
        ".obj or .fbx file, not '" +
        output + "'"};
  }
  CageOptions options;
  const std::string scheme = args.Get("scheme", "catmark");
  if (scheme == "loop") {
    options.scheme = SubdivisionScheme::kLoop;
  } else if (scheme != "catmark") {
    throw UsageError{"--scheme takes 'catmark' or 'loop', not '" + scheme +
                     "'"};
  }
  if (format == ".fbx" && options.scheme == SubdivisionScheme::kLoop) {
    throw UsageError{
        "FBX holds Catmull-Clark cages only (it has no Loop scheme): write a "
        "Loop cage as .obj"};
  }
  options.max_faces = args.GetInt("faces", options.max_faces, 1, 10000000);
  options.tolerance_percent =
      args.GetDouble("tolerance", options.tolerance_percent, 1e-6, 100);

  // Outputs are checked before the work (tools/cli.h).
  const Status outputs = PrepareOutputs({output, args.Get("json")});
  if (!outputs.ok()) return ReportError(outputs);
  StatusOr<Model> read = ReadSdcbModelFile(path);
  if (!read.ok()) return ReportError(read.status());
  const Model model = std::move(read).value();

  ProgressBar progress("sdcb cage", args.Has("quiet"));
  options.progress = progress.Callback();
  StatusOr<std::vector<PartCage>> cages = FitModelCages(model, options);
  progress.Finish();
  if (!cages.ok()) return ReportError(cages.status().WithPrefix(path));
  // Several parts: one OBJ with an object per part, or one FBX per part
  // (OUT-NAME.fbx; the FBX writer holds one mesh). The report and the
  // summary below are the first part's.
  Status written = Status::Ok();
  if (format == ".obj") {
    written = WriteFileAtomically(CageObjText(*cages), output);
  } else if (cages->size() == 1) {
    written = WriteCageFbx((*cages)[0].fit.cage, (*cages)[0].positions, output);
  } else {
    const std::filesystem::path out(output);
    for (size_t i = 0; written.ok() && i < cages->size(); ++i) {
      const PartCage& part = (*cages)[i];
      const std::string file =
          (out.parent_path() /
           (out.stem().string() + "-" + part.name + out.extension().string()))
              .string();
      written = WriteCageFbx(part.fit.cage, part.positions, file);
    }
  }
  if (!written.ok()) return ReportError(written);
  const CageFit* fit = &(*cages)[0].fit;
  const SubdivisionCage& cage = fit->cage;
  const CageDeviation& d = fit->deviation;
  if (args.Has("json")) {
    nlohmann::ordered_json j;
    j["model"] = path;
    j["output"] = output;
    j["scheme"] = scheme;
    j["faces"] = cage.layout.num_faces();
    j["vertices"] = cage.layout.num_vertices();
    j["creases"] = cage.creases.size();
    j["limit_rmse_percent"] = d.rms_percent;
    j["limit_max_error_percent"] = d.max_percent;
    j["limit_to_spline_rms_percent"] = d.limit_to_spline_rms_percent;
    j["limit_to_spline_max_percent"] = d.limit_to_spline_max_percent;
    j["spline_to_limit_rms_percent"] = d.spline_to_limit_rms_percent;
    j["spline_to_limit_max_percent"] = d.spline_to_limit_max_percent;
    j["folded_area_percent"] = d.folded_area_percent;
    j["limit_samples"] = d.limit_samples;
    j["spline_samples"] = d.spline_samples;
    j["tolerance_percent"] = options.tolerance_percent;
    j["max_faces"] = options.max_faces;
    j["stop_reason"] = fit->stop_reason;
    nlohmann::ordered_json rounds = nlohmann::ordered_json::array();
    for (const CageRound& r : fit->rounds) {
      rounds.push_back({{"round", r.round},
                        {"faces", r.faces},
                        {"vertices", r.vertices},
                        {"limit_rmse_percent", r.limit_rmse_percent},
                        {"limit_max_error_percent", r.limit_max_error_percent},
                        {"seconds", r.seconds}});
    }
    j["rounds"] = rounds;
    j["seconds"] = {{"setup", fit->stage_seconds.setup},
                    {"fit", fit->stage_seconds.fit},
                    {"measure", fit->stage_seconds.measure},
                    {"final_measure", fit->stage_seconds.final_measure},
                    {"total", fit->seconds}};
    written = WriteTextOutput(args.Get("json"), j.dump(2) + "\n");
    if (!written.ok()) {
      // Nothing left behind: the cage goes with its report.
      std::error_code ignored;
      std::filesystem::remove(output, ignored);
      return ReportError(written);
    }
  }
  if (!args.Has("quiet") && args.Get("json") != "-") {
    std::printf("%s -> %s: %s cage, %d faces, %d vertices, %d rounds (%s)\n",
                path.c_str(), output.c_str(),
                scheme == "loop" ? "Loop" : "Catmull-Clark",
                cage.layout.num_faces(), cage.layout.num_vertices(),
                static_cast<int>(fit->rounds.size()), fit->stop_reason.c_str());
    std::printf(
        "  limit surface vs spline: rms %.4f%%  max %.4f%%  (target rms "
        "%.4f%%)  %.2f s\n",
        d.rms_percent, d.max_percent, options.tolerance_percent, fit->seconds);
  }
  if (d.rms_percent > options.tolerance_percent) {
    std::fprintf(stderr,
                 "sdcb: %s: warning: limit rms %.4f%% did not reach the "
                 "tolerance %.4f%% within %d faces\n",
                 path.c_str(), d.rms_percent, options.tolerance_percent,
                 options.max_faces);
  }
  return kExitOk;
}

}  // namespace sdcb::cli
