// `sdcb fit --keep-unfittable` on a mesh of a closed ellipsoid, a torus
// (genus 1) and a fan of three triangles on one edge (not manifold): the
// ellipsoid fitted, the others kept as the input had them, in the report,
// the .sdcb file, the exported OBJ, `info`, `compare`, `eval`; STEP and
// cages refuse the kept parts. The oracle of every kept part is the input's
// own arrays. Without the flag the mesh is refused as before.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "sdcb/io/mesh/mesh_writer.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/open_sphere.h"
#include "testing/run_sdcb.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;

const char kTorusSentence[] =
    "part 2 (96 triangles) has genus 1; sdcb fits genus-0 parts";

// Rows of the input (the oracle): part 2 is the torus (48 vertices, 96
// faces after the ellipsoid's), part 3 the fan (5 and 3).
struct Rows {
  int first_vertex, vertices, first_face, faces;
};

TriangleMesh InputRows(const TriangleMesh& m, const Rows& r) {
  TriangleMesh out;
  out.vertices = m.vertices.middleRows(r.first_vertex, r.vertices);
  out.faces =
      m.faces.middleRows(r.first_face, r.faces).array() - r.first_vertex;
  return out;
}

// An OBJ's "v" rows and, per "o NAME" group, its "f" rows (1-based, the
// "//n" parts dropped), read by hand.
struct Obj {
  std::vector<Eigen::RowVector3d> vertices;
  std::vector<std::pair<std::string, std::vector<Eigen::RowVector3i>>> groups;
};

Obj ParseObj(const std::string& text) {
  Obj obj;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string tag;
    l >> tag;
    if (tag == "v") {
      std::string x, y, z;
      l >> x >> y >> z;
      obj.vertices.emplace_back(std::strtod(x.c_str(), nullptr),
                                std::strtod(y.c_str(), nullptr),
                                std::strtod(z.c_str(), nullptr));
    } else if (tag == "o") {
      std::string name;
      l >> name;
      obj.groups.push_back({name, {}});
    } else if (tag == "f") {
      Eigen::RowVector3i f;
      for (int k = 0; k < 3; ++k) {
        std::string corner;
        l >> corner;
        f[k] = std::atoi(corner.c_str());
      }
      obj.groups.back().second.push_back(f);
    }
  }
  return obj;
}

class KeptPartsCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshTestDir();
    input_ = testing::SphereTorusFan();
    mesh_ = dir_ + "/three.off";
    ASSERT_TRUE(WriteMesh(input_, mesh_).ok());
    const int nv = input_.num_vertices() - 53, nf = input_.num_faces() - 99;
    torus_ = InputRows(input_, {nv, 48, nf, 96});
    fan_ = InputRows(input_, {nv + 48, 5, nf + 96, 3});
  }

  std::string dir_, mesh_;
  TriangleMesh input_, torus_, fan_;
};

