// Commands that read a .sdcb model: info, dump, eval.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/report/fit_statistics_json.h"
#include "sdcb/io/report/model_json.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {

namespace {

size_t ConfigurationCount(const SplineModel& m) {
  size_t configurations = 0;
  for (const auto& set : m.configurations.sets) {
    configurations += set.boundaries.size();
  }
  return configurations;
}

size_t TrimPoints(const ModelPart& part) {
  size_t points = 0;
  for (const TrimLoop& loop : part.trims) points += loop.points.rows();
  return points;
}

// The keys `info --json` gives one spline (a one-part model's at the top).
void SplineInfoJson(const SplineModel& m, const SdcbPartStorage& storage,
                    nlohmann::ordered_json* out) {
  nlohmann::ordered_json& j = *out;
  const ControlPointQuantization& q = storage.quantization;
  const RoundStatistics& f = m.statistics.final_result;
  const bool dense = m.statistics.error_measure == ErrorMeasure::kDenseTwoSided;
  j["degree"] = m.degree;
  j["knots"] = m.knots.rows();
  j["control_points"] = m.control_points.rows();
  j["configurations"] = ConfigurationCount(m);
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
  j["knot_grid_bits"] = storage.knot_grid_bits;  // 0: knots stored exactly
  if (!q.lossless()) {
    j["quantization_error_bound_percent"] = q.surface_error_bound_percent();
    j["quantization_bound_measured"] = q.basis_sum_measured;
  }
}

// The text lines of one spline, each starting with `indent`.
void PrintSplineInfo(const SplineModel& m, const SdcbPartStorage& storage,
                     const char* indent) {
  const ControlPointQuantization& q = storage.quantization;
  const RoundStatistics& f = m.statistics.final_result;
  const bool dense = m.statistics.error_measure == ErrorMeasure::kDenseTwoSided;
  const int width = 24 - static_cast<int>(std::strlen(indent));
  std::printf("%s%-*s %d\n", indent, width, "degree", m.degree);
  std::printf("%s%-*s %lld\n", indent, width, "knots",
              static_cast<long long>(m.knots.rows()));
  std::printf("%s%-*s %lld\n", indent, width, "control points",
              static_cast<long long>(m.control_points.rows()));
  std::printf("%s%-*s %zu\n", indent, width, "configurations",
              ConfigurationCount(m));
  std::printf("%s%-*s %.5f%% (%s)\n", indent, width, "rmse", f.rmse_percent,
              dense ? "two-sided, dense" : "at the vertices");
  std::printf("%s%-*s %.5f%%\n", indent, width, "max error",
              f.max_error_percent);
  if (dense) {
    std::printf("%s%-*s %.5f%%\n", indent, width, "folded area",
                f.folded_area_percent);
  }
  std::printf("%s%-*s %s\n", indent, width, "reached target",
              m.statistics.reached_target ? "yes" : "no");
  std::printf("%s%-*s %zu\n", indent, width, "rounds",
              m.statistics.rounds.size());
  std::printf("%s%-*s %s (%lld vertices, %lld faces)\n", indent, width,
              "source", m.source.file_name.c_str(),
              static_cast<long long>(m.source.num_vertices),
              static_cast<long long>(m.source.num_faces));
  std::printf("%s%-*s %s\n", indent, width, "parameters stored",
              m.parameters.rows() ? "yes" : "no");
  if (storage.knot_grid_bits > 0) {
    std::printf("%s%-*s %d-bit grid (as fitted)\n", indent, width,
                "knots stored on", storage.knot_grid_bits);
  }
  if (q.lossless()) {
    std::printf("%s%-*s none (exact control points)\n", indent, width,
                "quantization");
  } else {
    std::printf("%s%-*s %d bits; surface within %.3g%% of the fit%s\n", indent,
                width, "quantization", q.bits, q.surface_error_bound_percent(),
                q.basis_sum_measured ? " (bound measured)" : "");
  }
}

}  // namespace

