#include "sdcb/io/report/fit_statistics_json.h"

#include <limits>
#include <string>
#include <type_traits>
#include <variant>

#include "sdcb/core/fit/fit_options.h"

namespace sdcb {
namespace {

using nlohmann::json;

json RoundToJson(const RoundStatistics& r) {
  json out{{"round", r.round},
           {"knots", r.knots},
           {"control_points", r.control_points},
           {"rmse_percent", r.rmse_percent},
           {"max_error_percent", r.max_error_percent},
           {"vertex_rmse_percent", r.vertex_rmse_percent},
           {"vertex_max_error_percent", r.vertex_max_error_percent},
           {"folded_area_percent", r.folded_area_percent}};
  // Open parts only (a closed part's statistics read as before).
  if (r.boundary_error_percent >= 0) {
    out["boundary_error_percent"] = r.boundary_error_percent;
  }
  return out;
}

const char* ErrorMeasureName(ErrorMeasure m) {
  return m == ErrorMeasure::kVertices ? "vertices" : "dense_two_sided";
}

// Looks up `key` in the object `obj`; `where` names obj in messages.
StatusOr<const json*> Member(const json& obj, const char* key,
                             const std::string& where) {
  if (!obj.is_object()) {
    return InvalidInputError(where + " is not a JSON object");
  }
  const auto it = obj.find(key);
  if (it == obj.end()) {
    return InvalidInputError(where + " lacks the key \"" + key + "\"");
  }
  return &*it;
}

Status GetInt(const json& obj, const char* key, const std::string& where,
              int* out) {
  SDCB_ASSIGN_OR_RETURN(const json* v, Member(obj, key, where));
  if (v->is_number_unsigned()) {
    const auto u = v->get<uint64_t>();
    if (u > static_cast<uint64_t>(std::numeric_limits<int>::max())) {
      return InvalidInputError(where + "." + key + " is out of range");
    }
    *out = static_cast<int>(u);
    return Status::Ok();
  }
  if (v->is_number_integer()) {
    const auto i = v->get<int64_t>();
    if (i < std::numeric_limits<int>::min() ||
        i > std::numeric_limits<int>::max()) {
      return InvalidInputError(where + "." + key + " is out of range");
    }
    *out = static_cast<int>(i);
    return Status::Ok();
  }
  return InvalidInputError(where + "." + key + " is not an integer");
}

Status GetDouble(const json& obj, const char* key, const std::string& where,
                 double* out) {
  SDCB_ASSIGN_OR_RETURN(const json* v, Member(obj, key, where));
  if (!v->is_number()) {
    return InvalidInputError(where + "." + key + " is not a number");
  }
  *out = v->get<double>();
  return Status::Ok();
}

Status GetBool(const json& obj, const char* key, const std::string& where,
               bool* out) {
  SDCB_ASSIGN_OR_RETURN(const json* v, Member(obj, key, where));
  if (!v->is_boolean()) {
    return InvalidInputError(where + "." + key + " is not true or false");
  }
  *out = v->get<bool>();
  return Status::Ok();
}

// Getters for keys that older files lack: absent leaves *out unchanged.
template <typename T, typename Getter>
Status GetOptional(const json& obj, const char* key, const std::string& where,
                   T* out, Getter get) {
  if (!obj.is_object() || !obj.contains(key)) return Status::Ok();
  return get(obj, key, where, out);
}

// The record's "options": every recorded option of FitOptionTable under its
// key.
json RecordedOptionsToJson(const RecordedFitOptions& r) {
  json options = json::object();
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    std::visit(
        [&](auto field) {
          if constexpr (!std::is_same_v<decltype(field), std::monostate>) {
            options[d.key] = r.*field;
          }
        },
        d.recorded);
  }
  return options;
}

// Reads what RecordedOptionsToJson wrote: the keys of format version 1
// required, the others read when present.
Status RecordedOptionsFromJson(const json& obj, const std::string& where,
                               RecordedFitOptions* r) {
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    const bool required = d.required_in_record;
    Status status = Status::Ok();
    if (const auto* f = std::get_if<int RecordedFitOptions::*>(&d.recorded)) {
      status = required ? GetInt(obj, d.key, where, &(r->**f))
                        : GetOptional(obj, d.key, where, &(r->**f), GetInt);
    } else if (const auto* g =
                   std::get_if<double RecordedFitOptions::*>(&d.recorded)) {
      status = required ? GetDouble(obj, d.key, where, &(r->**g))
                        : GetOptional(obj, d.key, where, &(r->**g), GetDouble);
    } else if (const auto* h =
                   std::get_if<bool RecordedFitOptions::*>(&d.recorded)) {
      status = required ? GetBool(obj, d.key, where, &(r->**h))
                        : GetOptional(obj, d.key, where, &(r->**h), GetBool);
    }
    SDCB_RETURN_IF_ERROR(status);
  }
  return Status::Ok();
}

