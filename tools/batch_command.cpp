// sdcb batch MANIFEST [--jobs N] [--shard I/N] [--json-lines FILE]
//            [--timeout SECONDS] [--force] [--quiet]
//
// Converts every asset of a manifest (io/batch/batch_manifest.h): each row runs
// as child processes of this same executable (`sdcb fit`, then `sdcb
// export` when the row's output is not a .sdcb model), so a crash, a kill
// by the out-of-memory killer or a hang (--timeout) ends that row only.
// One JSON line per row; finished outputs are skipped on a rerun; --shard
// (or the Slurm / Kubernetes array variables) selects every N-th row.
// docs/BATCH.md is the user's description; keep the two in step.
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "sdcb/core/spline/model.h"
#include "sdcb/io/batch/batch_manifest.h"
#include "sdcb/io/common/atomic_file.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/interrupts.h"

namespace sdcb::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string LowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// ---------------------------------------------------------------------------
// Which rows this process runs.

struct Shard {
  long index = 0;
  long count = 1;
  std::string source = "all rows";  // where index and count came from
};

bool ParseLong(const char* text, long* value) {
  if (text == nullptr || *text == '\0') return false;
  char* end = nullptr;
  errno = 0;
  *value = std::strtol(text, &end, 10);
  return errno == 0 && *end == '\0';
}

// "--shard I/N" (0 <= I < N) if given; else Slurm's array variables
// (index (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN) / SLURM_ARRAY_TASK_STEP
// of SLURM_ARRAY_TASK_COUNT); else Kubernetes' JOB_COMPLETION_INDEX with
// the count in SDCB_SHARD_COUNT; else every row. Inconsistent values are
// usage errors.
Shard ChooseShard(const Args& args) {
  Shard shard;
  if (args.Has("shard")) {
    const std::string text = args.Get("shard");
    const size_t slash = text.find('/');
    if (slash == std::string::npos ||
        !ParseLong(text.substr(0, slash).c_str(), &shard.index) ||
        !ParseLong(text.substr(slash + 1).c_str(), &shard.count) ||
        shard.count < 1 || shard.index < 0 || shard.index >= shard.count) {
      throw UsageError{"--shard must be I/N with 0 <= I < N, got '" + text +
                       "'"};
    }
    shard.source = "--shard";
    return shard;
  }
  if (const char* id_text = std::getenv("SLURM_ARRAY_TASK_ID")) {
    long id = 0, min = 0, step = 1, count = 0;
    const char* min_text = std::getenv("SLURM_ARRAY_TASK_MIN");
    const char* step_text = std::getenv("SLURM_ARRAY_TASK_STEP");
    if (!ParseLong(id_text, &id) ||
        !ParseLong(std::getenv("SLURM_ARRAY_TASK_COUNT"), &count) ||
        (min_text && !ParseLong(min_text, &min)) ||
        (step_text && !ParseLong(step_text, &step)) || count < 1 || step < 1 ||
        id < min || (id - min) % step != 0 || (id - min) / step >= count) {
      throw UsageError{
          "SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_ID/_MIN/_STEP/"
          "_COUNT do not describe a range array (--array=A-B[:S]); pass "
          "--shard I/N"};
    }
    shard.index = (id - min) / step;
    shard.count = count;
    shard.source = "SLURM_ARRAY_TASK_ID";
    return shard;
  }
  if (const char* index_text = std::getenv("JOB_COMPLETION_INDEX")) {
    if (!ParseLong(index_text, &shard.index) ||
        !ParseLong(std::getenv("SDCB_SHARD_COUNT"), &shard.count) ||
        shard.count < 1 || shard.index < 0 || shard.index >= shard.count) {
      throw UsageError{
          "JOB_COMPLETION_INDEX is set: SDCB_SHARD_COUNT must hold the Job's "
          "completions (greater than the index), or pass --shard I/N"};
    }
    shard.source = "JOB_COMPLETION_INDEX";
    return shard;
  }
  return shard;
}

// ---------------------------------------------------------------------------
// What each row does.

