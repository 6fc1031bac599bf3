// Times reading and writing `.sdcb` files (format version 2) and prints
// their sizes. Not run by CI.
//
// Usage: sdcb_file_bench [MODEL.sdcb ...]
// With files (e.g. written by `sdcb fit`): per file, the median and minimum
// of 11 reads (ReadSdcbFile: read, check, inflate, recompute the
// configurations from the knots, validate), the configuration recomputation
// alone, and the sizes of the model written lossless, with --quantize 16,
// with and without parameters.
// Without files: a synthetic degree-4 model at the scale of the paper's
// results and above (5000 random knots, their configurations, random control
// points, 50K parameters).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/spline_model.h"
#include "sdcb/io/report/model_json.h"
#include "sdcb/io/sdcb/sdcb_file.h"

namespace {

using sdcb::SplineModel;

Eigen::MatrixX3d RandomUnit(int n, std::mt19937* rng) {
  std::normal_distribution<double> g;
  Eigen::MatrixX3d m(n, 3);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d v(g(*rng), g(*rng), g(*rng));
    m.row(i) = v.normalized().transpose();
  }
  return m;
}

SplineModel SyntheticModel(int knots, int parameters) {
  constexpr int kDegree = 4;
  std::mt19937 rng(1);
  SplineModel m;
  m.degree = kDegree;
  m.knots = RandomUnit(knots, &rng);
  m.configurations =
      sdcb::ComputeDelaunayConfigurations(m.knots, kDegree).value();
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const auto sets = static_cast<Eigen::Index>(m.configurations.sets.size());
  m.control_points.resize(sets, 3);
  for (Eigen::Index i = 0; i < sets; ++i) {
    m.control_points.row(i) << u(rng), u(rng), u(rng);
  }
  m.transform.scale = 2.5;
  m.statistics.rounds.resize(8);
  m.source.num_vertices = parameters;
  m.source.num_faces = 2 * parameters - 4;
  m.source.file_name = "synthetic.off";
  m.parameters = RandomUnit(parameters, &rng);
  return m;
}

struct Timing {
  double median_ms = 0;
  double min_ms = 0;
};

template <typename F>
Timing Time(int runs, F&& f) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double, std::milli>(
                    std::chrono::steady_clock::now() - start)
                    .count());
  }
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front()};
}

size_t SizeOf(const SplineModel& m, const sdcb::SdcbWriteOptions& o) {
  return sdcb::SerializeSdcb(m, o).value().size();
}

int BenchFile(const std::string& path) {
  constexpr int kRuns = 11;
  sdcb::SdcbFileInfo info;
  sdcb::StatusOr<SplineModel> model = sdcb::ReadSdcbFile(path, &info);
  if (!model.ok()) {
    std::fprintf(stderr, "%s\n", model.status().message().c_str());
    return 1;
  }
  bool ok = true;
  const Timing read = Time(kRuns, [&] { ok &= sdcb::ReadSdcbFile(path).ok(); });
  const Timing configurations = Time(kRuns, [&] {
    ok &= sdcb::ComputeDelaunayConfigurations(model->knots, model->degree).ok();
  });
  std::string bytes;
  const Timing serialize = Time(
      kRuns, [&] { bytes = std::move(sdcb::SerializeSdcb(*model).value()); });
  if (!ok) {
    std::fprintf(stderr, "%s: a read failed\n", path.c_str());
    return 1;
  }
  std::printf(
      "%s: format version %u, %llu bytes; degree %d, %lld knots, %zu control "
      "points, %lld parameters stored\n"
      "  read (ReadSdcbFile, %d runs): median %.1f ms, min %.1f ms; of "
      "which recomputing the configurations: median %.1f ms\n"
      "  serialize (lossless): median %.1f ms\n"
      "  sizes written now: lossless %zu bytes, --quantize 16 %zu bytes",
      path.c_str(), info.format_version,
      static_cast<unsigned long long>(info.file_bytes), model->degree,
      static_cast<long long>(model->knots.rows()),
      model->configurations.sets.size(),
      static_cast<long long>(model->parameters.rows()), kRuns, read.median_ms,
      read.min_ms, configurations.median_ms, serialize.median_ms,
      SizeOf(*model, {false, 0}), SizeOf(*model, {false, 16}));
  if (model->parameters.rows() > 0) {
    std::printf(", lossless with parameters %zu bytes",
                SizeOf(*model, {true, 0}));
  }
  std::printf("\n");
  return 0;
}

int BenchSynthetic() {
  constexpr int kKnots = 5000, kParameters = 50000, kRuns = 5;
  const SplineModel model = SyntheticModel(kKnots, kParameters);
  const std::string path =
      (std::filesystem::temp_directory_path() / "sdcb_file_bench.sdcb")
          .string();
  std::string bytes;
  const Timing serialize = Time(
      kRuns, [&] { bytes = std::move(sdcb::SerializeSdcb(model).value()); });
  bool ok = true;
  const Timing parse = Time(kRuns, [&] { ok &= sdcb::ParseSdcb(bytes).ok(); });
  const Timing write =
      Time(kRuns, [&] { ok &= sdcb::WriteSdcbFile(model, path).ok(); });
  const Timing read = Time(kRuns, [&] { ok &= sdcb::ReadSdcbFile(path).ok(); });
  const Timing configurations = Time(kRuns, [&] {
    ok &= sdcb::ComputeDelaunayConfigurations(model.knots, model.degree).ok();
  });
  std::string json;
  const Timing dump = Time(kRuns, [&] { json = sdcb::ModelToJson(model); });
  std::filesystem::remove(path);
  if (!ok) {
    std::fprintf(stderr, "a round trip failed\n");
    return 1;
  }
  std::printf(
      "synthetic model: degree 4, %d random knots, %zu basis functions, %d "
      "parameters\n"
      ".sdcb size: %zu bytes (without parameters %zu, --quantize 16 %zu); "
      "JSON dump: %zu bytes\n"
      "median of %d runs (ms): serialize %.1f, parse %.1f (configurations "
      "%.1f), write file %.1f, read file %.1f, ModelToJson %.1f\n",
      kKnots, model.configurations.sets.size(), kParameters, bytes.size(),
      SizeOf(model, {false, 0}), SizeOf(model, {false, 16}), json.size(), kRuns,
      serialize.median_ms, parse.median_ms, configurations.median_ms,
      write.median_ms, read.median_ms, dump.median_ms);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return BenchSynthetic();
  int status = 0;
  for (int i = 1; i < argc; ++i) status |= BenchFile(argv[i]);
  return status;
}
