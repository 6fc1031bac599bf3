// Tests io/report/model_json.*: the dump parses back with nlohmann, has the
// keys docs/FORMAT.md lists, and its values are the model's (control points
// transformed to input coordinates, doubles exact); and the record of the fit
// options in it (io/report/fit_statistics_json.h) by core/fit/fit_options.h's
// table.
#include "sdcb/io/report/model_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "sdcb/core/fit/fit_options.h"
#include "sdcb/io/report/fit_statistics_json.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/spline_model_fixture.h"

namespace sdcb {
namespace {

using nlohmann::json;
using testing::MakeTestModel;

bool SameBits(double a, double b) { return std::memcmp(&a, &b, 8) == 0; }

// A model whose control points are ordinary numbers (the fixture's extremes
// would overflow when scaled back to input coordinates).
SplineModel OrdinaryModel(int parameters) {
  SplineModel m = MakeTestModel(2, 10, parameters);
  for (Eigen::Index i = 0; i < m.control_points.rows(); ++i) {
    m.control_points.row(i) << 0.1 * i - 0.5, std::sin(i), -0.0;
  }
  m.transform.scale = 37.5;
  m.transform.translation = Eigen::Vector3d(100.25, -3.0, 1.0 / 3.0);
  return m;
}

TEST(ModelJsonTest, KeysAndValues) {
  const SplineModel m = OrdinaryModel(4);
  const std::string text = ModelToJson(m);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  const json j = json::parse(text);

  EXPECT_EQ(j.at("format_version"), kSdcbFormatVersion);
  EXPECT_EQ(j.at("degree"), 2);

  ASSERT_EQ(j.at("knots").size(), 10u);
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(j["knots"][i].size(), 3u);
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(SameBits(j["knots"][i][c].get<double>(), m.knots(i, c)));
    }
  }

  const auto& sets = m.configurations.sets;
  ASSERT_EQ(j.at("basis").size(), sets.size());
  for (size_t i = 0; i < sets.size(); ++i) {
    const json& b = j["basis"][i];
    EXPECT_EQ(b.at("knots").get<std::vector<int>>(), sets[i].knots);
    ASSERT_EQ(b.at("configurations").size(), sets[i].boundaries.size());
    for (size_t t = 0; t < sets[i].boundaries.size(); ++t) {
      EXPECT_EQ((b["configurations"][t].get<std::array<int, 3>>()),
                sets[i].boundaries[t]);
    }
  }

  // Control points in input coordinates: scale * normalized + translation.
  const double s = 37.5;
  const Eigen::Vector3d tr(100.25, -3.0, 1.0 / 3.0);
  ASSERT_EQ(j.at("control_points").size(), sets.size());
  for (size_t i = 0; i < sets.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double expected = s * m.control_points(i, c) + tr[c];
      EXPECT_DOUBLE_EQ(j["control_points"][i][c].get<double>(), expected);
      EXPECT_TRUE(SameBits(j["control_points_normalized"][i][c].get<double>(),
                           m.control_points(i, c)));
    }
  }
  EXPECT_EQ(j["control_points"][0][2].get<double>(), 1.0 / 3.0);
  EXPECT_EQ(j["control_points"][2][0].get<double>(), s * (0.2 - 0.5) + 100.25);

  EXPECT_EQ(j.at("transform").at("scale"), 37.5);
  EXPECT_EQ(j["transform"].at("translation"),
            json::array({100.25, -3.0, 1.0 / 3.0}));

  const json& st = j.at("statistics");
  ASSERT_EQ(st.at("rounds").size(), 3u);
  EXPECT_EQ(st["rounds"][2].at("round"), 2);
  EXPECT_EQ(st["rounds"][2].at("knots"), 300);
  EXPECT_EQ(st["rounds"][2].at("control_points"), 270);
  EXPECT_EQ(st["rounds"][1].at("rmse_percent"), 1.0 / 4.0);
  EXPECT_EQ(st["rounds"][1].at("max_error_percent"), 2.0 / 3.0 + 1);
  EXPECT_TRUE(SameBits(st["rounds"][0].at("folded_area_percent").get<double>(),
                       std::numeric_limits<double>::denorm_min()));
  EXPECT_EQ(st["rounds"][1].at("vertex_rmse_percent"), 0.5 / 4.0);
  EXPECT_EQ(st["rounds"][1].at("vertex_max_error_percent"), 1.0 / 3.0 + 1);
  EXPECT_EQ(st.at("final"), st["rounds"][2]);
  EXPECT_FALSE(st.contains("timings"));  // the model keeps no wall times
  EXPECT_EQ(st.at("error_measure"), "dense_two_sided");
  EXPECT_EQ(st.at("reached_target"), true);
  EXPECT_EQ(st["options"].at("initial_knots"), 7);
  EXPECT_EQ(st["options"].at("max_control_points"), 5000);
  EXPECT_EQ(st["options"].at("alpha"), 4.0);
  EXPECT_EQ(st["options"].at("regularization"), 12.5);
  EXPECT_TRUE(std::signbit(st["options"].at("fairness").get<double>()));
  EXPECT_EQ(st["options"].at("samples_per_spacing"), 3.0);
  EXPECT_EQ(st["options"].at("final_surface_samples"), 100000);
  EXPECT_EQ(st["options"].at("thinned_cells_per_spacing"), 2.5);
  EXPECT_EQ(st["options"].at("final_mesh_samples"), 70000);
  EXPECT_EQ(st.at("options").at("degree"), 2);
  EXPECT_EQ(st["options"].at("rmse_percent"), 0.05);
  EXPECT_EQ(st["options"].at("knots_per_round"), 100);
  EXPECT_EQ(st["options"].at("max_rounds"), 10);
  EXPECT_EQ(st["options"].at("lambda"), 0.2);

  const json& src = j.at("source");
  EXPECT_EQ(src.at("vertices"), 4);
  EXPECT_EQ(src.at("faces"), 4);
  EXPECT_EQ(src.at("hash"), "0xfedcba9876543210");
  EXPECT_EQ(src.at("file_name"), "meshes/bunny \xc3\xa9.off");

  ASSERT_EQ(j.at("parameters").size(), 4u);
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(
          SameBits(j["parameters"][i][c].get<double>(), m.parameters(i, c)));
    }
  }
}