// sdcb info MODEL.sdcb [--json FILE]
int RunInfo(const std::vector<std::string>& argv) {
  const Args args(argv, {"json"}, {"quiet"});
  args.RequirePositionals(1,
                          "MODEL (usage: sdcb info MODEL.sdcb [--json FILE])");
  const std::string& path = args.positionals()[0];
  const Status outputs = PrepareOutputs({args.Get("json")});
  if (!outputs.ok()) return ReportError(outputs);
  SdcbFileInfo file;
  StatusOr<Model> model = ReadSdcbModelFile(path, &file);
  if (!model.ok()) return ReportError(model.status());
  const std::vector<ModelPart>& parts = model->parts;
  const bool one_part = parts.size() == 1;
  if (args.Has("json")) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["format_version"] = file.format_version;
    j["file_bytes"] = file.file_bytes;
    // A one-part model keeps the keys one-part files always had.
    if (one_part && parts[0].fitted()) {
      SplineInfoJson(parts[0].spline, file.parts[0], &j);
    }
    j["source"] = {{"file_name", model->source.file_name},
                   {"vertices", model->source.num_vertices},
                   {"faces", model->source.num_faces},
                   {"hash", model->source.hash}};
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (size_t i = 0; i < parts.size(); ++i) {
      nlohmann::ordered_json p;
      p["number"] = i + 1;
      p["name"] = parts[i].name;
      p["kept"] = parts[i].kept.has_value();
      if (parts[i].kept) {
        p["reason"] = parts[i].kept->reason;
        p["vertices"] = parts[i].kept->mesh.num_vertices();
        p["triangles"] = parts[i].kept->mesh.num_faces();
        list.push_back(std::move(p));
        continue;
      }
      p["trimmed"] = parts[i].trimmed();
      p["trim_loops"] = parts[i].trims.size();
      p["trim_points"] = TrimPoints(parts[i]);
      SplineInfoJson(parts[i].spline, file.parts[i], &p);
      list.push_back(std::move(p));
    }
    j["parts"] = std::move(list);
    const Status s = WriteTextOutput(
        args.Get("json"),
        j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    if (!s.ok()) return ReportError(s);
  }
  if (!args.Has("quiet") && args.Get("json") != "-") {
    std::printf("%s\n", path.c_str());
    std::printf("  %-22s %u (%llu bytes)\n", "format version",
                file.format_version,
                static_cast<unsigned long long>(file.file_bytes));
    if (one_part && parts[0].fitted() && !parts[0].trimmed() &&
        parts[0].name.empty()) {
      PrintSplineInfo(parts[0].spline, file.parts[0], "  ");
      return kExitOk;
    }
    std::printf("  %-22s %zu\n", "parts", parts.size());
    std::printf("  %-22s %s (%lld vertices, %lld faces)\n", "source",
                model->source.file_name.c_str(),
                static_cast<long long>(model->source.num_vertices),
                static_cast<long long>(model->source.num_faces));
    for (size_t i = 0; i < parts.size(); ++i) {
      const ModelPart& part = parts[i];
      const FitStatistics& st = part.spline.statistics;
      std::printf("  part %zu%s%s%s: ", i + 1, part.name.empty() ? "" : " \"",
                  part.name.c_str(), part.name.empty() ? "" : "\"");
      if (part.kept) {
        std::printf("kept as a mesh (%d triangles, %d vertices): %s\n",
                    part.kept->mesh.num_faces(), part.kept->mesh.num_vertices(),
                    part.kept->reason.c_str());
        continue;
      }
      std::printf("%s", part.trimmed() ? "trimmed" : "closed");
      if (part.trimmed()) {
        std::printf(" (%zu trim loop%s, %zu points)", part.trims.size(),
                    part.trims.size() == 1 ? "" : "s", TrimPoints(part));
      }
      std::printf(
          "; %lld knots, %lld control points; reached %s, rms %.5f%%, "
          "%s %.5f%%\n",
          static_cast<long long>(part.spline.knots.rows()),
          static_cast<long long>(part.spline.control_points.rows()),
          st.reached_target ? "yes" : "no", st.final_result.rmse_percent,
          st.error_measure == ErrorMeasure::kDenseTwoSided
              ? "Hausdorff"
              : "max at the vertices",
          st.final_result.max_error_percent);
      PrintSplineInfo(part.spline, file.parts[i], "      ");
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
  StatusOr<Model> model = ReadSdcbModelFile(args.positionals()[0]);
  if (!model.ok()) return ReportError(model.status());
  const Status s = WriteTextOutput(output, ModelToJson(*model));
  return s.ok() ? kExitOk : ReportError(s);
}

// sdcb eval MODEL.sdcb -i POINTS.txt -o VALUES.txt [--derivatives]
//      [--part N]
int RunEval(const std::vector<std::string>& argv) {
  const Args args(argv, {"input", "output", "part"}, {"derivatives"});
  args.RequirePositionals(
      1, "MODEL (usage: sdcb eval MODEL.sdcb -i POINTS.txt -o VALUES.txt)");
  const std::string input = args.Get("input"), output = args.Get("output");
  if (input.empty()) throw UsageError{"missing -i POINTS.txt"};
  if (output.empty()) throw UsageError{"missing -o VALUES.txt"};
  const int part = args.GetInt("part", 1, 1, std::numeric_limits<int>::max());
  StatusOr<Model> parts = ReadSdcbModelFile(args.positionals()[0]);
  if (!parts.ok()) return ReportError(parts.status());
  if (static_cast<size_t>(part) > parts->parts.size()) {
    return ReportError(InvalidInputError(
        args.positionals()[0] + ": --part " + std::to_string(part) +
        " does not exist; the model has " +
        std::to_string(parts->parts.size()) +
        (parts->parts.size() == 1 ? " part" : " parts")));
  }
  if (parts->parts[part - 1].kept) {
    return ReportError(InvalidInputError(
        args.positionals()[0] + ": part " + std::to_string(part) +
        " was kept as a mesh, not fitted; it has no surface to evaluate"));
  }
  // The part's spline everywhere on the sphere, trims or not.
  const SplineModel* model = &parts->parts[part - 1].spline;

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