Status RoundFromJson(const json& obj, const std::string& where,
                     RoundStatistics* r) {
  SDCB_RETURN_IF_ERROR(GetInt(obj, "round", where, &r->round));
  SDCB_RETURN_IF_ERROR(GetInt(obj, "knots", where, &r->knots));
  SDCB_RETURN_IF_ERROR(
      GetInt(obj, "control_points", where, &r->control_points));
  SDCB_RETURN_IF_ERROR(GetDouble(obj, "rmse_percent", where, &r->rmse_percent));
  SDCB_RETURN_IF_ERROR(
      GetDouble(obj, "max_error_percent", where, &r->max_error_percent));
  // Version 1 measured at the vertices only.
  r->vertex_rmse_percent = r->rmse_percent;
  r->vertex_max_error_percent = r->max_error_percent;
  SDCB_RETURN_IF_ERROR(GetOptional(obj, "vertex_rmse_percent", where,
                                   &r->vertex_rmse_percent, GetDouble));
  SDCB_RETURN_IF_ERROR(GetOptional(obj, "vertex_max_error_percent", where,
                                   &r->vertex_max_error_percent, GetDouble));
  SDCB_RETURN_IF_ERROR(GetOptional(obj, "folded_area_percent", where,
                                   &r->folded_area_percent, GetDouble));
  return GetOptional(obj, "boundary_error_percent", where,
                     &r->boundary_error_percent, GetDouble);
}

}  // namespace

json FitStatisticsToJson(const FitStatistics& s) {
  json rounds = json::array();
  for (const RoundStatistics& r : s.rounds) rounds.push_back(RoundToJson(r));
  return json{{"rounds", std::move(rounds)},
              {"final", RoundToJson(s.final_result)},
              {"options", RecordedOptionsToJson(s.options)},
              {"error_measure", ErrorMeasureName(s.error_measure)},
              {"reached_target", s.reached_target}};
}

StatusOr<FitStatistics> FitStatisticsFromJson(const json& j) {
  FitStatistics s;
  const std::string where = "statistics";
  SDCB_ASSIGN_OR_RETURN(const json* rounds, Member(j, "rounds", where));
  if (!rounds->is_array()) {
    return InvalidInputError("statistics.rounds is not a JSON array");
  }
  s.rounds.resize(rounds->size());
  for (size_t i = 0; i < rounds->size(); ++i) {
    SDCB_RETURN_IF_ERROR(RoundFromJson(
        (*rounds)[i], "statistics.rounds[" + std::to_string(i) + "]",
        &s.rounds[i]));
  }
  SDCB_ASSIGN_OR_RETURN(const json* final_json, Member(j, "final", where));
  SDCB_RETURN_IF_ERROR(
      RoundFromJson(*final_json, "statistics.final", &s.final_result));

  SDCB_ASSIGN_OR_RETURN(const json* o, Member(j, "options", where));
  const std::string ow = "statistics.options";
  RecordedFitOptions& so = s.options;
  SDCB_RETURN_IF_ERROR(RecordedOptionsFromJson(*o, ow, &so));

  // Version 1 measured at the vertices and did not store the outcome.
  s.error_measure = ErrorMeasure::kVertices;
  if (j.contains("error_measure")) {
    const json& m = j["error_measure"];
    if (m == "dense_two_sided") {
      s.error_measure = ErrorMeasure::kDenseTwoSided;
    } else if (m != "vertices") {
      return InvalidInputError(
          "statistics.error_measure is not \"vertices\" or "
          "\"dense_two_sided\"");
    }
  }
  s.reached_target = s.final_result.rmse_percent <= so.rmse_percent;
  SDCB_RETURN_IF_ERROR(
      GetOptional(j, "reached_target", where, &s.reached_target, GetBool));
  return s;
}

