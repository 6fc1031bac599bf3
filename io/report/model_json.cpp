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

json SourceToJson(const SourceMeshInfo& source) {
  return {{"vertices", source.num_vertices},
          {"faces", source.num_faces},
          {"hash", Hex64(source.hash)},
          {"file_name", source.file_name}};
}

// The keys of one spline (all of today's one-part dump but format_version).
json SplineToJson(const SplineModel& model) {
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
      {"source", SourceToJson(model.source)},
  };
  if (model.parameters.rows() > 0) {
    out["parameters"] = PointsToJson(model.parameters);
  }
  return out;
}

std::string Text(const json& j) {
  return j.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace

std::string ModelToJson(const SplineModel& model) {
  json out = SplineToJson(model);
  out["format_version"] = kSdcbFormatVersion;
  return Text(out);
}

std::string ModelToJson(const Model& model) {
  json parts = json::array();
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const ModelPart& part = model.parts[i];
    json p;
    if (part.kept) {
      const TriangleMesh& mesh = part.kept->mesh;
      json faces = json::array();
      for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
        faces.push_back(json::array(
            {mesh.faces(f, 0), mesh.faces(f, 1), mesh.faces(f, 2)}));
      }
      p = {{"reason", part.kept->reason},
           {"vertices", PointsToJson(mesh.vertices)},
           {"faces", std::move(faces)}};
    } else {
      p = SplineToJson(part.spline);
    }
    p["number"] = i + 1;
    p["name"] = part.name;
    p["kept"] = part.kept.has_value();
    p["trimmed"] = part.trimmed();
    json trims = json::array();
    for (const TrimLoop& loop : part.trims) {
      trims.push_back(PointsToJson(loop.points));
    }
    p["trims"] = std::move(trims);
    parts.push_back(std::move(p));
  }
  // One part: its spline's keys at the top too, as one-part dumps had them.
  json out = model.parts.size() == 1 && model.parts[0].fitted()
                 ? parts[0]
                 : json::object();
  for (const char* key : {"number", "name", "kept", "trimmed", "trims"}) {
    out.erase(key);
  }
  out["format_version"] = kSdcbFormatVersion;
  out["source"] = SourceToJson(model.source);
  out["parts"] = std::move(parts);
  return Text(out);
}

}  // namespace sdcb
