// Exports of a Model of several parts (converters/mesh/surface_mesh_export.h
// ExportSurfaceMesh(const Model&, ...)): the OBJ's objects, PLY / STL as one
// mesh, glTF nodes checked by the Khronos validator, a trimmed part's
// boundary, and a model of one closed part byte for byte as the SplineModel
// export.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "sdcb/converters/mesh/surface_mesh_export.h"
#include "sdcb/core/common/constants.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "testing/gltf_validator.h"
#include "testing/open_sphere.h"
#include "testing/run_sdcb.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

namespace fs = std::filesystem;

// A hole of `n` points at angular radius acos(cos_radius) around `axis`
// (kept region on the left: the points run clockwise seen from the axis).
TrimLoop Hole(const Eigen::Vector3d& axis, double cos_radius, int n) {
  const Eigen::Vector3d z = axis.normalized();
  const Eigen::Vector3d e1 = z.unitOrthogonal(), e2 = z.cross(e1);
  const double s = std::sqrt(1.0 - cos_radius * cos_radius);
  TrimLoop loop;
  loop.points.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = -2.0 * kPi * i / n;
    loop.points.row(i) =
        (cos_radius * z + s * (std::cos(t) * e1 + std::sin(t) * e2))
            .normalized()
            .transpose();
  }
  return loop;
}

class ModelExportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto mesh = ReadMesh(testing::MeshPath("blobby.off"));
    ASSERT_TRUE(mesh.ok());
    FitOptions options;
    options.rmse_percent = 0.2;
    auto fit = FitSphericalSpline(*mesh, options);
    ASSERT_TRUE(fit.ok());
    spline_ = new SplineModel(fit->model);
  }
  static void TearDownTestSuite() { delete spline_; }

  static Model OnePart() {
    Model model;
    model.source = spline_->source;
    model.parts.emplace_back();
    model.parts[0].spline = *spline_;
    return model;
  }
  // Part 1 the closed blobby, unnamed; part 2 ("lid") the same spline with
  // a hole.
  static Model TwoParts() {
    Model model = OnePart();
    model.parts.emplace_back();
    model.parts[1].name = "lid";
    model.parts[1].spline = *spline_;
    model.parts[1].trims = {Hole(Eigen::Vector3d(0.3, 0.2, 1.0), 0.8, 48)};
    return model;
  }
  static SurfaceMeshExportOptions Options(ExportFormat format) {
    SurfaceMeshExportOptions o;
    o.format = format;
    o.tolerance_percent = 0.5;
    return o;
  }
  static SplineModel* spline_;
};
SplineModel* ModelExportTest::spline_ = nullptr;

// Boundary loops of faces (directed edges without their reverse, chained).
int BoundaryLoops(const std::vector<std::array<int, 3>>& faces) {
  std::set<std::pair<int, int>> directed;
  for (const auto& f : faces) {
    for (int k = 0; k < 3; ++k) directed.insert({f[k], f[(k + 1) % 3]});
  }
  std::map<int, int> next;
  for (const auto& [a, b] : directed) {
    if (!directed.count({b, a})) next[a] = b;
  }
  int loops = 0;
  std::set<int> seen;
  for (const auto& [start, unused] : next) {
    if (seen.count(start)) continue;
    ++loops;
    for (int v = start; !seen.count(v); v = next.at(v)) seen.insert(v);
  }
  return loops;
}

TEST_F(ModelExportTest, OnePartModelWritesTheSameBytesAsTheSpline) {
  const Model model = OnePart();
  for (ExportFormat format : {ExportFormat::kObj, ExportFormat::kPly,
                              ExportFormat::kStl, ExportFormat::kGlb}) {
    for (GltfCompression c : {GltfCompression::kNone, GltfCompression::kDraco,
                              GltfCompression::kMeshopt}) {
      if (c != GltfCompression::kNone && format != ExportFormat::kGlb) continue;
      SurfaceMeshExportOptions o = Options(format);
      o.compression = c;
      auto a = ExportSurfaceMesh(*spline_, o);
      auto b = ExportSurfaceMesh(model, o);
      ASSERT_TRUE(a.ok() && b.ok());
      EXPECT_TRUE(a->bytes == b->bytes) << int(format) << " " << int(c);
      EXPECT_EQ(SurfaceMeshExportReportToJson(a->report)["triangles"],
                SurfaceMeshExportReportToJson(b->report)["triangles"]);
      EXPECT_FALSE(SurfaceMeshExportReportToJson(b->report).contains("parts"));
    }
  }
}

