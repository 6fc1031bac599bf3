// `sdcb batch` as a pipeline uses it: 10 assets with 3 bad ones, a rerun,
// shards (explicit and from the Slurm / Kubernetes variables), a timeout.
// Oracles: the outputs read back through the io library (not the batch),
// file modification times, the manifest's own row numbering.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/run_sdcb.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::MeshPath;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;
using testing::WriteBytes;

namespace fs = std::filesystem;

// The variables that choose a shard when --shard is absent: a test run
// inside a Slurm array or a Kubernetes Job must not inherit them.
void ClearShardEnvironment() {
  for (const char* name :
       {"SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN",
        "SLURM_ARRAY_TASK_STEP", "JOB_COMPLETION_INDEX", "SDCB_SHARD_COUNT"}) {
    unsetenv(name);
  }
}

struct Row {
  std::string input, output, options;
  bool bad = false;
};

// 10 rows: 7 small closed genus-0 meshes fitted coarsely (one round,
// degree 4 then 3; every third also exported), and 3 bad inputs at rows 2,
// 5 and 8: a genus-4 mesh, a missing file, a file that is not a mesh.
// Outputs are relative to the manifest's folder.
std::vector<Row> TenRows(const std::string& dir) {
  WriteBytes(dir + "/garbage.off", "this is not a mesh\n");
  const std::string fit = "--rmse 1 --max-rounds 1";
  const char* meshes[] = {"ellipsoid", "geosphere",   "blob-closed",
                          "dragknob",  "icosahedron", "cube-meshed",
                          "sphere966"};
  std::vector<Row> rows;
  for (int n = 0; n < 7; ++n) {
    const std::string mesh = meshes[n];
    Row r;
    r.input = MeshPath(mesh + ".off");
    r.output = "out/" + std::to_string(n) + " " + mesh;
    r.options = fit + (n >= 4 ? " --degree 3" : "");
    if (n % 3 == 1) {
      r.output += ".obj";
      r.options += " --uniform 200";
    } else {
      r.output += ".sdcb";
    }
    rows.push_back(r);
  }
  rows.insert(rows.begin() + 2,
              {MeshPath("anchor.off"), "out/anchor.sdcb", fit, true});
  rows.insert(rows.begin() + 5,
              {dir + "/missing.off", "out/missing.sdcb", fit, true});
  rows.insert(rows.begin() + 8, {"garbage.off", "out/garbage.obj", fit, true});
  return rows;
}

std::string WriteManifest(const std::string& dir,
                          const std::vector<Row>& rows) {
  std::ostringstream m;
  m << "# sdcb batch test manifest\n\n";
  for (const Row& r : rows) {
    m << "\"" << r.input << "\"\t\"" << r.output << "\"  " << r.options
      << "   # a comment\n";
  }
  const std::string path = dir + "/manifest.txt";
  WriteBytes(path, m.str());
  return path;
}

std::vector<nlohmann::json> ReadLines(const std::string& path) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(ReadBytes(path));
  for (std::string line; std::getline(in, line);) {
    lines.push_back(nlohmann::json::parse(line));
  }
  return lines;
}

std::map<int, nlohmann::json> ByRow(const std::vector<nlohmann::json>& lines) {
  std::map<int, nlohmann::json> rows;
  for (const auto& l : lines) {
    EXPECT_TRUE(rows.emplace(l["row"].get<int>(), l).second)
        << "row " << l["row"] << " reported twice";
  }
  return rows;
}

int CountLinesContaining(const std::string& text, const std::string& what) {
  int n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    n += line.find(what) != std::string::npos;
  }
  return n;
}

std::set<int> Rows(const std::vector<nlohmann::json>& lines) {
  std::set<int> rows;
  for (const auto& l : lines) rows.insert(l["row"].get<int>());
  return rows;
}

