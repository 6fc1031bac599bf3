// Runs the `sdcb param` executable as a user would.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/io/mesh/mesh_reader.h"

namespace {

struct RunResult {
  int exit_code = -1;
  std::string err;
};

RunResult RunSdcb(const std::string& args) {
  // One file per test: ctest runs the tests in parallel processes.
  const std::string err_path =
      std::string(SDCB_TEST_TMP) + "/param_cli_stderr_" +
      ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".txt";
  const std::string command = std::string(SDCB_BINARY) + " " + args + " 2> " +
                              err_path + " > /dev/null";
  const int status = std::system(command.c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_path);
  r.err.assign(std::istreambuf_iterator<char>(in),
               std::istreambuf_iterator<char>());
  return r;
}

std::string Mesh(const std::string& name) {
  return std::string(SDCB_MESH_DIR) + "/" + name;
}
std::string Tmp(const std::string& name) {
  return std::string(SDCB_TEST_TMP) + "/param_cli_" + name;
}

TEST(ParamCli, WritesSphereMeshAndJson) {
  const std::string out = Tmp("spool.obj"), json = Tmp("spool.json");
  std::filesystem::remove(out);
  const RunResult r = RunSdcb("param " + Mesh("spool.off") + " -o " + out +
                              " --lambda 0.5 --json " + json + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto input = sdcb::ReadMesh(Mesh("spool.off"));
  auto sphere = sdcb::ReadMesh(out);
  ASSERT_TRUE(input.ok() && sphere.ok());
  EXPECT_EQ(sphere->faces, input->faces);  // same connectivity and order
  ASSERT_EQ(sphere->num_vertices(), input->num_vertices());
  // ReadMesh parses ASCII as float; the full doubles are read here directly
  // from the OBJ text to check unit length and orientation exactly.
  std::vector<Eigen::Vector3d> points;
  std::ifstream obj(out);
  for (std::string line; std::getline(obj, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    double x, y, z;
    ASSERT_EQ(std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z), 3);
    points.emplace_back(x, y, z);
  }
  ASSERT_EQ(static_cast<int>(points.size()), input->num_vertices());
  for (const Eigen::Vector3d& p : points) EXPECT_NEAR(p.norm(), 1.0, 1e-12);
  for (int f = 0; f < input->num_faces(); ++f) {
    EXPECT_EQ(
        sdcb::Det3Sign(points[input->faces(f, 0)], points[input->faces(f, 1)],
                       points[input->faces(f, 2)]),
        1);
  }
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  for (const char* key :
       {"flipped_triangles", "angle_distortion_max", "angle_distortion_avg",
        "area_distortion_max", "area_distortion_avg", "seconds"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["flipped_triangles"], 0);
  EXPECT_DOUBLE_EQ(j["lambda"].get<double>(), 0.5);
  EXPECT_GE(j["angle_distortion_max"].get<double>(),
            j["angle_distortion_avg"].get<double>());
  EXPECT_GE(j["area_distortion_avg"].get<double>(), 2.0);
}

TEST(ParamCli, WritesDistortionColors) {
  const std::string out = Tmp("spool_colors.ply");
  const RunResult r = RunSdcb("param " + Mesh("spool.off") + " -o " + out +
                              " --colors area --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("property uchar red"), std::string::npos);
  EXPECT_TRUE(sdcb::ReadMesh(out).ok());
}

TEST(ParamCli, RejectsNonGenusZeroAndOpenMeshesWithTheIntakeReason) {
  const std::string out = Tmp("never.obj");
  std::filesystem::remove(out);
  RunResult r = RunSdcb("param " + Mesh("elephant.off") + " -o " + out);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("elephant.off"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("genus 3"), std::string::npos) << r.err;
  r = RunSdcb("param " + Mesh("mushroom.off") + " -o " + out);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("mushroom.off"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("boundary"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));  // no partial output
}

TEST(ParamCli, BadUsageExitsTwo) {
  const std::string out = Tmp("usage.obj");
  std::filesystem::remove(out);
  const std::string mesh = Mesh("spool.off");
  for (const std::string& args :
       {"param " + mesh, "param " + mesh + " -o " + out + " --lambda abc",
        "param " + mesh + " -o " + out + " --lambda 0",
        "param " + mesh + " -o " + out + " --colors curvature",
        "param " + mesh + " -o " + out + " --colors angle",  // needs .ply
        "param " + mesh + " -o " + out + " --bogus", "param -o " + out}) {
    EXPECT_EQ(RunSdcb(args).exit_code, 2) << args;
  }
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(ParamCli, UnwritableOutputExitsOne) {
  const RunResult r = RunSdcb("param " + Mesh("spool.off") +
                              " -o /nonexistent-dir/s.obj --quiet");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/nonexistent-dir/s.obj"), std::string::npos) << r.err;
}

}  // namespace
