// `sdcb info`, `dump` and `eval --part` on a model of two parts (format
// version 4), built from two fitted one-part files of the fuzz corpus:
// what the commands print per part must be what those one-part files say.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/run_sdcb.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;

std::string CorpusFile(const std::string& name) {
  return std::string(SDCB_SOURCE_DIR) + "/fuzz/corpus/sdcb/" + name;
}

// Part 1: the degree-2 octahedron fit, unnamed and closed; part 2: the
// degree-3 one, named "lid", with two trim loops (4 and 3 points).
std::string WriteTwoPartModel(const std::string& dir) {
  StatusOr<SplineModel> a =
      ReadSdcbFile(CorpusFile("fit_octahedron_degree2.sdcb"));
  StatusOr<SplineModel> b =
      ReadSdcbFile(CorpusFile("fit_octahedron_degree3.sdcb"));
  EXPECT_TRUE(a.ok() && b.ok());
  Model m;
  m.parts.resize(2);
  m.parts[0].spline = *a;
  m.parts[1].spline = *b;
  m.parts[1].name = "lid";
  const double s = std::sqrt(0.5);
  TrimLoop square, triangle;
  square.points.resize(4, 3);
  square.points << s, 0, s, 0, s, s, -s, 0, s, 0, -s, s;
  triangle.points.resize(3, 3);
  triangle.points << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  m.parts[1].trims = {square, triangle};
  m.source = a->source;
  m.source.num_faces = 16;
  const std::string path = dir + "/two.sdcb";
  const Status written = WriteSdcbModelFile(m, path);
  EXPECT_TRUE(written.ok()) << written.message();
  return path;
}