nlohmann::ordered_json FitReportToJson(const FitResult& fit) {
  using ojson = nlohmann::ordered_json;
  const FitStatistics& stats = fit.model.statistics;
  const json record = FitStatisticsToJson(stats);
  ojson report;
  report["reached_target"] = stats.reached_target;
  if (!fit.shortfall.empty()) report["shortfall"] = fit.shortfall;
  report["basis_form"] =
      fit.model.basis_form == BasisForm::kRaw ? "raw" : "normalized";
  report["error_measure"] = record["error_measure"];
  ojson rounds = ojson::array();
  for (size_t i = 0; i < stats.rounds.size(); ++i) {
    ojson r = record["rounds"][i];
    r["seconds"] =
        i < fit.round_details.size() ? fit.round_details[i].timings.total : 0.0;
    rounds.push_back(std::move(r));
  }
  // The returned round (the last one, or the best when the target was
  // missed), with its seconds.
  ojson final_round = record["final"];
  const int returned = stats.final_result.round;
  final_round["seconds"] =
      returned >= 0 && returned < static_cast<int>(fit.round_details.size())
          ? fit.round_details[returned].timings.total
          : 0.0;
  report["final"] = std::move(final_round);
  report["rounds"] = std::move(rounds);
  report["options"] = record["options"];
  report["map"] = {{"vertices", fit.map_vertices},
                   {"split_retry_run", fit.split_retry_run},
                   {"split_retry_returned", fit.split_retry_returned},
                   {"lambda", fit.model.statistics.options.lambda},
                   {"lambda_retries_run", fit.lambda_retries_run}};
  report["features"] = {{"angle_degrees", fit.features.angle_degrees},
                        {"edges", fit.features.edges.size()},
                        {"curves", fit.features.curves.size()},
                        {"corners", fit.features.corners.size()},
                        {"used", fit.features_kept}};
  const StageTimings& t = fit.timings;
  report["timings"] = {{"parameterization", t.parameterization},
                       {"knot_placement", t.knot_placement},
                       {"configurations", t.configurations},
                       {"basis", t.basis},
                       {"solve", t.solve},
                       {"measure", t.measure},
                       {"total", t.total}};
  ojson details = ojson::array();
  for (size_t i = 0; i < fit.round_details.size(); ++i) {
    const RoundDetails& d = fit.round_details[i];
    details.push_back(
        {{"round", static_cast<int>(i)},
         {"knot_placement", d.timings.knot_placement},
         {"configurations", d.timings.configurations},
         {"basis", d.timings.basis},
         {"solve", d.timings.solve},
         {"measure", d.timings.measure},
         {"cvt_initial_energy", d.cvt_initial_energy},
         {"cvt_final_energy", d.cvt_final_energy},
         {"cvt_iterations", d.cvt_iterations},
         {"hole_retries", d.hole_retries},
         {"min_knot_separation_radians", d.min_knot_separation},
         {"data_samples", d.data_samples},
         {"unthinned_samples", d.unthinned_samples},
         {"split_triangles", d.split_triangles},
         {"min_samples_per_basis", d.min_samples_per_basis},
         {"surface_samples", d.surface_samples},
         {"closest_points", d.closest_points},
         {"mesh_samples", d.mesh_samples},
         {"mesh_to_surface_max_bound_percent",
          d.mesh_to_surface_max_bound_percent},
         {"round_rmse_percent", d.round_rmse_percent},
         {"estimated_rmse_percent", d.estimated_rmse_percent},
         {"folded_before_repair_percent", d.folded_before_repair_percent},
         {"fold_repair_iterations", d.fold_repair_iterations},
         {"fold_repaired", d.fold_repaired}});
  }
  report["round_details"] = std::move(details);
  return report;
}

}  // namespace sdcb
