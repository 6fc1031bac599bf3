// `sdcb fit`, `export`, `compare`, `cad` and `cage` on meshes of open parts
// and of several parts: a disk cut from an ellipsoid and two disjoint
// ellipsoids, whose loops and parts are known by construction; and the
// refusals (a part of genus 1, more parts than --max-parts, a STEP or a
// cage of an open part): one sentence, exit 1, no output file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/mesh/mesh_writer.h"
#include "testing/open_sphere.h"
#include "testing/run_sdcb.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;

const Eigen::Vector3d kAxes(1.0, 0.8, 0.6);

std::string WriteOff(const TriangleMesh& mesh, const std::string& path) {
  EXPECT_TRUE(WriteMesh(mesh, path).ok());
  return path;
}

TEST(OpenPartsCliTest, ADiskIsFittedTrimmedAndExportedWithItsBoundary) {
  const std::string dir = FreshTestDir();
  const TriangleMesh disk =
      testing::OpenEllipsoid(3, kAxes, {{Eigen::Vector3d::UnitZ(), 0.5}});
  const std::string mesh = WriteOff(disk, dir + "/disk.off");
  RunResult r = RunSdcb({"fit", mesh, "-o", dir + "/disk.sdcb", "--rmse", "0.3",
                         "--json", dir + "/fit.json", "--quiet"},
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = nlohmann::json::parse(ReadBytes(dir + "/fit.json"));
  ASSERT_EQ(report["parts"].size(), 1u);
  EXPECT_EQ(report["parts"][0]["boundary_loops"], 1);
  EXPECT_EQ(report["parts"][0]["closed"], false);
  EXPECT_EQ(report["reached_target"], true);

  r = RunSdcb({"info", dir + "/disk.sdcb", "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto info = nlohmann::json::parse(r.out);
  ASSERT_EQ(info["parts"].size(), 1u);

  r = RunSdcb({"export", dir + "/disk.sdcb", "-o", dir + "/disk.obj",
               "--tolerance", "0.1", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  StatusOr<TriangleMesh> exported = ReadMesh(dir + "/disk.obj");
  ASSERT_TRUE(exported.ok());
  StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(*exported);
  ASSERT_TRUE(topology.ok());
  EXPECT_EQ(topology->boundary_loops, 1);
  EXPECT_EQ(topology->genus, 0);

  // The model measured against its mesh: the region it keeps only.
  r = RunSdcb({"compare", dir + "/disk.sdcb", mesh, "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto compare = nlohmann::json::parse(r.out);
  EXPECT_LT(compare["hausdorff_percent"].get<double>(), 3.0);
  // Its boundary: the trims' images against the mesh's boundary edges,
  // within the fit's boundary target (0.4 of the Hausdorff target, 3 %).
  const double boundary = compare["parts"][0]["boundary_percent"].get<double>();
  EXPECT_GT(boundary, 0.0);
  EXPECT_LE(boundary, 1.2);
  EXPECT_EQ(compare["boundary_percent"].get<double>(), boundary);
  // The mesh's loop moved by 2 % of its largest side along z: the boundary
  // distance moves by at most the distance between the two loops (the
  // triangle inequality), which is at most 2 % and at least the moved
  // loop's farthest vertex from the loop (brute force).
  TriangleMesh moved = disk;
  const double side =
      (disk.vertices.colwise().maxCoeff() - disk.vertices.colwise().minCoeff())
          .maxCoeff();
  StatusOr<Eigen::MatrixX2i> edges = BoundaryEdges(disk);
  ASSERT_TRUE(edges.ok());
  std::vector<bool> on_loop(disk.vertices.rows(), false);
  for (Eigen::Index e = 0; e < edges->rows(); ++e) {
    on_loop[(*edges)(e, 0)] = on_loop[(*edges)(e, 1)] = true;
  }
  for (Eigen::Index v = 0; v < moved.vertices.rows(); ++v) {
    if (on_loop[v]) moved.vertices(v, 2) += 0.02 * side;
  }
  double apart = 0;
  for (Eigen::Index v = 0; v < moved.vertices.rows(); ++v) {
    if (!on_loop[v]) continue;
    const Eigen::Vector3d q = moved.vertices.row(v);
    double nearest = 1e300;
    for (Eigen::Index e = 0; e < edges->rows(); ++e) {
      const Eigen::Vector3d a = disk.vertices.row((*edges)(e, 0));
      const Eigen::Vector3d d =
          disk.vertices.row((*edges)(e, 1)) - a.transpose();
      const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (a + t * d - q).norm());
    }
    apart = std::max(apart, nearest);
  }
  apart *= 100 / side;
  ASSERT_GT(apart, 1.0);  // the loop moved clear of itself
  const std::string moved_path = WriteOff(moved, dir + "/moved.off");
  r = RunSdcb({"compare", dir + "/disk.sdcb", moved_path, "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double moved_boundary =
      nlohmann::json::parse(r.out)["parts"][0]["boundary_percent"]
          .get<double>();
  EXPECT_GE(moved_boundary, apart - boundary - 1e-6);
  EXPECT_LE(moved_boundary, 2.0 + boundary + 1e-6);

  // STEP and cages of open parts: one sentence naming the part.
  for (const auto& [command, out] :
       {std::pair<std::string, std::string>{"export", dir + "/disk.step"},
        std::pair<std::string, std::string>{"cage", dir + "/disk_cage.obj"}}) {
    r = RunSdcb({command, dir + "/disk.sdcb", "-o", out}, dir);
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.err;
    EXPECT_NE(r.err.find("part 1 is open (1 trim loop)"), std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << out;
  }
}

TEST(OpenPartsCliTest, TwoPartsComeOutAsTwoObjects) {
  const std::string dir = FreshTestDir();
  TriangleMesh far = testing::OpenEllipsoid(2, kAxes, {});
  far.vertices.col(0).array() += 5.0;
  const std::string mesh =
      WriteOff(testing::Concatenated(testing::OpenEllipsoid(2, kAxes, {}), far),
               dir + "/two.off");
  RunResult r = RunSdcb(
      {"fit", mesh, "-o", dir + "/two.sdcb", "--rmse", "0.3", "--quiet"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunSdcb({"export", dir + "/two.sdcb", "-o", dir + "/two.obj",
               "--tolerance", "0.2", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string obj = ReadBytes(dir + "/two.obj");
  EXPECT_NE(obj.find("\no part1\n"), std::string::npos);
  EXPECT_NE(obj.find("\no part2\n"), std::string::npos);
  r = RunSdcb({"compare", dir + "/two.sdcb", mesh, "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["parts"].size(), 2u);
  // Against a mesh of another number of parts: one sentence.
  r = RunSdcb({"compare", dir + "/two.sdcb", WriteOff(far, dir + "/one.off")},
              dir);
  EXPECT_EQ(r.exit_code, 1);
  testing::ExpectOneSentenceNaming(r, "one.off");
}

TEST(OpenPartsCliTest, AnUnfittablePartRefusesTheMeshWithNoOutput) {
  const std::string dir = FreshTestDir();
  // Part 2: a torus of 8 x 6 quads (genus 1).
  const TriangleMesh torus = testing::GridTorus(8, 6, 2.0, 5.0);
  const std::string mesh = WriteOff(
      testing::Concatenated(testing::OpenEllipsoid(2, kAxes, {}), torus),
      dir + "/with_torus.off");
  RunResult r = RunSdcb({"fit", mesh, "-o", dir + "/x.sdcb"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  testing::ExpectOneSentenceNaming(r, "with_torus.off");
  EXPECT_NE(r.err.find("part 2 (96 triangles) has genus 1; sdcb fits genus-0 "
                       "parts"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.sdcb"));

  // More parts than --max-parts: refused before any fit.
  r = RunSdcb({"fit", mesh, "-o", dir + "/x.sdcb", "--max-parts", "1"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  testing::ExpectOneSentenceNaming(r, "with_torus.off");
  EXPECT_NE(r.err.find("--max-parts 1"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.sdcb"));
}

}  // namespace
}  // namespace sdcb