TEST(ModelPartsCliTest, InfoListsEachPart) {
  const std::string dir = FreshTestDir();
  const std::string model = WriteTwoPartModel(dir);
  const RunResult r = RunSdcb({"info", model, "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["format_version"], 4);
  EXPECT_EQ(j["source"]["faces"], 16);
  EXPECT_FALSE(j.contains("degree"));  // per part only
  ASSERT_EQ(j["parts"].size(), 2u);
  const RunResult one = RunSdcb(
      {"info", CorpusFile("fit_octahedron_degree3.sdcb"), "--json", "-"}, dir);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto k = nlohmann::json::parse(one.out);
  const auto& p = j["parts"][1];
  EXPECT_EQ(p["number"], 2);
  EXPECT_EQ(p["name"], "lid");
  EXPECT_EQ(p["trimmed"], true);
  EXPECT_EQ(p["trim_loops"], 2);
  EXPECT_EQ(p["trim_points"], 7);
  for (const char* key : {"degree", "knots", "control_points", "rmse_percent",
                          "max_error_percent", "reached_target"}) {
    EXPECT_EQ(p[key], k[key]) << key;
  }
  EXPECT_EQ(j["parts"][0]["trimmed"], false);
  EXPECT_EQ(j["parts"][0]["trim_loops"], 0);
  EXPECT_EQ(j["parts"][0]["degree"], 2);
  // A one-part file keeps its top-level keys and gains a one-entry list.
  EXPECT_EQ(k["degree"], 3);
  ASSERT_EQ(k["parts"].size(), 1u);
  EXPECT_EQ(k["parts"][0]["knots"], k["knots"]);

  const RunResult text = RunSdcb({"info", model}, dir);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("parts                  2\n"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("part 1: closed;"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("part 2 \"lid\": trimmed (2 trim loops, 7 points)"),
            std::string::npos)
      << text.out;
}

TEST(ModelPartsCliTest, DumpHasAPartsArray) {
  const std::string dir = FreshTestDir();
  const std::string model = WriteTwoPartModel(dir);
  ASSERT_EQ(RunSdcb({"dump", model, "-o", dir + "/two.json"}, dir).exit_code,
            0);
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/two.json"));
  ASSERT_EQ(j["parts"].size(), 2u);
  EXPECT_FALSE(j.contains("knots"));
  const std::string one = CorpusFile("fit_octahedron_degree3.sdcb");
  ASSERT_EQ(RunSdcb({"dump", one, "-o", dir + "/one.json"}, dir).exit_code, 0);
  const auto k = nlohmann::json::parse(ReadBytes(dir + "/one.json"));
  const auto& p = j["parts"][1];
  EXPECT_EQ(p["name"], "lid");
  EXPECT_EQ(p["trimmed"], true);
  ASSERT_EQ(p["trims"].size(), 2u);
  ASSERT_EQ(p["trims"][1].size(), 3u);
  EXPECT_EQ(p["trims"][1][1], nlohmann::json::array({0.0, 0.0, -1.0}));
  for (const char* key : {"degree", "knots", "basis", "control_points",
                          "transform", "statistics", "source"}) {
    EXPECT_EQ(p[key], k[key]) << key;
  }
  // The one-part dump: today's keys at the top, and the same in parts[0].
  ASSERT_EQ(k["parts"].size(), 1u);
  EXPECT_EQ(k["parts"][0]["knots"], k["knots"]);
  EXPECT_EQ(k["parts"][0]["number"], 1);
  EXPECT_EQ(k["parts"][0]["trimmed"], false);
}

TEST(ModelPartsCliTest, EvalTakesAPart) {
  const std::string dir = FreshTestDir();
  const std::string model = WriteTwoPartModel(dir);
  testing::WriteBytes(dir + "/points.txt", "1 0 0\n0.3 -0.2 0.9\n0 0 -1\n");
  const auto eval = [&](std::vector<std::string> args) {
    RunResult r = RunSdcb(args, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return ReadBytes(dir + "/v.txt");
  };
  const std::vector<std::string> base = {
      "eval", model, "-i", dir + "/points.txt", "-o", dir + "/v.txt"};
  auto with = [&](std::vector<std::string> extra, const std::string& file) {
    std::vector<std::string> a = base;
    a[1] = file;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const std::string part2 = eval(with({"--part", "2"}, model));
  const std::string lone =
      eval(with({}, CorpusFile("fit_octahedron_degree3.sdcb")));
  EXPECT_EQ(part2, lone);
  EXPECT_EQ(eval(with({}, model)),
            eval(with({}, CorpusFile("fit_octahedron_degree2.sdcb"))));
  EXPECT_EQ(eval(with({"--part", "1"}, model)), eval(with({}, model)));
  EXPECT_NE(part2, eval(with({"--part", "1"}, model)));
  // Out of range: one sentence naming the file, exit 1, nothing written.
  std::filesystem::remove(dir + "/v.txt");
  const RunResult three = RunSdcb(with({"--part", "3"}, model), dir);
  EXPECT_EQ(three.exit_code, 1);
  EXPECT_NE(three.err.find("--part 3 does not exist; the model has 2 parts"),
            std::string::npos)
      << three.err;
  testing::ExpectOneSentenceNaming(three, model);
  EXPECT_FALSE(std::filesystem::exists(dir + "/v.txt"));
  const RunResult lone_part2 = RunSdcb(
      with({"--part", "2"}, CorpusFile("fit_octahedron_degree3.sdcb")), dir);
  EXPECT_EQ(lone_part2.exit_code, 1);
  EXPECT_NE(lone_part2.err.find("the model has 1 part\n"), std::string::npos)
      << lone_part2.err;
}

TEST(ModelPartsCliTest, ExportWritesEachPartAndStepRefusesTheTrimmedOne) {
  const std::string dir = FreshTestDir();
  const std::string model = WriteTwoPartModel(dir);
  RunResult r = RunSdcb(
      {"export", model, "-o", dir + "/out.obj", "--tolerance", "1", "--quiet"},
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string obj = ReadBytes(dir + "/out.obj");
  EXPECT_NE(obj.find("\no part1\n"), std::string::npos);
  EXPECT_NE(obj.find("\no lid\n"), std::string::npos);
  r = RunSdcb({"export", model, "-o", dir + "/out.step"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("part 2 is open (2 trim loops)"), std::string::npos)
      << r.err;
  testing::ExpectOneSentenceNaming(r, model);
}

}  // namespace
}  // namespace sdcb
