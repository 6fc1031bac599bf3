// `sdcb check` as users and pipelines run it: exit codes, one-sentence
// errors naming the file, the JSON keys of docs/CLI.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "testing/run_sdcb.h"
#include "testing/seam_split_cube.h"

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

TEST(CheckCliTest, AnOpenGenusZeroSurfaceIsOk) {
  // CGAL's mushroom is a disk: one part, one boundary loop, chi = 1.
  const std::string dir = FreshTestDir();
  const RunResult r =
      RunSdcb({"check", MeshPath("mushroom.off"), "--json", "-"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const auto j =
      nlohmann::json::parse(r.out);  // --json - : only JSON on stdout
  EXPECT_GT(j["boundary_edges"].get<int>(), 0);
  EXPECT_EQ(j["boundary_loops"], 1);
  EXPECT_EQ(j["euler_characteristic"], 1);
  EXPECT_EQ(j["ok"], true);
  ASSERT_EQ(j["parts"].size(), 1u);
  const auto& part = j["parts"][0];
  EXPECT_EQ(part["closed"], false);
  EXPECT_EQ(part["boundary_loops"], 1);
  EXPECT_EQ(part["genus"], 0);
  EXPECT_EQ(part["fittable"], true);
  EXPECT_EQ(part["triangles"], j["faces"]);
}

// Two copies of the corner tetrahedron, the second at x = 5 and written
// first, with the vertex (3, 3, 3) between them used by no triangle; then
// `extra` faces over `extra_vertices` appended.
std::string TwoTetrahedraOff(const std::string& extra_vertices = "",
                             const std::string& extra_faces = "",
                             int extra_v = 0, int extra_f = 0) {
  return "OFF\n" + std::to_string(9 + extra_v) + " " +
         std::to_string(8 + extra_f) +
         " 0\n"
         "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 3 3\n"
         "5 0 0\n6 0 0\n5 1 0\n5 0 1\n" +
         extra_vertices +
         "3 5 7 6\n3 5 6 8\n3 6 7 8\n3 5 8 7\n"
         "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n" +
         extra_faces;
}

TEST(CheckCliTest, EachPartIsReported) {
  const std::string dir = FreshTestDir();
  WriteBytes(dir + "/two.off", TwoTetrahedraOff());
  RunResult r = RunSdcb({"check", dir + "/two.off", "--json", "-"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  // Today's keys describe the whole mesh.
  EXPECT_EQ(j["vertices"], 9);
  EXPECT_EQ(j["faces"], 8);
  EXPECT_EQ(j["components"], 2);
  EXPECT_EQ(j["unreferenced_vertices"], 1);
  EXPECT_EQ(j["euler_characteristic"], 4);
  EXPECT_EQ(j["ok"], true);
  EXPECT_EQ(j["problem"], "");
  EXPECT_EQ(j["self_intersections"], 0);
  ASSERT_EQ(j["parts"].size(), 2u);
  for (int p = 0; p < 2; ++p) {
    const auto& part = j["parts"][p];
    EXPECT_EQ(part["number"], p + 1);
    EXPECT_EQ(part["triangles"], 4);
    EXPECT_EQ(part["vertices"], 4);
    EXPECT_EQ(part["closed"], true);
    EXPECT_EQ(part["boundary_loops"], 0);
    EXPECT_EQ(part["genus"], 0);
    EXPECT_EQ(part["manifold"], true);
    EXPECT_EQ(part["fittable"], true);
    EXPECT_EQ(part["problem"], "");
  }
  r = RunSdcb({"check", dir + "/two.off"}, dir);
  EXPECT_NE(r.out.find("part 2: 4 triangles, 4 vertices, closed, genus 0, "
                       "fittable"),
            std::string::npos)
      << r.out;
}

TEST(CheckCliTest, APartSdcbCannotFitIsNamed) {
  // A third part: two triangles that share only the vertex (10, 0, 0), a
  // bowtie.
  const std::string dir = FreshTestDir();
  WriteBytes(dir + "/bowtie.off",
             TwoTetrahedraOff("10 0 0\n11 0 0\n11 1 0\n9 0 0\n9 -1 0\n",
                              "3 9 10 11\n3 9 12 13\n", 5, 2));
  const RunResult r =
      RunSdcb({"check", dir + "/bowtie.off", "--json", dir + "/b.json"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneSentenceNaming(r, "bowtie.off");
  const std::string sentence =
      "part 3 (2 triangles) is not manifold (1 vertex where several sheets "
      "meet); sdcb fits manifold parts";
  EXPECT_EQ(r.err, "sdcb: " + dir + "/bowtie.off: " + sentence + "\n");
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/b.json"));
  EXPECT_EQ(j["ok"], false);
  EXPECT_EQ(j["problem"], sentence);
  ASSERT_EQ(j["parts"].size(), 3u);
  EXPECT_EQ(j["parts"][0]["fittable"], true);
  EXPECT_EQ(j["parts"][2]["manifold"], false);
  EXPECT_EQ(j["parts"][2]["fittable"], false);
  EXPECT_TRUE(j["self_intersections"].is_null());
}

TEST(CheckCliTest, AGenusTwoPartWithHolesIsNamedAsTheIssueWrites) {
  // CGAL's double torus with three holes; the sentence of issue 54.
  const std::string dir = FreshTestDir();
  const RunResult r =
      RunSdcb({"check", MeshPath("double-torus-3-holes.off")}, dir);
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneSentenceNaming(r, "double-torus-3-holes.off");
  EXPECT_NE(r.err.find("double-torus-3-holes.off: part 1 (428 triangles) has "
                       "genus 2 and 3 boundary loops; sdcb fits genus-0 "
                       "parts\n"),
            std::string::npos)
      << r.err;
}

TEST(CheckCliTest, BonesIsTwentySixClosedGenusZeroParts) {
  const std::string dir = FreshTestDir();
  const RunResult r =
      RunSdcb({"check", MeshPath("bones.off"), "--json", "-"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["ok"], true);
  ASSERT_EQ(j["parts"].size(), 26u);
  int triangles = 0, vertices = 0;
  for (const auto& part : j["parts"]) {
    EXPECT_EQ(part["closed"], true);
    EXPECT_EQ(part["genus"], 0);
    EXPECT_EQ(part["fittable"], true);
    // A closed genus-0 triangle mesh: F = 2V - 4.
    EXPECT_EQ(part["triangles"].get<int>(),
              2 * part["vertices"].get<int>() - 4);
    triangles += part["triangles"].get<int>();
    vertices += part["vertices"].get<int>();
  }
  EXPECT_EQ(triangles, j["faces"].get<int>());
  EXPECT_EQ(vertices,
            j["vertices"].get<int>() - j["unreferenced_vertices"].get<int>());
}

TEST(CheckCliTest, CheckAndFitRefuseCoordinatesTooLarge) {
  // The corner tetrahedron with its apex at 1e308: the area of its faces
  // there overflows, which the fit refuses.
  const std::string dir = FreshTestDir();
  WriteBytes(dir + "/big.off",
             "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1e308\n"
             "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
  const RunResult check = RunSdcb({"check", dir + "/big.off"}, dir);
  EXPECT_EQ(check.exit_code, 1);
  ExpectOneSentenceNaming(check, "big.off");
  EXPECT_NE(check.err.find("part 1 (4 triangles) has coordinates too large"),
            std::string::npos)
      << check.err;
  const RunResult fit = RunSdcb(
      {"fit", dir + "/big.off", "-o", dir + "/big.sdcb", "--quiet"}, dir);
  EXPECT_EQ(fit.exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir + "/big.sdcb"));
}

TEST(CheckCliTest, MorePartsThanMaxPartsAreRefusedWithTheCount) {
  const std::string dir = FreshTestDir();
  WriteBytes(dir + "/two.off", TwoTetrahedraOff());
  RunResult r = RunSdcb({"check", dir + "/two.off", "--max-parts", "1",
                         "--json", dir + "/t.json"},
                        dir);
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneSentenceNaming(r, "two.off");
  EXPECT_NE(r.err.find("two.off: mesh has 2 parts, more than --max-parts 1"),
            std::string::npos)
      << r.err;
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/t.json"));
  EXPECT_TRUE(j["parts"].is_null());
  EXPECT_EQ(j["ok"], false);
  EXPECT_EQ(j["components"], 2);
  EXPECT_EQ(
      RunSdcb({"check", dir + "/two.off", "--max-parts", "2"}, dir).exit_code,
      0);
  // 10,000 disjoint triangles (a soup): refused at the default limit.
  std::string soup = "OFF\n30000 10000 0\n";
  for (int i = 0; i < 10000; ++i) {
    soup += std::to_string(i) + " 0 0\n" + std::to_string(i) + ".5 0 0\n" +
            std::to_string(i) + " 0.5 0\n";
  }
  for (int i = 0; i < 10000; ++i) {
    soup += "3 " + std::to_string(3 * i) + " " + std::to_string(3 * i + 1) +
            " " + std::to_string(3 * i + 2) + "\n";
  }
  WriteBytes(dir + "/soup.off", soup);
  r = RunSdcb({"check", dir + "/soup.off"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "sdcb: " + dir +
                       "/soup.off: mesh has 10,000 parts, more than "
                       "--max-parts 1000\n");
  EXPECT_EQ(
      RunSdcb({"check", dir + "/two.off", "--max-parts", "-1"}, dir).exit_code,
      2);
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
      {"negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"},
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

// The unit cube as OBJ writers with per-face normals store it: 24 vertices,
// each quad with its own four (and its own vt / vn). Without the weld it is
// six open quads; welded, the 8-corner cube.
TEST(CheckCliTest, SeamSplitCubeIsWeldedWithoutRepair) {
  const std::string dir = FreshTestDir();
  std::string obj = "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n";
  for (const auto& quad : testing::kCubeQuads) {
    for (int c : quad) {
      const double* p = testing::kCubeCorners[c];
      obj += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
             std::to_string(p[2]) + "\n";
    }
    obj += "f -4/1/1 -3/2/1 -2/3/1 -1/4/1\n";
  }
  WriteBytes(dir + "/cube24.obj", obj);
  const RunResult r =
      RunSdcb({"check", dir + "/cube24.obj", "--json", dir + "/c.json"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "sdcb: " + dir +
                       "/cube24.obj: merged 16 vertices split at equal "
                       "positions (UV or normal seams)\n");
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/c.json"));
  EXPECT_EQ(j["seam_vertices_merged"], 16);
  EXPECT_EQ(j["vertices"], 8);
  EXPECT_EQ(j["faces"], 12);
  EXPECT_EQ(j["boundary_edges"], 0);
  EXPECT_EQ(j["repaired"], false);
  ASSERT_EQ(j["parts"].size(), 1u);
  EXPECT_EQ(j["parts"][0]["closed"], true);
  EXPECT_EQ(j["ok"], true);
}

// Three fins on one segment, each with its own copies of the segment's
// ends: welding would give the segment three triangles, so the copies stay
// apart, and the refusal that follows names --repair.
TEST(CheckCliTest, ADeclinedWeldIsNamedInTheRefusal) {
  const std::string dir = FreshTestDir();
  WriteBytes(dir + "/fins.obj",
             "v 0 0 0\nv 0 0 1\nv 1 0 0.5\nv 0 0 0\nv 0 0 1\nv 0 1 0.5\n"
             "v 0 0 0\nv 0 0 1\nv -1 -1 0.5\nf 1 2 3\nf 4 5 6\nf 7 8 9\n");
  const RunResult r = RunSdcb({"check", dir + "/fins.obj", "--max-parts", "2",
                               "--json", dir + "/c.json"},
                              dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("fins.obj: mesh has 3 parts, more than --max-parts 2; "
                       "4 vertices at the positions of others were left "
                       "apart (merging them would make 1 edge non-manifold): "
                       "--repair merges them\n"),
            std::string::npos)
      << r.err;
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/c.json"));
  EXPECT_EQ(j["seam_vertices_merged"], 0);
  EXPECT_EQ(j["seam_vertices_left_apart"], 4);
}

// Two triangles on one edge, the second's normal `degrees` from the first's
// by construction: (0 0 1) rotated about the shared edge's normal plane,
// n = (-sin t / sqrt 2, -sin t / sqrt 2, cos t). An edge turns back when the
// normals are more than 150 degrees apart: the warning names it and the
// JSON counts it; at 140 degrees it is a sharp edge, not a turn.
std::string HingeOff(double degrees) {
  const double t = degrees * 3.14159265358979323846 / 180.0;
  // v3 = v2 + (0.5 + c, -0.5 + c, h): (v1 - v2) x (v3 - v2) = (-h, -h, 2c).
  const double c = 0.5 * std::cos(t), h = std::sin(t) / std::sqrt(2.0);
  char v3[96];
  std::snprintf(v3, sizeof v3, "%.17g %.17g %.17g\n", 0.5 + c, 0.5 + c, h);
  return std::string("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n") + v3 +
         "3 0 1 2\n3 2 1 3\n";
}

TEST(CheckCliTest, AnEdgeWhereTheMeshTurnsBackIsCountedAndNamed) {
  const std::string dir = FreshTestDir();
  for (const double degrees : {160.0, 140.0}) {
    SCOPED_TRACE(degrees);
    WriteBytes(dir + "/hinge.off", HingeOff(degrees));
    const RunResult r = RunSdcb(
        {"check", dir + "/hinge.off", "--json", dir + "/hinge.json"}, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(ReadBytes(dir + "/hinge.json"));
    const bool turns = degrees > 150;
    EXPECT_EQ(j["turn_back_edges"], turns ? 1 : 0);
    EXPECT_EQ(
        r.err.find("turns back on itself at 1 edge ") != std::string::npos,
        turns)
        << r.err;
  }
}

}  // namespace
}  // namespace sdcb