TEST(BatchCliTest, TenAssetsThreeBadRerunAndShards) {
  ClearShardEnvironment();
  const std::string dir = FreshTestDir();
  const std::vector<Row> rows = TenRows(dir);
  ASSERT_EQ(rows.size(), 10u);
  const std::string manifest = WriteManifest(dir, rows);

  // First run: 7 outputs, 3 failure lines, exit 1.
  RunResult r = RunSdcb(
      {"batch", manifest, "--jobs", "2", "--json-lines", dir + "/run1.jsonl"},
      dir);
  EXPECT_FALSE(r.crashed);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(CountLinesContaining(r.err, ": failed: "), 3) << r.err;
  std::vector<nlohmann::json> lines = ReadLines(dir + "/run1.jsonl");
  ASSERT_EQ(lines.size(), 10u);
  std::map<int, nlohmann::json> by_row = ByRow(lines);
  std::map<std::string, fs::file_time_type> written;
  for (int i = 0; i < 10; ++i) {
    const Row& row = rows[i];
    const nlohmann::json& l = by_row.at(i);
    const std::string output = (fs::path(dir) / row.output).string();
    EXPECT_EQ(l["output"], output);
    if (row.bad) {
      EXPECT_EQ(l["status"], "failed") << l;
      // The failure names the input, on stderr and in the line.
      const std::string name = fs::path(row.input).filename().string();
      EXPECT_NE(l["error"].get<std::string>().find(name), std::string::npos)
          << l;
      EXPECT_EQ(CountLinesContaining(r.err, name), 1) << r.err;
      EXPECT_FALSE(fs::exists(output));  // no partial output
      continue;
    }
    ASSERT_EQ(l["status"], "ok") << l;
    const bool exports = fs::path(output).extension() == ".obj";
    const std::string model =
        exports ? fs::path(output).replace_extension(".sdcb").string() : output;
    // The numbers of the line are the model's own (read back by the io
    // library, not by the batch).
    StatusOr<SplineModel> m = ReadSdcbFile(model);
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_EQ(l["control_points"], m->statistics.final_result.control_points);
    EXPECT_DOUBLE_EQ(l["rmse_percent"].get<double>(),
                     m->statistics.final_result.rmse_percent);
    EXPECT_EQ(m->degree,
              row.options.find("--degree 3") != std::string::npos ? 3 : 4);
    if (exports) {
      StatusOr<TriangleMesh> mesh = ReadMesh(output);
      ASSERT_TRUE(mesh.ok()) << mesh.status().message();
      EXPECT_EQ(l["triangles"], mesh->num_faces());
      EXPECT_EQ(l["steps"], nlohmann::json({"fit", "export"}));
    }
    written[output] = fs::last_write_time(output);
  }
  EXPECT_EQ(written.size(), 7u);
  // No temporary or scratch files left next to the outputs.
  for (const auto& entry : fs::directory_iterator(dir + "/out")) {
    EXPECT_NE(entry.path().filename().string()[0], '.') << entry.path();
  }

  // Rerun: nothing to do for the 7; the 3 fail again.
  r = RunSdcb(
      {"batch", manifest, "--jobs", "2", "--json-lines", dir + "/run2.jsonl"},
      dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  by_row = ByRow(ReadLines(dir + "/run2.jsonl"));
  ASSERT_EQ(by_row.size(), 10u);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(by_row[i]["status"], rows[i].bad ? "failed" : "skipped")
        << by_row[i];
    if (!rows[i].bad) {
      EXPECT_TRUE(by_row[i]["steps"].empty());
      EXPECT_TRUE(by_row[i].contains("rmse_percent"));  // from the model
    }
  }
  for (const auto& [output, time] : written) {
    EXPECT_EQ(fs::last_write_time(output), time) << output << " rewritten";
  }

  // A lost export output whose model is still there: only the export runs.
  const int lost = 6;  // "out/4 icosahedron.obj"
  ASSERT_EQ(fs::path(rows[lost].output).extension(), ".obj");
  fs::remove(fs::path(dir) / rows[lost].output);
  r = RunSdcb({"batch", manifest, "--json-lines", dir + "/run3.jsonl"}, dir);
  by_row = ByRow(ReadLines(dir + "/run3.jsonl"));
  EXPECT_EQ(by_row[lost]["status"], "ok");
  EXPECT_EQ(by_row[lost]["steps"], nlohmann::json({"export"}));
  EXPECT_TRUE(fs::exists(fs::path(dir) / rows[lost].output));

  // Two shards cover every row exactly once; the environment variables of
  // Slurm arrays and Kubernetes Indexed Jobs choose the same rows.
  std::set<int> all;
  for (int shard = 0; shard < 2; ++shard) {
    const std::string s = std::to_string(shard);
    RunSdcb({"batch", manifest, "--shard", s + "/2", "--json-lines",
             dir + "/shard" + s + ".jsonl"},
            dir);
    const std::set<int> mine = Rows(ReadLines(dir + "/shard" + s + ".jsonl"));
    EXPECT_EQ(mine.size(), 5u);
    for (int row : mine) {
      EXPECT_EQ(row % 2, shard);
      EXPECT_TRUE(all.insert(row).second) << "row " << row << " twice";
    }
    // Slurm: --array=1-2 gives task ids 1 and 2.
    setenv("SLURM_ARRAY_TASK_ID", std::to_string(shard + 1).c_str(), 1);
    setenv("SLURM_ARRAY_TASK_MIN", "1", 1);
    setenv("SLURM_ARRAY_TASK_COUNT", "2", 1);
    r = RunSdcb({"batch", manifest, "--json-lines", dir + "/slurm.jsonl"}, dir);
    ClearShardEnvironment();
    EXPECT_EQ(Rows(ReadLines(dir + "/slurm.jsonl")), mine) << r.err;
    setenv("JOB_COMPLETION_INDEX", s.c_str(), 1);
    setenv("SDCB_SHARD_COUNT", "2", 1);
    r = RunSdcb({"batch", manifest, "--json-lines", dir + "/k8s.jsonl"}, dir);
    ClearShardEnvironment();
    EXPECT_EQ(Rows(ReadLines(dir + "/k8s.jsonl")), mine) << r.err;
  }
  EXPECT_EQ(all.size(), 10u);
}