struct Asset {
  int row = 0;   // 0-based index among the manifest's rows
  int line = 0;  // line in the manifest
  std::string input, output;
  std::string model;  // the .sdcb the fit writes (== output for fit rows)
  bool exports = false;
  std::vector<std::string> fit_args, export_args;
};

bool Contains(const std::vector<std::string>& list, const std::string& s) {
  return std::find(list.begin(), list.end(), s) != list.end();
}

// A path of the manifest, relative to the manifest's folder.
std::string Resolve(const fs::path& base, const std::string& path) {
  const fs::path p(path);
  return (p.is_absolute() ? p : base / p).lexically_normal().string();
}

// Splits a row's options between fit and export (by the commands' own
// option lists) and resolves its paths. Errors name the line.
StatusOr<Asset> PlanRow(const ManifestRow& row, int index,
                        const fs::path& base) {
  const std::string where = "line " + std::to_string(row.line) + ": ";
  Asset a;
  a.row = index;
  a.line = row.line;
  a.input = Resolve(base, row.input);
  a.output = Resolve(base, row.output);
  const std::string ext = LowerExtension(a.output);
  a.exports = ext != ".sdcb";
  if (a.exports && !IsExportExtension(ext)) {
    return InvalidInputError(
        where + "output " + row.output +
        " must end in .sdcb (a model) or an export format (.obj, .ply, .stl, "
        ".gltf, .glb)");
  }
  const CommandOptions& fit = FitOptionNames();
  const CommandOptions& exp = ExportOptionNames();
  for (size_t i = 0; i < row.options.size(); ++i) {
    const std::string& token = row.options[i];
    if (token.size() < 3 || token.compare(0, 2, "--") != 0) {
      return InvalidInputError(where + "'" + token +
                               "' is not an option (options start with --)");
    }
    std::string name = token.substr(2), value;
    const size_t eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name.resize(eq);
    }
    if (name == "output" || name == "json" || name == "quiet") {
      return InvalidInputError(where + "--" + name +
                               " is set by sdcb batch (results are the JSON "
                               "lines)");
    }
    const bool is_model = name == "model";
    const bool fit_value = Contains(fit.values, name);
    const bool export_value = Contains(exp.values, name);
    const bool takes_value = is_model || fit_value || export_value;
    const bool is_flag = Contains(fit.flags, name) || Contains(exp.flags, name);
    if (!takes_value && !is_flag) {
      return InvalidInputError(where + "unknown option '" + token + "'");
    }
    if (is_flag && inline_value) {
      return InvalidInputError(where + "option --" + name + " takes no value");
    }
    if (takes_value && !inline_value) {
      if (i + 1 >= row.options.size()) {
        return InvalidInputError(where + "option --" + name + " needs a value");
      }
      value = row.options[++i];
    }
    const bool for_export =
        is_model || export_value || Contains(exp.flags, name);
    if (for_export && !a.exports) {
      return InvalidInputError(where + "--" + name +
                               " is an export option, but the output " +
                               row.output + " is a .sdcb model");
    }
    if (name == "mesh" || name == "plot") value = Resolve(base, value);
    if (is_model) {
      a.model = value;
      continue;
    }
    std::vector<std::string>& args = for_export ? a.export_args : a.fit_args;
    args.push_back("--" + name);
    if (takes_value) args.push_back(value);
  }
  if (!a.exports) {
    a.model = a.output;
  } else if (a.model.empty()) {
    a.model = fs::path(a.output).replace_extension(".sdcb").string();
  }
  if (LowerExtension(a.model) != ".sdcb") {
    return InvalidInputError(where + "--model " + a.model +
                             " must end in .sdcb");
  }
  return a;
}