TEST(ModelJsonTest, ParametersOnlyWhenStoredAndDeterministic) {
  const SplineModel m = OrdinaryModel(0);
  const std::string text = ModelToJson(m);
  EXPECT_FALSE(json::parse(text).contains("parameters"));
  EXPECT_EQ(ModelToJson(OrdinaryModel(0)), text);
  // A file name that is not UTF-8 does not break the dump.
  SplineModel bad_name = m;
  bad_name.source.file_name = "mesh\xff.off";
  const json j = json::parse(ModelToJson(bad_name));
  EXPECT_EQ(j["source"]["file_name"], "mesh\xef\xbf\xbd.off");
}

TEST(ModelJsonTest, SameDumpAfterFileRoundTrip) {
  const SplineModel m = OrdinaryModel(4);
  const StatusOr<std::string> bytes = SerializeSdcb(m);
  ASSERT_TRUE(bytes.ok());
  const StatusOr<SplineModel> back = ParseSdcb(*bytes);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(ModelToJson(*back), ModelToJson(m));
}

// A FitOptions with each recorded option of FitOptionTable changed: the
// record's JSON changes, under the option's key, and reads back equal.
TEST(ModelJsonTest, EveryRecordedFitOptionRoundTripsThroughTheJson) {
  FitStatistics defaults;
  defaults.options = RecordFitOptions(FitOptions());
  const json base = FitStatisticsToJson(defaults);
  int changed = 0;
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    if (std::holds_alternative<std::monostate>(d.recorded)) continue;
    FitOptions o;
    if (const auto* f = std::get_if<int FitOptions::*>(&d.field)) {
      int& value = o.**f;
      value += 3;
    } else if (const auto* g = std::get_if<double FitOptions::*>(&d.field)) {
      double& value = o.**g;
      value = value * 0.5 + 0.1 + 0.2;  // not a short decimal
    } else {
      bool FitOptions::*b = std::get<bool FitOptions::*>(d.field);
      o.*b = !(o.*b);
    }
    FitStatistics s;
    s.options = RecordFitOptions(o);
    const json j = FitStatisticsToJson(s);
    EXPECT_NE(j["options"][d.key], base["options"][d.key]) << d.key;
    ASSERT_EQ(j["options"].size(), base["options"].size());
    const StatusOr<FitStatistics> back = FitStatisticsFromJson(j);
    ASSERT_TRUE(back.ok()) << back.status().message();
    EXPECT_EQ(FitStatisticsToJson(*back), j) << d.key;
    ++changed;
  }
  EXPECT_EQ(static_cast<size_t>(changed), base["options"].size());
}

