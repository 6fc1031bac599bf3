// Prints the size and the serialize / parse / write / read / JSON-dump times
// of a synthetic model at the scale of the paper's results (Table 2: ~5000
// control points; here more, to bound real models from above). Not run by
// CI. Usage: sdcb_file_bench [knots] [basis_functions] [parameters]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "sdcb/core/spline/spline_model.h"
#include "sdcb/io/model_json.h"
#include "sdcb/io/sdcb_file.h"

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

// Structurally valid (not geometrically meaningful) degree-4 model: random
// distinct knot sets, three boundary triples each.
SplineModel SyntheticModel(int knots, int sets, int parameters) {
  constexpr int kDegree = 4;
  std::mt19937 rng(1);
  SplineModel m;
  m.degree = kDegree;
  m.knots = RandomUnit(knots, &rng);
  m.configurations.degree = kDegree;
  std::set<std::vector<int>> unique;
  std::uniform_int_distribution<int> pick(0, knots - 1);
  while (static_cast<int>(unique.size()) < sets) {
    std::set<int> s;
    while (static_cast<int>(s.size()) < kDegree + 3) s.insert(pick(rng));
    unique.insert(std::vector<int>(s.begin(), s.end()));
  }
  for (const std::vector<int>& k : unique) {
    m.configurations.sets.push_back(
        {k, {{k[0], k[1], k[2]}, {k[0], k[1], k[3]}, {k[1], k[4], k[6]}}});
  }
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  m.control_points.resize(sets, 3);
  for (int i = 0; i < sets; ++i) {
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

// Median wall time of `runs` calls, in milliseconds.
template <typename F>
double MedianMs(int runs, F&& f) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double, std::milli>(
                    std::chrono::steady_clock::now() - start)
                    .count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int knots = argc > 1 ? std::atoi(argv[1]) : 5000;
  const int sets = argc > 2 ? std::atoi(argv[2]) : 20000;
  const int parameters = argc > 3 ? std::atoi(argv[3]) : 50000;
  const SplineModel model = SyntheticModel(knots, sets, parameters);
  const std::string path =
      (std::filesystem::temp_directory_path() / "sdcb_file_bench.sdcb")
          .string();
  constexpr int kRuns = 5;

  std::string bytes;
  const double serialize = MedianMs(
      kRuns, [&] { bytes = std::move(sdcb::SerializeSdcb(model).value()); });
  bool ok = true;
  const double parse =
      MedianMs(kRuns, [&] { ok &= sdcb::ParseSdcb(bytes).ok(); });
  const double write =
      MedianMs(kRuns, [&] { ok &= sdcb::WriteSdcbFile(model, path).ok(); });
  const double read =
      MedianMs(kRuns, [&] { ok &= sdcb::ReadSdcbFile(path).ok(); });
  std::string json;
  const double dump = MedianMs(kRuns, [&] { json = sdcb::ModelToJson(model); });
  std::filesystem::remove(path);
  if (!ok) {
    std::fprintf(stderr, "a round trip failed\n");
    return 1;
  }
  std::printf(
      "model: degree 4, %d knots, %d basis functions, %d parameters\n"
      ".sdcb size: %zu bytes; JSON dump: %zu bytes\n"
      "median of %d runs (ms): serialize %.2f, parse %.2f, write file %.2f, "
      "read file %.2f, ModelToJson %.2f\n",
      knots, sets, parameters, bytes.size(), json.size(), kRuns, serialize,
      parse, write, read, dump);
  return 0;
}
