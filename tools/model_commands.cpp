// Commands that read a .sdcb model: info, dump, eval.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/report/fit_statistics_json.h"
#include "sdcb/io/report/model_json.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {

// sdcb info MODEL.sdcb [--json FILE]
int RunInfo(const std::vector<std::string>& argv) {
  const Args args(argv, {"json"}, {"quiet"});
  args.RequirePositionals(1,
                          "MODEL (usage: sdcb info MODEL.sdcb [--json FILE])");
  const std::string& path = args.positionals()[0];
  const Status outputs = PrepareOutputs({args.Get("json")});
  if (!outputs.ok()) return ReportError(outputs);
  SdcbFileInfo file;
  StatusOr<SplineModel> model = ReadSdcbFile(path, &file);
  if (!model.ok()) return ReportError(model.status());
  const SplineModel& m = *model;
  const ControlPointQuantization& q = file.quantization;
  size_t configurations = 0;
  for (const auto& set : m.configurations.sets)
    configurations += set.boundaries.size();
  const RoundStatistics& f = m.statistics.final_result;
  const bool dense = m.statistics.error_measure == ErrorMeasure::kDenseTwoSided;
  if (args.Has("json")) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["format_version"] = file.format_version;
    j["file_bytes"] = file.file_bytes;
    j["degree"] = m.degree;
    j["knots"] = m.knots.rows();
    j["control_points"] = m.control_points.rows();
    j["configurations"] = configurations;
    j["rmse_percent"] = f.rmse_percent;
    j["max_error_percent"] = f.max_error_percent;
    j["error_measure"] = dense ? "dense_two_sided" : "vertices";
    j["folded_area_percent"] = f.folded_area_percent;
    j["reached_target"] = m.statistics.reached_target;
    j["rounds"] = m.statistics.rounds.size();
    j["source"] = {{"file_name", m.source.file_name},
                   {"vertices", m.source.num_vertices},
                   {"faces", m.source.num_faces},
                   {"hash", m.source.hash}};
    j["has_parameters"] = m.parameters.rows() > 0;
    j["basis_form"] = m.basis_form == BasisForm::kRaw ? "raw" : "normalized";
    j["quantization_bits"] = q.bits;  // 0: control points stored exactly
    j["knot_grid_bits"] = file.knot_grid_bits;  // 0: knots stored exactly
    if (!q.lossless()) {
      j["quantization_error_bound_percent"] = q.surface_error_bound_percent();
      j["quantization_bound_measured"] = q.basis_sum_measured;
    }
    const Status s = WriteTextOutput(args.Get("json"), j.dump(2) + "\n");
    if (!s.ok()) return ReportError(s);
  }
  if (!args.Has("quiet") && args.Get("json") != "-") {
    std::printf("%s\n", path.c_str());
    std::printf("  %-22s %u (%llu bytes)\n", "format version",
                file.format_version,
                static_cast<unsigned long long>(file.file_bytes));
    std::printf("  %-22s %d\n", "degree", m.degree);
    std::printf("  %-22s %lld\n", "knots",
                static_cast<long long>(m.knots.rows()));
    std::printf("  %-22s %lld\n", "control points",
                static_cast<long long>(m.control_points.rows()));
    std::printf("  %-22s %zu\n", "configurations", configurations);
    std::printf("  %-22s %.5f%% (%s)\n", "rmse", f.rmse_percent,
                dense ? "two-sided, dense" : "at the vertices");
    std::printf("  %-22s %.5f%%\n", "max error", f.max_error_percent);
    if (dense) {
      std::printf("  %-22s %.5f%%\n", "folded area", f.folded_area_percent);
    }
    std::printf("  %-22s %s\n", "reached target",
                m.statistics.reached_target ? "yes" : "no");
    std::printf("  %-22s %zu\n", "rounds", m.statistics.rounds.size());
    std::printf("  %-22s %s (%lld vertices, %lld faces)\n", "source",
                m.source.file_name.c_str(),
                static_cast<long long>(m.source.num_vertices),
                static_cast<long long>(m.source.num_faces));
    std::printf("  %-22s %s\n", "parameters stored",
                m.parameters.rows() ? "yes" : "no");
    if (file.knot_grid_bits > 0) {
      std::printf("  %-22s %d-bit grid (as fitted)\n", "knots stored on",
                  file.knot_grid_bits);
    }
    if (q.lossless()) {
      std::printf("  %-22s none (exact control points)\n", "quantization");
    } else {
      std::printf("  %-22s %d bits; surface within %.3g%% of the fit%s\n",
                  "quantization", q.bits, q.surface_error_bound_percent(),
                  q.basis_sum_measured ? " (bound measured)" : "");
    }
  }
  return kExitOk;
}