// A record of a file older than feature_angle_degrees and keep_features
// reads them as 0 / false; one without a key of format version 1 is refused.
TEST(ModelJsonTest, OlderRecordsReadWithoutTheNewerKeys) {
  FitStatistics s;
  s.options = RecordFitOptions(FitOptions());
  json j = FitStatisticsToJson(s);
  j["options"].erase("feature_angle_degrees");
  j["options"].erase("keep_features");
  StatusOr<FitStatistics> back = FitStatisticsFromJson(j);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->options.feature_angle_degrees, 0.0);
  EXPECT_FALSE(back->options.keep_features);
  EXPECT_EQ(back->options.degree, 4);
  j["options"].erase("max_rounds");
  back = FitStatisticsFromJson(j);
  ASSERT_FALSE(back.ok());
  EXPECT_EQ(back.status().message(),
            "statistics.options lacks the key \"max_rounds\"");
}

TEST(ModelJsonTest, AModelOfPartsListsThemAndOnePartKeepsTheTopLevelKeys) {
  const SplineModel spline = MakeTestModel(1, 7, 0);
  Model one;
  one.parts.emplace_back();
  one.parts[0].spline = spline;
  one.source = spline.source;
  json top = json::parse(ModelToJson(one));
  const json single = json::parse(ModelToJson(spline));
  ASSERT_EQ(top["parts"].size(), 1u);
  json part = top["parts"][0];
  top.erase("parts");
  EXPECT_EQ(top, single);
  EXPECT_EQ(part["number"], 1);
  EXPECT_EQ(part["name"], "");
  EXPECT_EQ(part["trimmed"], false);
  EXPECT_EQ(part["trims"], json::array());
  EXPECT_EQ(part["kept"], false);
  for (const char* key : {"number", "name", "kept", "trimmed", "trims"}) {
    part.erase(key);
  }
  json spline_keys = single;
  spline_keys.erase("format_version");
  EXPECT_EQ(part, spline_keys);

  Model two = one;
  two.parts.push_back(one.parts[0]);
  two.parts[1].name = "b";
  two.parts[1].trims.resize(1);
  two.parts[1].trims[0].points.resize(3, 3);
  two.parts[1].trims[0].points << 1, 0, 0, 0, 1, 0, 0, 0, -0.0;
  two.source.file_name = "whole.off";
  const json j = json::parse(ModelToJson(two));
  EXPECT_FALSE(j.contains("knots"));
  EXPECT_EQ(j["source"]["file_name"], "whole.off");
  ASSERT_EQ(j["parts"].size(), 2u);
  EXPECT_EQ(j["parts"][1]["number"], 2);
  EXPECT_EQ(j["parts"][1]["name"], "b");
  EXPECT_EQ(j["parts"][1]["trimmed"], true);
  EXPECT_EQ(j["parts"][1]["trims"],
            json::parse("[[[1.0,0.0,0.0],[0.0,1.0,0.0],[0.0,0.0,-0.0]]]"));
  EXPECT_EQ(j["parts"][1]["source"], single["source"]);
}

TEST(ModelJsonTest, AKeptPartListsItsTrianglesAndWhy) {
  Model m;
  m.parts.resize(2);
  m.parts[0].spline = MakeTestModel(1, 7, 0);
  KeptMesh kept;
  kept.mesh.vertices.resize(3, 3);
  kept.mesh.vertices << 0.1, -0.0, 2, 1, 0, 0, 0, 1e-300, 0;
  kept.mesh.faces.resize(1, 3);
  kept.mesh.faces << 0, 2, 1;
  kept.reason = "part 2 (1 triangles) has no area";
  m.parts[1].kept = kept;
  const json j = json::parse(ModelToJson(m));
  EXPECT_FALSE(j.contains("knots"));
  const json& p = j["parts"][1];
  EXPECT_EQ(p["kept"], true);
  EXPECT_EQ(p["reason"], kept.reason);
  EXPECT_EQ(p["vertices"],
            json::parse("[[0.1,-0.0,2.0],[1.0,0.0,0.0],[0.0,1e-300,0.0]]"));
  EXPECT_EQ(p["faces"], json::parse("[[0,2,1]]"));
  EXPECT_FALSE(p.contains("knots"));
  EXPECT_EQ(j["parts"][0]["kept"], false);
  // One kept part alone: no spline keys at the top.
  m.parts.erase(m.parts.begin());
  EXPECT_FALSE(json::parse(ModelToJson(m)).contains("degree"));
}

}  // namespace
}  // namespace sdcb