TEST_F(KeptPartsCliTest, WithoutTheFlagTheMeshIsRefusedAsBefore) {
  const std::string out = dir_ + "/three.sdcb";
  const RunResult r = RunSdcb({"fit", mesh_, "-o", out, "--quiet"}, dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "sdcb: " + mesh_ + ": " + kTorusSentence + "\n");
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(KeptPartsCliTest, TheSphereIsFittedTheOthersKeptAndPassedThrough) {
  const std::string model = dir_ + "/three.sdcb";
  RunResult r = RunSdcb({"fit", mesh_, "-o", model, "--rmse", "0.3",
                         "--keep-unfittable", "--json", dir_ + "/fit.json"},
                        dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("3 parts, 1 reached the targets, 2 kept"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(std::string("part 2: 96 triangles, kept as a mesh: ") +
                       kTorusSentence),
            std::string::npos)
      << r.out;
  const auto report = nlohmann::json::parse(ReadBytes(dir_ + "/fit.json"));
  ASSERT_EQ(report["parts"].size(), 3u);
  EXPECT_EQ(report["parts"][0]["kept"], false);
  EXPECT_EQ(report["parts"][0]["reached_target"], true);
  EXPECT_EQ(report["parts"][1]["kept"], true);
  EXPECT_EQ(report["parts"][1]["reason"], kTorusSentence);
  EXPECT_EQ(report["parts"][2]["kept"], true);
  EXPECT_EQ(report["parts"][2]["reason"].get<std::string>().rfind(
                "part 3 (3 triangles) is not manifold", 0),
            0u)
      << report["parts"][2]["reason"];
  EXPECT_EQ(report["reached_target"], true);

  // The file holds the kept parts' arrays exactly.
  StatusOr<Model> read = ReadSdcbModelFile(model);
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read->parts.size(), 3u);
  EXPECT_TRUE(read->parts[0].fitted());
  ASSERT_TRUE(read->parts[1].kept && read->parts[2].kept);
  EXPECT_EQ(read->parts[1].kept->mesh.vertices, torus_.vertices);
  EXPECT_EQ(read->parts[1].kept->mesh.faces, torus_.faces);
  EXPECT_EQ(read->parts[2].kept->mesh.vertices, fan_.vertices);
  EXPECT_EQ(read->parts[2].kept->mesh.faces, fan_.faces);
  EXPECT_EQ(read->parts[1].kept->reason, kTorusSentence);

  // The OBJ: every kept part's vertices (17 digits) and faces as given.
  r = RunSdcb({"export", model, "-o", dir_ + "/three.obj", "--tolerance", "0.5",
               "--quiet"},
              dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Obj obj = ParseObj(ReadBytes(dir_ + "/three.obj"));
  ASSERT_EQ(obj.groups.size(), 3u);
  for (const auto& [index, expected] :
       {std::pair<int, const TriangleMesh*>{1, &torus_}, {2, &fan_}}) {
    EXPECT_EQ(obj.groups[index].first, "part" + std::to_string(index + 1));
    const auto& faces = obj.groups[index].second;
    ASSERT_EQ(faces.size(), static_cast<size_t>(expected->num_faces()));
    int first = faces[0].minCoeff();
    for (const auto& f : faces) first = std::min(first, f.minCoeff());
    for (int v = 0; v < expected->num_vertices(); ++v) {
      ASSERT_LT(static_cast<size_t>(first - 1 + v), obj.vertices.size());
      EXPECT_EQ(obj.vertices[first - 1 + v], expected->vertices.row(v))
          << index << " " << v;
    }
    for (int f = 0; f < expected->num_faces(); ++f) {
      const Eigen::RowVector3i got = faces[f].array() - first;
      EXPECT_EQ(got, expected->faces.row(f)) << index << " " << f;
    }
  }

  // glTF: one node and mesh per part.
  r = RunSdcb({"export", model, "-o", dir_ + "/three.glb", "--tolerance", "0.5",
               "--quiet"},
              dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // info and compare name the kept parts; eval, STEP and cages refuse them.
  r = RunSdcb({"info", model, "--json", "-"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto info = nlohmann::json::parse(r.out);
  EXPECT_EQ(info["parts"][1]["kept"], true);
  EXPECT_EQ(info["parts"][1]["triangles"], 96);
  EXPECT_EQ(info["parts"][2]["vertices"], 5);
  r = RunSdcb({"compare", model, mesh_, "--json", "-"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto compare = nlohmann::json::parse(r.out);
  EXPECT_EQ(compare["parts"][1]["kept"], true);
  EXPECT_FALSE(compare["parts"][1].contains("hausdorff_percent"));
  EXPECT_TRUE(compare["parts"][0].contains("hausdorff_percent"));
  std::ofstream(dir_ + "/points.txt") << "0 0 1\n";
  r = RunSdcb({"eval", model, "-i", dir_ + "/points.txt", "-o",
               dir_ + "/values.txt", "--part", "3"},
              dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("part 3 was kept as a mesh, not fitted"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/values.txt"));
  for (const auto& [command, out] :
       {std::pair<std::string, std::string>{"export", dir_ + "/three.step"},
        std::pair<std::string, std::string>{"cage", dir_ + "/cage.obj"}}) {
    r = RunSdcb({command, model, "-o", out}, dir_);
    EXPECT_EQ(r.exit_code, 1) << command;
    EXPECT_NE(r.err.find("part 2 was kept as a mesh, not fitted"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << out;
  }
}

}  // namespace
}  // namespace sdcb
