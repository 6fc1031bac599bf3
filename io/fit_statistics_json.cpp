#include "sdcb/io/fit_statistics_json.h"

#include <limits>
#include <string>

namespace sdcb {
namespace {

using nlohmann::json;

json RoundToJson(const RoundStatistics& r) {
  return json{{"round", r.round},
              {"knots", r.knots},
              {"control_points", r.control_points},
              {"rmse_percent", r.rmse_percent},
              {"max_error_percent", r.max_error_percent},
              {"seconds", r.seconds}};
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

Status RoundFromJson(const json& obj, const std::string& where,
                     RoundStatistics* r) {
  SDCB_RETURN_IF_ERROR(GetInt(obj, "round", where, &r->round));
  SDCB_RETURN_IF_ERROR(GetInt(obj, "knots", where, &r->knots));
  SDCB_RETURN_IF_ERROR(
      GetInt(obj, "control_points", where, &r->control_points));
  SDCB_RETURN_IF_ERROR(GetDouble(obj, "rmse_percent", where, &r->rmse_percent));
  SDCB_RETURN_IF_ERROR(
      GetDouble(obj, "max_error_percent", where, &r->max_error_percent));
  return GetDouble(obj, "seconds", where, &r->seconds);
}

}  // namespace

json FitStatisticsToJson(const FitStatistics& s) {
  json rounds = json::array();
  for (const RoundStatistics& r : s.rounds) rounds.push_back(RoundToJson(r));
  const StageTimings& t = s.timings;
  const RecordedFitOptions& o = s.options;
  return json{{"rounds", std::move(rounds)},
              {"final", RoundToJson(s.final_result)},
              {"timings",
               {{"parameterization", t.parameterization},
                {"knot_placement", t.knot_placement},
                {"configurations", t.configurations},
                {"basis", t.basis},
                {"solve", t.solve},
                {"total", t.total}}},
              {"options",
               {{"degree", o.degree},
                {"rmse_percent", o.rmse_percent},
                {"knots_per_round", o.knots_per_round},
                {"max_rounds", o.max_rounds},
                {"lambda", o.lambda}}}};
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

  SDCB_ASSIGN_OR_RETURN(const json* t, Member(j, "timings", where));
  const std::string tw = "statistics.timings";
  StageTimings& st = s.timings;
  SDCB_RETURN_IF_ERROR(
      GetDouble(*t, "parameterization", tw, &st.parameterization));
  SDCB_RETURN_IF_ERROR(GetDouble(*t, "knot_placement", tw, &st.knot_placement));
  SDCB_RETURN_IF_ERROR(GetDouble(*t, "configurations", tw, &st.configurations));
  SDCB_RETURN_IF_ERROR(GetDouble(*t, "basis", tw, &st.basis));
  SDCB_RETURN_IF_ERROR(GetDouble(*t, "solve", tw, &st.solve));
  SDCB_RETURN_IF_ERROR(GetDouble(*t, "total", tw, &st.total));

  SDCB_ASSIGN_OR_RETURN(const json* o, Member(j, "options", where));
  const std::string ow = "statistics.options";
  RecordedFitOptions& so = s.options;
  SDCB_RETURN_IF_ERROR(GetInt(*o, "degree", ow, &so.degree));
  SDCB_RETURN_IF_ERROR(GetDouble(*o, "rmse_percent", ow, &so.rmse_percent));
  SDCB_RETURN_IF_ERROR(GetInt(*o, "knots_per_round", ow, &so.knots_per_round));
  SDCB_RETURN_IF_ERROR(GetInt(*o, "max_rounds", ow, &so.max_rounds));
  SDCB_RETURN_IF_ERROR(GetDouble(*o, "lambda", ow, &so.lambda));
  return s;
}

}  // namespace sdcb