TEST_F(ModelExportTest, ObjHasOneObjectPerPartAndTheTrimAsBoundary) {
  auto closed = ExportSurfaceMesh(*spline_, Options(ExportFormat::kObj));
  ASSERT_TRUE(closed.ok());
  auto two = ExportSurfaceMesh(TwoParts(), Options(ExportFormat::kObj));
  ASSERT_TRUE(two.ok()) << two.status().message();
  // Parse the OBJ: objects in order, their faces (1-based "v//vn" corners).
  std::istringstream lines(two->bytes);
  std::string line;
  std::vector<std::string> objects;
  std::vector<std::vector<std::array<int, 3>>> faces;
  int vertices = 0;
  std::vector<Eigen::Vector3d> positions;
  while (std::getline(lines, line)) {
    if (line.rfind("o ", 0) == 0) {
      objects.push_back(line.substr(2));
      faces.emplace_back();
    } else if (line.rfind("v ", 0) == 0) {
      ++vertices;
      std::istringstream xyz(line.substr(2));
      Eigen::Vector3d x;
      xyz >> x[0] >> x[1] >> x[2];
      positions.push_back(x);
    } else if (line.rfind("f ", 0) == 0) {
      ASSERT_FALSE(faces.empty()) << "a face before the first object";
      std::istringstream corners(line.substr(2));
      std::array<int, 3> f;
      for (int& c : f) {
        std::string token;
        corners >> token;
        c = std::stoi(token.substr(0, token.find('/')));
      }
      faces.back().push_back(f);
    }
  }
  ASSERT_EQ(objects, (std::vector<std::string>{"part1", "lid"}));
  EXPECT_EQ(vertices, two->report.vertices);
  EXPECT_EQ(two->report.parts, 2);
  EXPECT_EQ(two->report.trim_loops, 1);
  // Part 1 is the closed spline's own mesh: the same faces, no boundary.
  EXPECT_EQ(static_cast<int64_t>(faces[0].size()), closed->report.triangles);
  EXPECT_EQ(BoundaryLoops(faces[0]), 0);
  // Part 2 has the hole: one boundary loop, less area than the whole, its
  // vertices after part 1's.
  EXPECT_EQ(BoundaryLoops(faces[1]), 1);
  const auto area = [&](const std::vector<std::array<int, 3>>& part) {
    double sum = 0.0;
    for (const auto& f : part) {
      const Eigen::Vector3d a = positions[f[0] - 1], b = positions[f[1] - 1],
                            c = positions[f[2] - 1];
      sum += 0.5 * (b - a).cross(c - a).norm();
    }
    return sum;
  };
  EXPECT_LT(area(faces[1]), 0.99 * area(faces[0]));
  EXPECT_GT(area(faces[1]), 0.3 * area(faces[0]));
  EXPECT_EQ(static_cast<int64_t>(faces[0].size() + faces[1].size()),
            two->report.triangles);
  for (const auto& f : faces[1]) {
    for (int c : f) EXPECT_GT(c, two->part_vertices[1]);
  }
  // STL: one mesh of both parts (its triangle count at byte 80).
  auto stl = ExportSurfaceMesh(TwoParts(), Options(ExportFormat::kStl));
  ASSERT_TRUE(stl.ok());
  uint32_t count = 0;
  std::memcpy(&count, stl->bytes.data() + 80, 4);
  EXPECT_EQ(int64_t{count}, two->report.triangles);
}

