// `sdcb check` as users and pipelines run it: exit codes, one-sentence
// errors naming the file, the JSON keys of docs/CLI.md.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "testing/run_sdcb.h"

namespace sdcb {
namespace {

using testing::ExpectOneSentenceNaming;
using testing::FreshTestDir;
using testing::MeshPath;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;
using testing::WriteBytes;

TEST(CheckCliTest, GenusZeroMeshesAreOk) {
  const std::string dir = FreshTestDir();
  for (const char* name : {"bunny00.off", "fandisk_large.off", "fandisk.off",
                           "cow.off", "blobby.off", "sphere966.off"}) {
    SCOPED_TRACE(name);
    const std::string json = dir + "/" + name + ".json";
    const RunResult r = RunSdcb({"check", MeshPath(name), "--json", json}, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(ReadBytes(json));
    // CGAL's cow passes through itself (a warning, not an error); the
    // others do not, and are checked without a word.
    ASSERT_TRUE(j["self_intersections"].is_number()) << name;
    if (std::string(name) == "cow.off") {
      EXPECT_GT(j["self_intersections"].get<int>(), 0);
      EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
    } else {
      EXPECT_EQ(j["self_intersections"], 0);
      EXPECT_TRUE(r.err.empty()) << r.err;
    }
    for (const char* key :
         {"vertices", "faces", "boundary_edges", "non_manifold_edges",
          "components", "euler_characteristic", "genus", "degenerate_faces",
          "ok"}) {
      EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_EQ(j["ok"], true);
    EXPECT_EQ(j["genus"], 0);
    EXPECT_EQ(j["components"], 1);
    EXPECT_EQ(j["boundary_edges"], 0);
    // Closed triangle mesh: 2E = 3F and chi = V - E + F = 2.
    EXPECT_EQ(j["euler_characteristic"], 2);
    EXPECT_EQ(2 * j["vertices"].get<int>() - 4, j["faces"].get<int>());
    EXPECT_NE(r.out.find("genus"), std::string::npos) << "a table for people";
  }
}

TEST(CheckCliTest, HigherGenusIsRefusedWithItsGenus) {
  const std::string dir = FreshTestDir();
  const std::vector<std::pair<std::string, int>> cases = {
      {"elephant.off", 3}, {"eight.off", 2}, {"knot1.off", 1}};
  for (const auto& [name, genus] : cases) {
    SCOPED_TRACE(name);
    const std::string json = dir + "/" + name + ".json";
    const RunResult r = RunSdcb({"check", MeshPath(name), "--json", json}, dir);
    EXPECT_EQ(r.exit_code, 1);
    ExpectOneSentenceNaming(r, name);
    EXPECT_NE(r.err.find("genus " + std::to_string(genus)), std::string::npos)
        << r.err;
    // The report is still written: it is the answer, not partial output.
    const auto j = nlohmann::json::parse(ReadBytes(json));
    EXPECT_EQ(j["genus"], genus);
    EXPECT_EQ(j["ok"], false);
    // Closed orientable surface: chi = 2 - 2g.
    EXPECT_EQ(j["euler_characteristic"], 2 - 2 * genus);
  }
}

TEST(CheckCliTest, OpenSurfaceIsRefusedWithItsBoundary) {
  const std::string dir = FreshTestDir();
  const RunResult r =
      RunSdcb({"check", MeshPath("mushroom.off"), "--json", "-"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneSentenceNaming(r, "mushroom.off");
  EXPECT_NE(r.err.find("open surface"), std::string::npos) << r.err;
  const auto j =
      nlohmann::json::parse(r.out);  // --json - : only JSON on stdout
  const int boundary = j["boundary_edges"];
  EXPECT_GT(boundary, 0);
  EXPECT_NE(r.err.find(std::to_string(boundary) + " boundary edges"),
            std::string::npos)
      << r.err;
}

TEST(CheckCliTest, BadFilesGiveExitOneAndASentence) {
  const std::string dir = FreshTestDir();
  std::mt19937 rng(11);
  std::string random(4096, '\0');
  for (char& c : random) c = static_cast<char>(rng());
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty "
      "float x\n"
      "property float y\nproperty float z\nelement face 50\n"
      "property list uchar int vertex_indices\nend_header\n" +
      std::string(300, '\0');
  std::string stl(80, ' ');
  stl += std::string("\x10\x00\x00\x00", 4) + std::string(50 * 7, '\0');
  const std::vector<std::pair<std::string, std::string>> files = {
      {"empty.off", ""},
      {"random.ply", random},
      {"random.off", random},
      {"random.stl", random},
      {"random.obj", random},
      {"truncated.ply", ply},
      {"truncated.stl", stl},
      {"out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"},
      {"negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -3\n"},
      {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n"},
  };
  for (const auto& [name, bytes] : files) {
    SCOPED_TRACE(name);
    WriteBytes(dir + "/" + name, bytes);
    const RunResult r =
        RunSdcb({"check", dir + "/" + name, "--json", dir + "/x.json"}, dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    ExpectOneSentenceNaming(r, name);
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.json"))
        << "no output on bad input";
  }
  const RunResult missing = RunSdcb({"check", dir + "/missing.off"}, dir);
  EXPECT_EQ(missing.exit_code, 1);
  ExpectOneSentenceNaming(missing, "missing.off");
  const RunResult directory = RunSdcb({"check", dir}, dir);
  EXPECT_EQ(directory.exit_code, 1);
  ExpectOneSentenceNaming(directory, dir);
}

TEST(CheckCliTest, BadUsageGivesExitTwo) {
  const std::string dir = FreshTestDir();
  EXPECT_EQ(RunSdcb({}, dir).exit_code, 2);
  EXPECT_EQ(RunSdcb({"frobnicate"}, dir).exit_code, 2);
  EXPECT_EQ(RunSdcb({"check"}, dir).exit_code, 2);
  EXPECT_EQ(RunSdcb({"check", MeshPath("cow.off"), "--bogus"}, dir).exit_code,
            2);
  EXPECT_EQ(RunSdcb({"check", MeshPath("cow.off"), "--json"}, dir).exit_code,
            2);
  EXPECT_EQ(RunSdcb({"check", "a.off", "b.off"}, dir).exit_code, 2);
  const RunResult help = RunSdcb({"--help"}, dir);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("check"), std::string::npos);
}

TEST(CheckCliTest, UnwritableJsonIsExitOne) {
  const std::string dir = FreshTestDir();
  const RunResult r = RunSdcb(
      {"check", MeshPath("cow.off"), "--json", dir + "/no/such/dir/r.json"},
      dir);
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneSentenceNaming(r, "r.json");
}

}  // namespace
}  // namespace sdcb