StatusOr<std::vector<Asset>> PlanManifest(const std::string& path) {
  std::error_code ec;
  const uintmax_t size = fs::file_size(path, ec);
  constexpr uintmax_t kMaxManifestBytes = uintmax_t{256} << 20;
  if (!ec && size > kMaxManifestBytes) {
    return InvalidInputError(path + ": manifest larger than 256 MB");
  }
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) return IoError(path + ": cannot read the manifest");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  StatusOr<std::vector<ManifestRow>> rows = ParseBatchManifest(text);
  if (!rows.ok()) return rows.status().WithPrefix(path);
  const fs::path base = fs::absolute(path).parent_path();
  std::vector<Asset> assets;
  // Every file a row writes, with the line that writes it: two rows writing
  // one file would race.
  std::map<std::string, int> writers;
  for (size_t i = 0; i < rows->size(); ++i) {
    StatusOr<Asset> asset = PlanRow((*rows)[i], static_cast<int>(i), base);
    if (!asset.ok()) return asset.status().WithPrefix(path);
    for (const std::string& file : {asset->output, asset->model}) {
      const std::string key = fs::absolute(file).lexically_normal().string();
      const auto [it, inserted] = writers.emplace(key, asset->line);
      if (!inserted && it->second != asset->line) {
        return InvalidInputError(
            path + ": line " + std::to_string(asset->line) + ": " + file +
            " is also written by line " + std::to_string(it->second));
      }
    }
    assets.push_back(std::move(asset).value());
  }
  return assets;
}

// ---------------------------------------------------------------------------
// Whether an output is finished.

// `path` exists and is not older than any of `sources` that exist.
bool IsUpToDate(const std::string& path,
                const std::vector<std::string>& sources) {
  std::error_code ec;
  const fs::file_time_type written = fs::last_write_time(path, ec);
  if (ec) return false;
  for (const std::string& source : sources) {
    const fs::file_time_type t = fs::last_write_time(source, ec);
    if (!ec && t > written) return false;
  }
  return true;
}

// The model at `path` if it is up to date with `sources` and reads back.
std::optional<Model> FinishedModel(const std::string& path,
                                   const std::vector<std::string>& sources) {
  if (!IsUpToDate(path, sources)) return std::nullopt;
  StatusOr<Model> model = ReadSdcbModelFile(path);
  if (!model.ok()) return std::nullopt;
  return std::move(model).value();
}

// Whether an export output is up to date with `sources` and reads back.
// Outputs are written atomically (a temporary file renamed into place), so a
// file that exists is complete unless something else wrote it; reading it
// back checks that too.
bool FinishedExport(const std::string& path,
                    const std::vector<std::string>& sources) {
  if (!IsUpToDate(path, sources)) return false;
  const std::string ext = LowerExtension(path);
  if (ext == ".obj" || ext == ".ply" || ext == ".stl") {
    return ReadMesh(path).ok();
  }
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const uintmax_t size = fs::file_size(path, ec);
  if (!in || ec) return false;
  if (ext == ".glb") {
    // GLB header: magic "glTF", version 2, total length (little endian).
    unsigned char header[12] = {};
    if (!in.read(reinterpret_cast<char*>(header), 12)) return false;
    const uint32_t version = header[4] | header[5] << 8 | header[6] << 16 |
                             uint32_t{header[7]} << 24;
    const uint32_t length = header[8] | header[9] << 8 | header[10] << 16 |
                            uint32_t{header[11]} << 24;
    return std::equal(header, header + 4, "glTF") && version == 2 &&
           length == size;
  }
  if (ext == ".gltf") {
    const Json j = Json::parse(std::istreambuf_iterator<char>(in), {}, nullptr,
                               /*allow_exceptions=*/false);
    return j.is_object() && j.contains("asset");
  }
  return false;
}

// ---------------------------------------------------------------------------
// Child processes.

struct ChildResult {
  pid_t pid = -1;
  int exit_code = -1;  // when it exited
  int signal = 0;      // when a signal ended it
  bool timed_out = false;
  std::string error;                  // the last line it wrote on stderr
  std::vector<std::string> warnings;  // earlier stderr lines
};

std::string SelfExecutable() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : self.string();
}

