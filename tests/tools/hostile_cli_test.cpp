// The CLI against hostile situations: outputs checked before any work,
// interrupted runs that leave no temporary file, self-intersection
// warnings, --repair, and eval that never writes a non-finite number.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/mesh/mesh_writer.h"
#include "sdcb/io/sdcb/sdcb_file.h"
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

namespace fs = std::filesystem;

// Names in `dir`, except the captured stdout/stderr of RunSdcb.
std::vector<std::string> Listing(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name != ".stdout" && name != ".stderr") names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(HostileCliTest, OutputsAreCheckedBeforeTheInput) {
  // The output's problem is reported although the mesh does not even
  // exist: it was checked first, before any reading or fitting.
  const std::string dir = FreshTestDir();
  const std::string missing_mesh = dir + "/no_such_mesh.off";
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"fit", missing_mesh, "-o", dir + "/no/such/folder/m.sdcb"},
           {"fit", missing_mesh, "-o", dir + "/m.sdcb", "--json",
            dir + "/no/r.json"},
           {"fit", missing_mesh, "-o", dir},
           {"param", missing_mesh, "-o", dir + "/no/s.off"},
           {"check", missing_mesh, "--json", dir + "/no/c.json"}}) {
    SCOPED_TRACE(args[0] + " " + args.back());
    const RunResult r = RunSdcb(args, dir);
    EXPECT_EQ(r.exit_code, 1);
    ExpectOneSentenceNaming(r, fs::path(args.back()).filename().string());
    EXPECT_EQ(r.err.find("no_such_mesh"), std::string::npos) << r.err;
  }
  // A read-only folder (unless running as root, which may write anyway).
  fs::create_directories(dir + "/ro");
  fs::permissions(dir + "/ro", fs::perms::owner_read | fs::perms::owner_exec);
  if (::access((dir + "/ro").c_str(), W_OK) != 0) {
    const RunResult r =
        RunSdcb({"fit", missing_mesh, "-o", dir + "/ro/m.sdcb"}, dir);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("ro/m.sdcb"), std::string::npos) << r.err;
  }
  fs::permissions(dir + "/ro", fs::perms::owner_all);
  EXPECT_EQ(Listing(dir), std::vector<std::string>{"ro"});
  EXPECT_TRUE(fs::is_empty(dir + "/ro")) << "the probe file was removed";
}

// Starts `sdcb args...` with stdout/stderr to /dev/null; returns its pid.
pid_t Spawn(const std::vector<std::string>& args) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_RDWR);
    ::dup2(null, 1);
    ::dup2(null, 2);
    std::vector<char*> argv = {const_cast<char*>(SDCB_BINARY)};
    for (const std::string& a : args)
      argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(SDCB_BINARY, argv.data());
    ::_exit(127);
  }
  return pid;
}

// Runs `sdcb eval` writing into `dir`, and sends `signal_number` while a
// temporary file of its output exists (seen through inotify, the process
// frozen by SIGSTOP at that moment): the probe of the output check (the
// first, ".0") or, with `only_the_write`, the file being written. Returns
// whether that moment was caught; the process must have died by the signal.
bool InterruptWhileWriting(const std::vector<std::string>& eval_args,
                           const std::string& dir, int signal_number,
                           bool only_the_write) {
  const int watch = ::inotify_init1(IN_CLOEXEC);
  ::inotify_add_watch(watch, dir.c_str(), IN_CREATE);
  const pid_t pid = Spawn(eval_args);
  bool caught = false, exited = false;
  int status = 0;
  alignas(inotify_event) char buffer[4096];
  while (!caught && !exited) {
    pollfd ready = {watch, POLLIN, 0};
    if (::poll(&ready, 1, 50) <= 0) {
      exited = ::waitpid(pid, &status, WNOHANG) == pid;
      continue;
    }
    const ssize_t n = ::read(watch, buffer, sizeof buffer);
    if (n <= 0) break;
    for (char* p = buffer; p < buffer + n;) {
      const auto* event = reinterpret_cast<const inotify_event*>(p);
      p += sizeof(inotify_event) + event->len;
      const std::string name = event->len > 0 ? event->name : "";
      if (caught || name.find(".tmp.") == std::string::npos) continue;
      if (only_the_write && name.size() > 2 &&
          name.compare(name.size() - 2, 2, ".0") == 0) {
        continue;
      }
      ::kill(pid, SIGSTOP);
      // The output-check probe lives for microseconds; wait for the real
      // temporary file if this one is gone already.
      caught = fs::exists(dir + "/" + name);
      if (!caught) ::kill(pid, SIGCONT);
    }
  }
  if (caught) {
    ::kill(pid, signal_number);
    ::kill(pid, SIGCONT);
  }
  if (!exited) ::waitpid(pid, &status, 0);
  ::close(watch);
  if (caught) {
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal_number)
        << "status " << status;
  }
  return caught;
}