// sdcb dump MODEL.sdcb -o MODEL.json
int RunDump(const std::vector<std::string>& argv) {
  const Args args(argv, {"output"}, {});
  args.RequirePositionals(1,
                          "MODEL (usage: sdcb dump MODEL.sdcb -o MODEL.json)");
  const std::string output = args.Get("output");
  if (output.empty()) throw UsageError{"missing -o MODEL.json"};
  const Status outputs = PrepareOutputs({output});
  if (!outputs.ok()) return ReportError(outputs);
  StatusOr<SplineModel> model = ReadSdcbFile(args.positionals()[0]);
  if (!model.ok()) return ReportError(model.status());
  const Status s = WriteTextOutput(output, ModelToJson(*model));
  return s.ok() ? kExitOk : ReportError(s);
}

// sdcb eval MODEL.sdcb -i POINTS.txt -o VALUES.txt [--derivatives]
int RunEval(const std::vector<std::string>& argv) {
  const Args args(argv, {"input", "output"}, {"derivatives"});
  args.RequirePositionals(
      1, "MODEL (usage: sdcb eval MODEL.sdcb -i POINTS.txt -o VALUES.txt)");
  const std::string input = args.Get("input"), output = args.Get("output");
  if (input.empty()) throw UsageError{"missing -i POINTS.txt"};
  if (output.empty()) throw UsageError{"missing -o VALUES.txt"};
  StatusOr<SplineModel> model = ReadSdcbFile(args.positionals()[0]);
  if (!model.ok()) return ReportError(model.status());

  const Status outputs = PrepareOutputs({output});
  if (!outputs.ok()) return ReportError(outputs);

  // Points: three numbers per non-empty line (a '#' starts a comment).
  std::ifstream in(input);
  if (!in) return ReportError(IoError(input + ": cannot open the points file"));
  std::vector<Eigen::Vector3d> points;
  std::vector<long long> line_numbers;
  std::string line;
  for (long long number = 1; std::getline(in, line); ++number) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream s(line);
    std::string token;
    std::vector<double> values;
    while (s >> token) {
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (*end != '\0' || !std::isfinite(v)) {
        return ReportError(
            InvalidInputError(input + ": line " + std::to_string(number) +
                              ": '" + token + "' is not a finite number"));
      }
      values.push_back(v);
    }
    if (values.empty()) continue;
    // Scaled by its largest coordinate first, a direction normalizes
    // without overflow (1e300) or underflow (1e-200); only zero cannot.
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    if (values.size() == 3)
      p = Eigen::Vector3d(values[0], values[1], values[2]);
    const double largest = p.cwiseAbs().maxCoeff();
    if (values.size() != 3 || !(largest > 0)) {
      return ReportError(InvalidInputError(input + ": line " +
                                           std::to_string(number) +
                                           " must hold three numbers, not all "
                                           "zero (a direction on the sphere)"));
    }
    points.push_back((p / largest).normalized());
    line_numbers.push_back(number);
  }
  StatusOr<SphericalSpline> surface = SurfaceFromModel(*model);
  if (!surface.ok()) {
    return ReportError(surface.status().WithPrefix(args.positionals()[0]));
  }
  Eigen::MatrixX3d directions(points.size(), 3);
  for (size_t i = 0; i < points.size(); ++i) directions.row(i) = points[i];
  const bool derivatives = args.Has("derivatives");
  Eigen::MatrixX3d positions, normals;
  if (derivatives) {
    const std::vector<SurfacePoint> jets =
        surface->EvaluateDifferentialMany(directions, JetOrder::kGradient);
    positions.resize(jets.size(), 3);
    normals.resize(jets.size(), 3);
    for (size_t i = 0; i < jets.size(); ++i) {
      positions.row(i) = jets[i].position;
      normals.row(i) = jets[i].normal;
    }
  } else {
    positions = surface->EvaluateMany(directions);
  }
  positions = model->transform.ToInput(positions);
  // Nothing non-finite is ever written: a model whose numbers overflow
  // (e.g. an extreme transform) is refused at the first such direction.
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    const bool finite = positions.row(i).allFinite() &&
                        (!derivatives || normals.row(i).allFinite());
    if (!finite) {
      return ReportError(InvalidInputError(
          args.positionals()[0] +
          ": the surface has no finite value at the "
          "direction on line " +
          std::to_string(line_numbers[i]) + " of " + input +
          " (the model's numbers overflow); nothing was written"));
    }
  }
  std::string text;
  char buffer[160];
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    std::snprintf(buffer, sizeof buffer, "%.17g %.17g %.17g", positions(i, 0),
                  positions(i, 1), positions(i, 2));
    text += buffer;
    if (derivatives) {
      std::snprintf(buffer, sizeof buffer, " %.17g %.17g %.17g", normals(i, 0),
                    normals(i, 1), normals(i, 2));
      text += buffer;
    }
    text += '\n';
  }
  const Status s = WriteTextOutput(output, text);
  return s.ok() ? kExitOk : ReportError(s);
}

}  // namespace sdcb::cli
