#include "sdcb/io/report/model_json.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "sdcb/io/report/fit_statistics_json.h"
#include "sdcb/io/sdcb/sdcb_file.h"

namespace sdcb {
namespace {

using nlohmann::json;

json PointsToJson(const Eigen::MatrixX3d& points) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    rows.push_back(json::array({points(i, 0), points(i, 1), points(i, 2)}));
  }
  return rows;
}

std::string Hex64(uint64_t v) {
  char buffer[19];
  std::snprintf(buffer, sizeof buffer, "0x%016llx",
                static_cast<unsigned long long>(v));
  return buffer;
}

}  // namespace

std::string ModelToJson(const SplineModel& model) {
  json basis = json::array();
  for (const ConfigurationSet& set : model.configurations.sets) {
    json triples = json::array();
    for (const std::array<int, 3>& t : set.boundaries) {
      triples.push_back(json::array({t[0], t[1], t[2]}));
    }
    basis.push_back(
        json{{"knots", set.knots}, {"configurations", std::move(triples)}});
  }
  const NormalizingTransform& t = model.transform;
  json out{
      {"format_version", kSdcbFormatVersion},
      {"degree", model.degree},
      {"knots", PointsToJson(model.knots)},
      {"basis", std::move(basis)},
      {"control_points", PointsToJson(t.ToInput(model.control_points))},
      {"control_points_normalized", PointsToJson(model.control_points)},
      {"transform",
       {{"scale", t.scale},
        {"translation",
         json::array({t.translation[0], t.translation[1], t.translation[2]})},
        {"definition", "input = scale * normalized + translation"}}},
      {"statistics", FitStatisticsToJson(model.statistics)},
      {"source",
       {{"vertices", model.source.num_vertices},
        {"faces", model.source.num_faces},
        {"hash", Hex64(model.source.hash)},
        {"file_name", model.source.file_name}}},
  };
  if (model.parameters.rows() > 0) {
    out["parameters"] = PointsToJson(model.parameters);
  }
  return out.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace sdcb
