// `sdcb export MODEL.sdcb -o OUT.{step,stp,igs,iges}` as one library call
// (docs/CAD.md): the model's surface as a network of tangent-continuous
// bicubic B-spline faces within a tolerance (converters/cad/cad_network.h),
// moved to the input's coordinates, written as one closed solid
// (converters/cad/cad_file.h), with a report of every figure.
// Lengths in options and report are percent of the largest side of the
// input's bounding box (1 in the model's normalized frame).
#ifndef SDCB_CONVERTERS_CAD_CAD_EXPORT_H_
#define SDCB_CONVERTERS_CAD_CAD_EXPORT_H_

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sdcb/converters/cad/cad_file.h"
#include "sdcb/converters/cad/cad_network.h"
#include "sdcb/core/common/progress.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

struct CadExportOptions {
  CadFormat format = CadFormat::kStep;
  // tolerance_percent, smoothness_degrees, the budgets and the lattices;
  // its length_unit and progress are set by the export.
  CadNetworkOptions network;
  // Called with a stage name and the finished fraction of the whole export
  // in [0, 1], from the calling thread.
  ProgressCallback progress;
};

struct CadExportReport {
  std::string format;  // "step", "iges"
  // Solids in the file (one per part). With several, counts add up and
  // distances and angles are the largest, each in percent of its own part's
  // largest side; face_max_distance_percent lists every part's faces.
  int solids = 1;
  int faces = 0;  // B-spline faces
  // The network's layout (CadQuadLayout::name) and its edges on creases.
  std::string layout;
  int crease_edges = 0;
  int control_points = 0;
  double tolerance_percent = 0.0;
  double smoothness_degrees = 0.0;
  int max_faces = 0;
  // CadNetwork's figures (the parametric distance and the normals, sampled
  // on lattices; the jump at points of every side).
  double max_distance_percent = 0.0;
  double rms_distance_percent = 0.0;
  int64_t measured_points = 0;
  double max_normal_angle_degrees = 0.0;
  double max_normal_jump_degrees = 0.0;
  int jump_points = 0;
  std::vector<double> face_max_distance_percent;
  int rounds = 0;
  std::string stop_reason;
  // The solid (CadSolidReport), in the input's units.
  double volume = 0.0;
  double area = 0.0;
  bool valid = false;
  int64_t bytes = 0;
  struct Seconds {
    double fit = 0.0, measure = 0.0, build = 0.0, check = 0.0, translate = 0.0,
           write = 0.0, total = 0.0;
  } seconds;
};

// Exports `model`'s surface to `path` (its extension is not read: the
// format is options.format). kInvalidArgument for bad options;
// kInvalidInput, in one sentence, when the model's fit measured folds
// (unless smoothness_degrees is 180) or the budgets do not reach the
// tolerance and the smoothness (naming what was reached); kIoError when the
// file cannot be written. Nothing is written unless the result is ok.
StatusOr<CadExportReport> WriteCadExport(const SplineModel& model,
                                         const CadExportOptions& options,
                                         const std::string& path);

// Every part of `model`, one solid per part in one file (WriteCadSolids),
// each fitted in its own frame and moved to the input's coordinates; one
// closed part writes what the SplineModel overload writes. A trimmed part is
// refused before anything is fitted or written (CheckCadParts); other
// errors as above, naming the part ("part 2: ...") when there are several.
StatusOr<CadExportReport> WriteCadExport(const Model& model,
                                         const CadExportOptions& options,
                                         const std::string& path);

// Ok, or kInvalidInput naming the first open part: "part 2 is open (1 trim
// loop); STEP of open parts is not supported yet" (IGES likewise).
Status CheckCadParts(const Model& model, CadFormat format);

// The report as the JSON object of `sdcb export --json` for STEP and IGES
// (docs/CLI.md), without the command line's "model" and "output".
nlohmann::ordered_json CadExportReportToJson(const CadExportReport& report);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_CAD_EXPORT_H_