// A coarse model of blobby.off (one round), written into `dir`.
std::string FitQuickModel(const std::string& dir) {
  const std::string model = dir + "/blobby.sdcb";
  EXPECT_EQ(RunSdcb({"fit", MeshPath("blobby.off"), "-o", model, "--max-rounds",
                     "1", "--rmse", "1", "--quiet"},
                    dir)
                .exit_code,
            0);
  return model;
}

TEST(HostileCliTest, InterruptedRunsLeaveNoTemporaryFile) {
  const std::string dir = FreshTestDir();
  const std::string model = FitQuickModel(dir);
  // Enough directions that writing the values (3.7 MB) takes a while.
  std::string points;
  for (int i = 0; i < 60000; ++i) {
    points += std::to_string(std::sin(i)) + " " + std::to_string(std::cos(i)) +
              " " + std::to_string(std::sin(0.5 * i)) + "\n";
  }
  WriteBytes(dir + "/points.txt", points);
  ASSERT_EQ(RunSdcb({"eval", model, "-i", dir + "/points.txt", "-o",
                     dir + "/complete.txt"},
                    dir)
                .exit_code,
            0);
  const std::string complete = ReadBytes(dir + "/complete.txt");
  const std::string out_dir = dir + "/out";
  // SIGTERM while the output is written; SIGINT while the output check's
  // probe (or the output) exists. What may be left: nothing, or the whole
  // output if its rename into place came first (the process resumes
  // before its signal thread runs; a finished output is complete and
  // stays, tools/interrupts.h). Never a temporary or a partial file.
  for (const auto& [signal_number, only_the_write] :
       {std::pair{SIGTERM, true}, std::pair{SIGINT, false}}) {
    SCOPED_TRACE(std::to_string(signal_number) +
                 (only_the_write ? " during the write" : ""));
    bool caught = false;
    for (int attempt = 0; attempt < 10 && !caught; ++attempt) {
      fs::remove_all(out_dir);
      fs::create_directories(out_dir);
      caught = InterruptWhileWriting({"eval", model, "-i", dir + "/points.txt",
                                      "-o", out_dir + "/values.txt"},
                                     out_dir, signal_number, only_the_write);
    }
    ASSERT_TRUE(caught) << "the write was never caught in progress";
    const std::vector<std::string> left = Listing(out_dir);
    if (!left.empty()) {
      EXPECT_EQ(left, std::vector<std::string>{"values.txt"});
      EXPECT_TRUE(ReadBytes(out_dir + "/values.txt") == complete)
          << "a partial output was left";
    }
  }
  // Interrupted while computing (no temporary file yet): also nothing.
  fs::remove_all(out_dir);
  fs::create_directories(out_dir);
  const pid_t pid = Spawn({"fit", MeshPath("bunny00.off"), "-o",
                           out_dir + "/b.sdcb", "--json", out_dir + "/b.json"});
  ::usleep(300'000);
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  EXPECT_TRUE(fs::is_empty(out_dir));
}

// A tetrahedron flattened into a plane: closed, genus 0, no degenerate
// face, but three pairs of its triangles overlap.
TriangleMesh FlatTetrahedron() {
  TriangleMesh m;
  m.vertices.resize(4, 3);
  m.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.25, 0;
  m.faces.resize(4, 3);
  m.faces << 0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3;
  return m;
}

TEST(HostileCliTest, SelfIntersectionsAreReportedAndWarned) {
  const std::string dir = FreshTestDir();
  ASSERT_TRUE(WriteMesh(FlatTetrahedron(), dir + "/flat.off").ok());
  TriangleMesh crumpled = MakeIcosphere(2);
  crumpled.vertices.row(0) *= -1.5;  // pushed through the far side
  ASSERT_TRUE(WriteMesh(crumpled, dir + "/crumpled.off").ok());
  ASSERT_TRUE(WriteMesh(MakeIcosphere(2), dir + "/sphere.off").ok());

  RunResult r = RunSdcb({"check", dir + "/flat.off", "--json", "-"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["self_intersections"], 3);
  // Flat, it also turns back on itself at the 3 edges of its outline (the
  // triangles on each face opposite ways): two warnings, a line each.
  EXPECT_EQ(nlohmann::json::parse(r.out)["turn_back_edges"], 3);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 2) << r.err;
  EXPECT_EQ(r.err.rfind("sdcb: " + dir +
                            "/flat.off: warning: 3 pairs of "
                            "triangles intersect",
                        0),
            0u)
      << r.err;
  EXPECT_NE(r.err.find("\nsdcb: " + dir +
                       "/flat.off: warning: the input turns back on itself "
                       "at 3 edges"),
            std::string::npos)
      << r.err;

  r = RunSdcb({"check", dir + "/crumpled.off", "--json", "-"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(nlohmann::json::parse(r.out)["self_intersections"], 0);
  ExpectOneSentenceNaming(r, "crumpled.off");

  r = RunSdcb({"check", dir + "/sphere.off", "--json", "-"}, dir);
  EXPECT_EQ(nlohmann::json::parse(r.out)["self_intersections"], 0);
  EXPECT_TRUE(r.err.empty()) << r.err;
  // Not tested on a mesh with a part sdcb cannot fit: null and why.
  r = RunSdcb({"check", MeshPath("knot1.off"), "--json", "-"}, dir);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["self_intersections"].is_null());
  EXPECT_TRUE(j.contains("self_intersections_skipped"));
  // Tested on an open part (one boundary loop), which sdcb fits.
  r = RunSdcb({"check", MeshPath("mushroom.off"), "--json", "-"}, dir);
  EXPECT_TRUE(nlohmann::json::parse(r.out)["self_intersections"].is_number());

  // fit warns too (whatever the fit then makes of it).
  r = RunSdcb({"fit", dir + "/crumpled.off", "-o", dir + "/c.sdcb",
               "--max-rounds", "1", "--quiet"},
              dir);
  EXPECT_NE(r.err.find("crumpled.off: warning:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pairs of triangles intersect"), std::string::npos);
  // So does param (the search runs beside the parameterization).
  r = RunSdcb(
      {"param", dir + "/crumpled.off", "-o", dir + "/c_param.off", "--quiet"},
      dir);
  EXPECT_NE(r.err.find("crumpled.off: warning:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pairs of triangles intersect"), std::string::npos);
  // A target it misses names the intersections among the reasons; a mesh
  // without them does not.
  r = RunSdcb(
      {"fit", dir + "/crumpled.off", "-o", dir + "/c.sdcb", "--rmse", "0.001",
       "--max-rounds", "1", "--json", dir + "/c.json", "--quiet"},
      dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("were not reached: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("; the input intersects itself ("), std::string::npos)
      << r.err;
  const std::string shortfall =
      nlohmann::json::parse(ReadBytes(dir + "/c.json"))["shortfall"];
  EXPECT_NE(shortfall.find("; the input intersects itself ("),
            std::string::npos)
      << shortfall;
  r = RunSdcb({"fit", dir + "/sphere.off", "-o", dir + "/s.sdcb", "--rmse",
               "0.001", "--max-rounds", "1", "--quiet"},
              dir);
  EXPECT_NE(r.err.find("were not reached: "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("intersects itself"), std::string::npos) << r.err;
}

// sphere966 as a triangle soup (every triangle with its own vertices, as in
// STL) with three faces missing: three small holes, 3 x #F vertices.
TriangleMesh DamagedSphere(int* faces_kept, int* sphere_vertices) {
  auto mesh = ReadMesh(MeshPath("sphere966.off"));
  EXPECT_TRUE(mesh.ok());
  TriangleMesh soup;
  const std::vector<int> dropped = {0, 500, 1200};
  const int kept = mesh->num_faces() - 3;
  soup.vertices.resize(3 * kept, 3);
  soup.faces.resize(kept, 3);
  int row = 0;
  for (int f = 0; f < mesh->num_faces(); ++f) {
    if (std::find(dropped.begin(), dropped.end(), f) != dropped.end()) continue;
    for (int k = 0; k < 3; ++k) {
      soup.vertices.row(3 * row + k) = mesh->vertices.row(mesh->faces(f, k));
      soup.faces(row, k) = 3 * row + k;
    }
    ++row;
  }
  *faces_kept = kept;
  *sphere_vertices = mesh->num_vertices();
  return soup;
}

TEST(HostileCliTest, RepairTurnsASoupWithHolesIntoAMeshThatFits) {
  const std::string dir = FreshTestDir();
  int kept = 0, sphere_vertices = 0;
  ASSERT_TRUE(
      WriteMesh(DamagedSphere(&kept, &sphere_vertices), dir + "/damaged.off")
          .ok());

  // Unwelded, every soup triangle is a part of its own (the 1848
  // triangles of sphere966.off's header less 3). The intake welds the
  // soup's copies, which only closes edges: one open part with the three
  // holes as its boundary loops.
  ASSERT_EQ(kept, 1845);
  RunResult r = RunSdcb(
      {"check", dir + "/damaged.off", "--json", dir + "/welded.json"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("damaged.off: merged " +
                       std::to_string(3 * kept - sphere_vertices) +
                       " vertices split at equal positions"),
            std::string::npos)
      << r.err;
  const auto welded = nlohmann::json::parse(ReadBytes(dir + "/welded.json"));
  ASSERT_EQ(welded["parts"].size(), 1u);
  EXPECT_EQ(welded["parts"][0]["boundary_loops"], 3);

  r = RunSdcb(
      {"check", dir + "/damaged.off", "--repair", "--json", dir + "/c.json"},
      dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // 3 x kept soup vertices merge into the sphere's vertices.
  EXPECT_NE(r.err.find("repaired: merged " +
                       std::to_string(3 * kept - sphere_vertices) +
                       " duplicate vertices and filled 3 holes"),
            std::string::npos)
      << r.err;
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/c.json"));
  EXPECT_EQ(j["ok"], true);
  EXPECT_EQ(j["repaired"], true);
  EXPECT_EQ(j["euler_characteristic"], 2);
  EXPECT_EQ(j["duplicate_vertices"], 0);
  EXPECT_EQ(j["self_intersections"], 0);

  r = RunSdcb({"fit", dir + "/damaged.off", "--repair", "-o", dir + "/m.sdcb",
               "--json", dir + "/fit.json", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto fit = nlohmann::json::parse(ReadBytes(dir + "/fit.json"));
  EXPECT_EQ(fit["reached_target"], true);
  EXPECT_LE(fit["final"]["rmse_percent"].get<double>(), 0.05);
  EXPECT_TRUE(ReadSdcbFile(dir + "/m.sdcb").ok());

  // What cannot become genus 0 is refused in one sentence.
  r = RunSdcb(
      {"fit", MeshPath("elephant.off"), "--repair", "-o", dir + "/e.sdcb"},
      dir);
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneSentenceNaming(r, "elephant.off");
  EXPECT_NE(r.err.find("after repair, mesh has genus 3"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir + "/e.sdcb"));
}

TEST(HostileCliTest, EvalNeverWritesNonFiniteNumbers) {
  const std::string dir = FreshTestDir();
  const std::string model = FitQuickModel(dir);
  // Directions that only normalize after scaling give the same values as
  // their unit versions.
  WriteBytes(dir + "/tiny.txt", "1e-200 1e-200 1e-200\n-1e300 0 1e300\n");
  WriteBytes(dir + "/unit.txt", "1 1 1\n-1 0 1\n");
  ASSERT_EQ(RunSdcb({"eval", model, "-i", dir + "/tiny.txt", "-o",
                     dir + "/tiny_values.txt"},
                    dir)
                .exit_code,
            0);
  ASSERT_EQ(RunSdcb({"eval", model, "-i", dir + "/unit.txt", "-o",
                     dir + "/unit_values.txt"},
                    dir)
                .exit_code,
            0);
  EXPECT_EQ(ReadBytes(dir + "/tiny_values.txt"),
            ReadBytes(dir + "/unit_values.txt"));
  // Directions that cannot be normalized.
  for (const std::string& bad :
       {std::string("0 0 0\n"), std::string("0 -0 0\n"),
        std::string("nan 1 0\n"), std::string("1 inf 0\n"),
        std::string("1e999 0 0\n")}) {
    SCOPED_TRACE(bad);
    WriteBytes(dir + "/bad.txt", "0 0 1\n" + bad);
    const RunResult r = RunSdcb(
        {"eval", model, "-i", dir + "/bad.txt", "-o", dir + "/v.txt"}, dir);
    EXPECT_EQ(r.exit_code, 1);
    ExpectOneSentenceNaming(r, "bad.txt");
    EXPECT_NE(r.err.find("line 2"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/v.txt"));
  }
  // A valid model whose transform overflows: with scale 1e308 and a
  // translation of 1.7e308, every positive coordinate of the surface
  // (normalized, about +-0.4 at the axes) maps beyond the double range.
  auto m = ReadSdcbFile(model);
  ASSERT_TRUE(m.ok());
  m->transform.scale = 1e308;
  m->transform.translation.setConstant(1.7e308);
  ASSERT_TRUE(WriteSdcbFile(*m, dir + "/huge.sdcb").ok());
  WriteBytes(dir + "/axes.txt", "1 0 0\n0 1 0\n0 0 1\n");
  for (const char* flag : {"", "--derivatives"}) {
    std::vector<std::string> args = {"eval", dir + "/huge.sdcb",
                                     "-i",   dir + "/axes.txt",
                                     "-o",   dir + "/v.txt"};
    if (*flag) args.push_back(flag);
    const RunResult r = RunSdcb(args, dir);
    EXPECT_EQ(r.exit_code, 1) << flag;
    ExpectOneSentenceNaming(r, "huge.sdcb");
    EXPECT_NE(r.err.find("no finite value"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/v.txt"));
  }
}

}  // namespace
}  // namespace sdcb