// Runs `exe args...` with stdin and stdout on /dev/null and stderr into
// `stderr_path`. The child gets SIGTERM if this thread ends first (so a
// killed batch leaves no orphans); after `deadline` it gets SIGTERM (time
// to remove its temporary files), then SIGKILL 5 s later.
ChildResult RunChild(const std::string& exe,
                     const std::vector<std::string>& args,
                     const std::string& stderr_path,
                     std::optional<Clock::time_point> deadline) {
  ChildResult result;
  std::vector<std::string> all = {exe};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int err_fd =
      open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int null_fd = open("/dev/null", O_RDWR | O_CLOEXEC);
  if (err_fd < 0 || null_fd < 0) {
    if (err_fd >= 0) close(err_fd);
    if (null_fd >= 0) close(null_fd);
    result.error = "cannot create " + stderr_path;
    return result;
  }
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    // Only async-signal-safe calls until exec.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    dup2(null_fd, 0);
    dup2(null_fd, 1);
    dup2(err_fd, 2);
    execv(exe.c_str(), argv.data());
    _exit(127);
  }
  close(err_fd);
  close(null_fd);
  if (pid < 0) {
    result.error = std::string("cannot start a process: ") + strerror(errno);
    return result;
  }
  result.pid = pid;
  int status = 0;
  std::optional<Clock::time_point> kill_at;
  auto pause = std::chrono::milliseconds(1);
  while (true) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) break;
    const Clock::time_point now = Clock::now();
    if (deadline && !result.timed_out && now >= *deadline) {
      result.timed_out = true;
      kill(pid, SIGTERM);
      kill_at = now + std::chrono::seconds(5);
    }
    if (kill_at && now >= *kill_at) {
      kill(pid, SIGKILL);
      kill_at.reset();
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::milliseconds(50));
  }
  if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
  std::ifstream err(stderr_path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(err, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  std::error_code ec;
  fs::remove(stderr_path, ec);
  const bool failed = result.exit_code != 0;
  if (failed && !lines.empty()) {
    result.error = lines.back();
    lines.pop_back();
    if (result.error.rfind("sdcb: ", 0) == 0) result.error.erase(0, 6);
  }
  result.warnings = std::move(lines);
  if (result.timed_out) {
    result.error = "timed out (--timeout), stopped by SIGTERM";
  } else if (result.signal != 0) {
    const char* name = sigdescr_np(result.signal);
    result.error = "crashed: killed by signal " +
                   std::to_string(result.signal) + " (" +
                   (name ? name : "unknown") + ")" +
                   (result.signal == SIGKILL
                        ? "; out of memory? (the kernel's OOM killer sends "
                          "SIGKILL)"
                        : "");
  } else if (failed && result.error.empty()) {
    result.error = "exited with status " + std::to_string(result.exit_code) +
                   " and no message";
  }
  return result;
}

// ---------------------------------------------------------------------------
// One asset.

struct BatchSettings {
  std::string exe;
  bool force = false;
  double timeout_seconds = 0;  // 0: none
  int threads_per_child = 0;   // 0: the child's default (every core)
};

// A model's numbers on its line: one part's as they are; several parts'
// knots and control points summed, rounds, rms and maximum the largest (each
// part's in percent of its own size), reached when every fitted part
// reached; kept parts (fit options in the row, --keep-unfittable) counted.
void PutModelNumbers(const Model& model, Json* line) {
  int knots = 0, control_points = 0, kept = 0;
  size_t rounds = 0;
  double rmse = 0, max = 0;
  bool reached = true;
  for (const ModelPart& part : model.parts) {
    if (part.kept) {
      ++kept;
      continue;
    }
    const FitStatistics& s = part.spline.statistics;
    knots += s.final_result.knots;
    control_points += s.final_result.control_points;
    rounds = std::max(rounds, s.rounds.size());
    rmse = std::max(rmse, s.final_result.rmse_percent);
    max = std::max(max, s.final_result.max_error_percent);
    reached = reached && s.reached_target;
  }
  (*line)["vertices"] = model.source.num_vertices;
  (*line)["knots"] = knots;
  (*line)["control_points"] = control_points;
  (*line)["rounds"] = rounds;
  (*line)["rmse_percent"] = rmse;
  (*line)["max_error_percent"] = max;
  (*line)["reached_target"] = reached;
  if (kept > 0) (*line)["kept_parts"] = kept;
}

Json ReadJsonFile(const std::string& path) {
  std::ifstream in(path);
  Json j = Json::parse(std::istreambuf_iterator<char>(in), {}, nullptr,
                       /*allow_exceptions=*/false);
  std::error_code ec;
  fs::remove(path, ec);
  return j.is_object() ? j : Json::object();
}

// Converts one asset; returns its JSON line (status "ok", "skipped" or
// "failed").
Json RunAsset(const Asset& a, const BatchSettings& settings) {
  const Clock::time_point start = Clock::now();
  Json line;
  line["row"] = a.row;
  line["line"] = a.line;
  line["input"] = a.input;
  line["output"] = a.output;
  if (a.exports) line["model"] = a.model;
  line["status"] = "ok";
  line["steps"] = Json::array();
  line["error"] = nullptr;
  Json warnings = Json::array();
  auto finish = [&](const std::string& status, const std::string& error) {
    line["status"] = status;
    if (!error.empty()) line["error"] = error;
    line["warnings"] = warnings;
    line["seconds"] = Since(start);
    return line;
  };

  // Finished already? (docs/BATCH.md, "Reruns")
  if (!settings.force) {
    if (!a.exports) {
      if (std::optional<Model> model = FinishedModel(a.output, {a.input})) {
        PutModelNumbers(*model, &line);
        return finish("skipped", "");
      }
    } else if (FinishedExport(a.output, {a.input, a.model})) {
      StatusOr<Model> model = ReadSdcbModelFile(a.model);
      if (model.ok()) PutModelNumbers(*model, &line);
      return finish("skipped", "");
    }
  }
  std::error_code ec;
  for (const std::string& file : {a.output, a.model}) {
    const fs::path folder = fs::path(file).parent_path();
    if (!folder.empty() && !fs::is_directory(folder, ec)) {
      fs::create_directories(folder, ec);
      if (ec) {
        return finish(
            "failed",
            folder.string() + ": cannot create the folder: " + ec.message());
      }
    }
  }
  // Per-step files next to the output, named like the atomic writer's
  // temporaries so that an interrupted batch removes them.
  RemoveTemporariesOnInterrupt(a.output);
  const std::string scratch = TemporaryFilePrefix(a.output);
  std::optional<Clock::time_point> deadline;
  if (settings.timeout_seconds > 0) {
    deadline =
        start + std::chrono::duration_cast<Clock::duration>(
                    std::chrono::duration<double>(settings.timeout_seconds));
  }
  auto run = [&](const std::string& step, std::vector<std::string> args,
                 Json* report) {
    line["steps"].push_back(step);
    const std::string json_path = scratch + step + ".json";
    args.insert(args.end(), {"--json", json_path, "--quiet"});
    ChildResult r =
        RunChild(settings.exe, args, scratch + step + ".stderr", deadline);
    for (std::string& w : r.warnings) warnings.push_back(std::move(w));
    if (r.signal != 0) {
      // A child ended by a signal may have left its temporary files.
      RemoveFilesStartingWith(TemporaryFilePrefix(a.output, r.pid));
      RemoveFilesStartingWith(TemporaryFilePrefix(a.model, r.pid));
    }
    *report = ReadJsonFile(json_path);
    if (r.signal == 0 && r.exit_code != 0) line["exit_code"] = r.exit_code;
    if (r.signal != 0) line["signal"] = r.signal;
    return r.exit_code == 0 ? std::string() : r.error;
  };

  bool fit_needed = true;
  if (a.exports && !settings.force) {
    // The model of an earlier run that stopped before its export.
    if (std::optional<Model> model = FinishedModel(a.model, {a.input})) {
      PutModelNumbers(*model, &line);
      fit_needed = false;
    }
  }
  if (fit_needed) {
    std::vector<std::string> args = {"fit", a.input, "-o", a.model};
    args.insert(args.end(), a.fit_args.begin(), a.fit_args.end());
    if (settings.threads_per_child > 0 && !Contains(a.fit_args, "--threads")) {
      args.insert(args.end(),
                  {"--threads", std::to_string(settings.threads_per_child)});
    }
    Json report;
    const std::string error = run("fit", args, &report);
    if (!error.empty()) return finish("failed", error);
    // The model's numbers, as for a skipped row (the file the fit wrote).
    StatusOr<Model> model = ReadSdcbModelFile(a.model);
    if (!model.ok()) return finish("failed", model.status().message());
    PutModelNumbers(*model, &line);
    line["vertices"] = report.value("vertices", Json());
  }
  if (a.exports) {
    std::vector<std::string> args = {"export", a.model, "-o", a.output};
    args.insert(args.end(), a.export_args.begin(), a.export_args.end());
    Json report;
    const std::string error = run("export", args, &report);
    if (!error.empty()) return finish("failed", error);
    line["triangles"] = report.value("triangles", Json());
    line["export_max_distance_percent"] =
        report.value("max_distance_percent", Json());
  }
  std::uintmax_t bytes = fs::file_size(a.output, ec);
  if (!ec) line["output_bytes"] = bytes;
  return finish("ok", "");
}

int CpusAvailable() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) == 0) {
    return std::max(1, CPU_COUNT(&set));
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace

int RunBatch(const std::vector<std::string>& argv) {
  const Args args(argv, {"jobs", "shard", "json-lines", "timeout"},
                  {"force", "quiet"});
  args.RequirePositionals(
      1,
      "MANIFEST (usage: sdcb batch MANIFEST [--jobs N] [--shard I/N] "
      "[--json-lines FILE])");
  const std::string manifest = args.positionals()[0];
  const int jobs = args.GetInt("jobs", 1, 1, 1024);
  const Shard shard = ChooseShard(args);
  BatchSettings settings;
  settings.force = args.Has("force");
  settings.timeout_seconds = args.GetDouble("timeout", 0, 0, 1e9);
  settings.exe = SelfExecutable();
  if (settings.exe.empty()) {
    return ReportError(IoError("cannot find this executable (/proc/self/exe)"));
  }
  if (jobs > 1)
    settings.threads_per_child = std::max(1, CpusAvailable() / jobs);

  StatusOr<std::vector<Asset>> planned = PlanManifest(manifest);
  if (!planned.ok()) return ReportError(planned.status());
  std::vector<Asset> assets;
  for (Asset& a : *planned) {
    if (a.row % shard.count == shard.index) assets.push_back(std::move(a));
  }

  // The JSON lines go out as rows finish (a killed batch keeps the lines of
  // the rows it finished), to stdout unless --json-lines names a file.
  const std::string lines_path = args.Get("json-lines", "-");
  std::ofstream lines_file;
  if (lines_path != "-") {
    if (fs::is_directory(lines_path)) {
      return ReportError(IoError(lines_path + ": is a directory"));
    }
    lines_file.open(lines_path, std::ios::trunc);
    if (!lines_file) {
      return ReportError(IoError(lines_path + ": cannot write the JSON lines"));
    }
  }
  std::ostream& lines = lines_path == "-" ? std::cout : lines_file;

  std::mutex mutex;
  std::map<std::string, int> counts = {
      {"ok", 0}, {"skipped", 0}, {"failed", 0}};
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t i; (i = next++) < assets.size();) {
      const Json line = RunAsset(assets[i], settings);
      const std::string status = line["status"];
      std::lock_guard<std::mutex> lock(mutex);
      ++counts[status];
      lines << line.dump() << "\n";
      lines.flush();
      if (status == "failed") {
        std::string error = line["error"];
        if (error.find(assets[i].input) == std::string::npos) {
          error = assets[i].input + ": " + error;
        }
        std::cerr << "sdcb batch: " << manifest << ":" << assets[i].line
                  << ": failed: " << error << "\n";
      }
    }
  };
  std::vector<std::thread> workers;
  const size_t n_workers = std::min<size_t>(jobs, assets.size());
  for (size_t w = 0; w < n_workers; ++w) workers.emplace_back(worker);
  for (std::thread& t : workers) t.join();

  if (!lines) {
    return ReportError(IoError(lines_path + ": writing the JSON lines failed"));
  }
  if (!args.Has("quiet")) {
    std::cerr << "sdcb batch: " << manifest << ": shard " << shard.index << "/"
              << shard.count << " (" << shard.source << "): " << assets.size()
              << " of " << planned->size() << " rows: " << counts["ok"]
              << " ok, " << counts["skipped"] << " skipped, "
              << counts["failed"] << " failed\n";
  }
  return counts["failed"] > 0 ? kExitBadInput : kExitOk;
}

}  // namespace sdcb::cli