TEST_F(ModelExportTest, GltfOfTwoPartsPassesTheValidatorWithTwoNodes) {
  const std::string dir = testing::FreshTestDir();
  const Model model = TwoParts();
  struct Case {
    std::string name;
    ExportFormat format;
    GltfCompression compression;
  };
  const std::vector<Case> cases = {
      {"plain.glb", ExportFormat::kGlb, GltfCompression::kNone},
      {"plain.gltf", ExportFormat::kGltf, GltfCompression::kNone},
      {"draco.glb", ExportFormat::kGlb, GltfCompression::kDraco},
      {"meshopt.gltf", ExportFormat::kGltf, GltfCompression::kMeshopt}};
  std::vector<std::string> files;
  for (const Case& c : cases) {
    SurfaceMeshExportOptions o = Options(c.format);
    o.compression = c.compression;
    auto exported = ExportSurfaceMesh(model, o);
    ASSERT_TRUE(exported.ok()) << exported.status().message();
    std::ofstream(dir + "/" + c.name, std::ios::binary) << exported->bytes;
    files.push_back(dir + "/" + c.name);
    if (c.format == ExportFormat::kGltf) {
      const auto j = nlohmann::json::parse(exported->bytes);
      ASSERT_EQ(j["nodes"].size(), 2u) << c.name;
      ASSERT_EQ(j["meshes"].size(), 2u) << c.name;
      EXPECT_EQ(j["nodes"][0]["name"], "part1");
      EXPECT_EQ(j["nodes"][1]["name"], "lid");
      EXPECT_EQ(j["meshes"][1]["name"], "lid");
      EXPECT_EQ(j["scenes"][0]["nodes"], nlohmann::json({0, 1}));
    }
  }
  const std::vector<nlohmann::json> reports = testing::ValidateGltf(files, dir);
  EXPECT_EQ(reports.size(), cases.size());
  for (const nlohmann::json& j : reports) {
    EXPECT_EQ(j["errors"], 0) << j.dump();
    EXPECT_EQ(j["warnings"], 0) << j.dump();
  }
}

// Part 1 fitted, part 2 a kept torus, part 3 a kept fan (not manifold):
// every glTF form passes the validator with one node and mesh per part, the
// kept parts' vertices and triangles as many as the input's.
TEST_F(ModelExportTest, KeptPartsPassThroughToGltfAsTheirOwnNodes) {
  const std::string dir = testing::FreshTestDir();
  Model model = TwoParts();
  model.parts[1] = ModelPart();
  model.parts[1].kept =
      KeptMesh{testing::GridTorus(8, 6, 3.0, 0.0), "part 2: genus 1"};
  model.parts.emplace_back();
  model.parts[2].name = "fan";
  model.parts[2].kept = KeptMesh{testing::NonManifoldFan(5.0), "part 3: fan"};
  std::vector<std::string> files;
  for (const GltfCompression compression :
       {GltfCompression::kNone, GltfCompression::kDraco,
        GltfCompression::kMeshopt}) {
    SurfaceMeshExportOptions o = Options(ExportFormat::kGltf);
    o.compression = compression;
    auto exported = ExportSurfaceMesh(model, o);
    ASSERT_TRUE(exported.ok()) << exported.status().message();
    const std::string name =
        dir + "/kept" + std::to_string(static_cast<int>(compression)) + ".gltf";
    std::ofstream(name, std::ios::binary) << exported->bytes;
    files.push_back(name);
    const auto j = nlohmann::json::parse(exported->bytes);
    ASSERT_EQ(j["nodes"].size(), 3u);
    EXPECT_EQ(j["nodes"][1]["name"], "part2");
    EXPECT_EQ(j["nodes"][2]["name"], "fan");
    if (compression == GltfCompression::kNone) {
      const auto& accessors = j["accessors"];
      const auto& torus = j["meshes"][1]["primitives"][0];
      EXPECT_EQ(accessors[torus["attributes"]["POSITION"].get<int>()]["count"],
                48);
      EXPECT_EQ(accessors[torus["indices"].get<int>()]["count"], 3 * 96);
      const auto& fan = j["meshes"][2]["primitives"][0];
      EXPECT_EQ(accessors[fan["attributes"]["POSITION"].get<int>()]["count"],
                5);
      EXPECT_EQ(accessors[fan["indices"].get<int>()]["count"], 9);
    }
    EXPECT_EQ(exported->report.parts, 3);
  }
  const std::vector<nlohmann::json> reports = testing::ValidateGltf(files, dir);
  EXPECT_EQ(reports.size(), 3u);
  for (const nlohmann::json& j : reports) EXPECT_EQ(j["errors"], 0) << j.dump();
}

TEST_F(ModelExportTest, UniformMeshOfATrimmedPartIsRefusedNamingIt) {
  SurfaceMeshExportOptions o = Options(ExportFormat::kObj);
  o.uniform_vertices = 2000;
  auto exported = ExportSurfaceMesh(TwoParts(), o);
  ASSERT_FALSE(exported.ok());
  EXPECT_EQ(exported.status().code(), StatusCode::kInvalidInput);
  EXPECT_EQ(exported.status().message().rfind("part 2: ", 0), 0u)
      << exported.status().message();
}

}  // namespace
}  // namespace sdcb