TEST(BatchCliTest, ATimedOutRowIsStoppedAndLeavesNothing) {
  ClearShardEnvironment();
  const std::string dir = FreshTestDir();
  // A finished row first (no timeout), so that the second run's other row
  // does not depend on the machine's speed: it is skipped in-process.
  const std::string ico =
      MeshPath("icosahedron.off") + " out/ico.sdcb --rmse 5 --max-rounds 1\n";
  WriteBytes(dir + "/first.txt", ico);
  ASSERT_EQ(RunSdcb({"batch", dir + "/first.txt"}, dir).exit_code, 0);
  // bunny00 at the default 0.05 % takes far longer than 2 s on any machine.
  WriteBytes(dir + "/m.txt",
             MeshPath("bunny00.off") + " out/bunny.sdcb\n" + ico);
  const RunResult r = RunSdcb({"batch", dir + "/m.txt", "--timeout", "2",
                               "--json-lines", dir + "/l.jsonl"},
                              dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const std::map<int, nlohmann::json> rows = ByRow(ReadLines(dir + "/l.jsonl"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows.at(0)["status"], "failed");
  EXPECT_NE(rows.at(0)["error"].get<std::string>().find("timed out"),
            std::string::npos);
  EXPECT_EQ(rows.at(0)["signal"], 15);         // SIGTERM, the child cleaned up
  EXPECT_EQ(rows.at(1)["status"], "skipped");  // the batch went on
  for (const auto& entry : fs::directory_iterator(dir + "/out")) {
    EXPECT_EQ(entry.path().filename(), "ico.sdcb") << entry.path();
  }
}

TEST(BatchCliTest, AManifestErrorStopsBeforeAnyWork) {
  ClearShardEnvironment();
  const std::string dir = FreshTestDir();
  const std::string ok_row = MeshPath("icosahedron.off") + " out/a.sdcb\n";
  for (const std::string& bad :
       {std::string("x.off out/b.sdcb --no-such-option 1\n"),
        std::string("x.off out/b.sdcb --draco\n"),  // export option, .sdcb
        std::string("x.off out/a.sdcb\n"),          // same output twice
        std::string("x.off out/b.xyz\n"), std::string("x.off\n"),
        std::string("\"x.off out/b.sdcb\n")}) {
    WriteBytes(dir + "/m.txt", ok_row + bad);
    const RunResult r = RunSdcb({"batch", dir + "/m.txt"}, dir);
    EXPECT_EQ(r.exit_code, 1) << bad;
    testing::ExpectOneSentenceNaming(r, "m.txt");
    EXPECT_NE(r.err.find("line 2"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/out")) << bad;
  }
  EXPECT_EQ(RunSdcb({"batch", dir + "/m.txt", "--shard", "2/2"}, dir).exit_code,
            2);
}

}  // namespace
}  // namespace sdcb
