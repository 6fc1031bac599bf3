// `sdcb fit / info / dump / eval` as pipelines use them.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/mesh/mesh_writer.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/brute_force_configurations.h"
#include "testing/honest_fit_errors.h"
#include "testing/run_sdcb.h"
#include "testing/seam_split_cube.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::MeshPath;
using testing::ReadBytes;
using testing::RunResult;
using testing::RunSdcb;
using testing::WriteBytes;

namespace fs = std::filesystem;

// Fits blobby into `dir` (model blobby.sdcb, report.json, plot.svg), with
// `extra` flags; returns the model path.
std::string FitBlobby(const std::string& dir,
                      const std::string& extra_rounds = "1",
                      const std::vector<std::string>& extra = {}) {
  const std::string model = dir + "/blobby.sdcb";
  std::vector<std::string> args = {"fit",          MeshPath("blobby.off"),
                                   "-o",           model,
                                   "--rmse",       "0.1",
                                   "--max-rounds", extra_rounds,
                                   "--json",       dir + "/report.json",
                                   "--plot",       dir + "/plot.svg",
                                   "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  const RunResult r = RunSdcb(args, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return model;
}

// `sdcb eval` of `model` at `points` (a POINTS.txt); #points by 3.
Eigen::MatrixX3d Eval(const std::string& model, const std::string& points,
                      const std::string& dir) {
  const RunResult r =
      RunSdcb({"eval", model, "-i", points, "-o", dir + "/values.txt"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::istringstream in(ReadBytes(dir + "/values.txt"));
  std::vector<Eigen::RowVector3d> rows;
  Eigen::RowVector3d v;
  while (in >> v[0] >> v[1] >> v[2]) rows.push_back(v);
  Eigen::MatrixX3d out(rows.size(), 3);
  for (size_t i = 0; i < rows.size(); ++i) out.row(i) = rows[i];
  return out;
}

TEST(FitCliTest, ReportHasTheDesignKeysAndThePlotIsWritten) {
  const std::string dir = FreshTestDir();
  FitBlobby(dir, "3");
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/report.json"));
  ASSERT_TRUE(j.contains("rounds") && j.contains("final") &&
              j.contains("timings"));
  for (const auto& round : j["rounds"]) {
    for (const char* key :
         {"round", "knots", "control_points", "rmse_percent",
          "max_error_percent", "vertex_rmse_percent",
          "vertex_max_error_percent", "folded_area_percent", "seconds"}) {
      EXPECT_TRUE(round.contains(key)) << key;
    }
  }
  EXPECT_EQ(j["error_measure"], "dense_two_sided");
  EXPECT_EQ(j["basis_form"], "normalized");
  EXPECT_TRUE(j.contains("reached_target"));
  for (const char* key : {"parameterization", "knot_placement",
                          "configurations", "basis", "solve", "total"}) {
    EXPECT_TRUE(j["timings"].contains(key)) << key;
  }
  EXPECT_EQ(j["final"], j["rounds"].back());
  // Reached on the input's own triangles: no split, no second fit.
  EXPECT_EQ(j["map"]["vertices"], j["vertices"]);
  EXPECT_EQ(j["map"]["split_retry_run"], false);
  EXPECT_EQ(j["map"]["lambda"], 1.0);
  EXPECT_EQ(j["map"]["lambda_retries_run"], 0);
  EXPECT_EQ(j["options"]["map_vertices"], 0);
  const std::string svg = ReadBytes(dir + "/plot.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("polyline"), std::string::npos);
}

// The report names the input's sharp features (core/mesh/feature_curves.h):
// the cube's 12 edges, each a curve between two of its 8 corners, kept by
// the corners' clusters (32 knots); none at --feature-angle 180, which fits
// the cube smooth (knots placed by curvature); an angle outside (0, 180] is
// a usage error.
TEST(FitCliTest, ReportCountsTheCubesSharpFeatures) {
  const std::string dir = FreshTestDir();
  const auto fit = [&](const std::string& angle) {
    std::vector<std::string> args = {
        "fit", MeshPath("cube.off"), "-o", dir + "/c.sdcb", "--rmse",
        "5",   "--max-rounds",       "1",  "--json",        dir + "/c.json"};
    if (!angle.empty()) {
      args.push_back("--feature-angle");
      args.push_back(angle);
    }
    return RunSdcb(args, dir);
  };
  RunResult r = fit("");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto features = nlohmann::json::parse(ReadBytes(dir + "/c.json"))["features"];
  EXPECT_EQ(features["angle_degrees"], 30.0);
  EXPECT_EQ(features["edges"], 12);
  EXPECT_EQ(features["curves"], 12);
  EXPECT_EQ(features["corners"], 8);
  EXPECT_EQ(features["used"], true);
  EXPECT_EQ(nlohmann::json::parse(ReadBytes(dir + "/c.json"))["final"]["knots"],
            32);
  r = fit("180");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto smooth = nlohmann::json::parse(ReadBytes(dir + "/c.json"));
  features = smooth["features"];
  EXPECT_EQ(features["edges"], 0);
  EXPECT_EQ(features["corners"], 0);
  EXPECT_EQ(features["used"], false);
  EXPECT_GE(smooth["final"]["knots"], 70);  // at least the default round 0
  r = fit("0");
  EXPECT_EQ(r.exit_code, 2);
}

// --map-vertices N fits a coarser input split to about N vertices from the
// start: the report's map counts them, the model records N and keeps the
// sphere points of the input's vertices only; a negative N is a usage
// error, and so is a word other than auto (the message names both forms, as
// --quantize's does).
TEST(FitCliTest, MapVerticesSplitsACoarseInput) {
  const std::string dir = FreshTestDir();
  RunResult r = RunSdcb({"fit", MeshPath("sphere.off"), "-o", dir + "/s.sdcb",
                         "--rmse", "0.2", "--map-vertices", "3000",
                         "--store-parameters", "--json", dir + "/s.json"},
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/s.json"));
  EXPECT_EQ(j["vertices"], 162);
  EXPECT_GT(j["map"]["vertices"], 1500);
  EXPECT_EQ(j["map"]["split_retry_run"], false);
  EXPECT_EQ(j["options"]["map_vertices"], 3000);
  auto model = ReadSdcbFile(dir + "/s.sdcb");
  ASSERT_TRUE(model.ok()) << model.status().message();
  EXPECT_EQ(model->parameters.rows(), 162);
  EXPECT_EQ(model->statistics.options.map_vertices, 3000);
  r = RunSdcb({"fit", MeshPath("sphere.off"), "-o", dir + "/t.sdcb",
               "--map-vertices", "-1"},
              dir);
  EXPECT_EQ(r.exit_code, 2);
  for (const char* option : {"--map-vertices", "--quantize"}) {
    r = RunSdcb(
        {"fit", MeshPath("sphere.off"), "-o", dir + "/t.sdcb", option, "abc"},
        dir);
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_NE(r.err.find("] or auto, got 'abc'"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/t.sdcb"));
}

// By default the cube's corners' knot clusters alone reach the
// target (docs/FITTING.md): a few hundred control points where the smooth
// fit needs thousands, and the report says the features were used; its
// STEP export has the cube's faces; with --quantize as well, and its mesh
// export follows the creases.
// The tetrahedron's edges are alone on their great circles: kept by the
// second try, four knots along each edge from each corner; the summary says
// the surface is creased, and its STEP solid is every face split in three
// quads, bordered by the 6 edges (each two crease edges of the B-rep, split
// at its midpoint).
TEST(FitCliTest, TheTetrahedronKeepsItsEdges) {
  const std::string dir = FreshTestDir();
  RunResult r =
      RunSdcb({"fit", MeshPath("tetrahedron.off"), "-o", dir + "/t.sdcb",
               "--rmse", "0.1", "--json", dir + "/t.json"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("4 corners (kept: the surface is creased along them)"),
            std::string::npos)
      << r.out;
  const auto report = nlohmann::json::parse(ReadBytes(dir + "/t.json"));
  EXPECT_EQ(report["features"]["used"], true);
  EXPECT_EQ(report["reached_target"], true);
  EXPECT_EQ(report["final"]["knots"], 52);
  r = RunSdcb({"export", dir + "/t.sdcb", "-o", dir + "/t.step", "--json",
               dir + "/step.json", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto step = nlohmann::json::parse(ReadBytes(dir + "/step.json"));
  EXPECT_EQ(step["layout"], "feature faces");
  EXPECT_EQ(step["faces"], 12);
  EXPECT_EQ(step["crease_edges"], 12);
  EXPECT_EQ(step["valid"], true);
}

TEST(FitCliTest, TheCubeKeepsItsEdgesWithItsCornerClusters) {
  const std::string dir = FreshTestDir();
  RunResult r = RunSdcb({"fit", MeshPath("cube.off"), "-o", dir + "/c.sdcb",
                         "--rmse", "0.1", "--json", dir + "/c.json", "--quiet"},
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = nlohmann::json::parse(ReadBytes(dir + "/c.json"));
  EXPECT_EQ(report["features"]["used"], true);
  EXPECT_EQ(report["reached_target"], true);
  EXPECT_EQ(report["final"]["knots"], 32);
  EXPECT_LE(report["final"]["control_points"], 300);
  EXPECT_LE(report["final"]["max_error_percent"], 0.2);
  // Its STEP solid is the cube's six faces, bordered by the 12 creases.
  r = RunSdcb({"export", dir + "/c.sdcb", "-o", dir + "/c.step", "--json",
               dir + "/step.json", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto step = nlohmann::json::parse(ReadBytes(dir + "/step.json"));
  EXPECT_EQ(step["layout"], "feature faces");
  EXPECT_EQ(step["faces"], 6);
  EXPECT_EQ(step["crease_edges"], 12);
  EXPECT_EQ(step["valid"], true);
  // Quantized too (the clusters are not snapped to the knot grid): the
  // export still follows the 12 creases, 12 triangles.
  r = RunSdcb({"fit", MeshPath("cube.off"), "-o", dir + "/q.sdcb", "--rmse",
               "0.1", "--quantize", "auto", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunSdcb({"export", dir + "/q.sdcb", "-o", dir + "/q.glb", "--json",
               dir + "/q.json", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto exported = nlohmann::json::parse(ReadBytes(dir + "/q.json"));
  EXPECT_EQ(exported["feature_arcs"], 12);
  EXPECT_EQ(exported["triangles"], 12);
}

// A cube stored with its vertices split at every face (24 vertices, six
// open quads) is welded at intake without --repair and fitted as the closed
// 8-vertex cube; the report carries the count.
TEST(FitCliTest, ASeamSplitCubeIsWeldedAndFittedClosed) {
  const std::string dir = FreshTestDir();
  ASSERT_TRUE(WriteMesh(testing::SeamSplitCube(), dir + "/cube24.obj").ok());
  const RunResult r =
      RunSdcb({"fit", dir + "/cube24.obj", "-o", dir + "/c.sdcb", "--rmse",
               "0.5", "--json", dir + "/c.json", "--quiet"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("cube24.obj: merged 16 vertices split at equal "
                       "positions (UV or normal seams)"),
            std::string::npos)
      << r.err;
  const auto report = nlohmann::json::parse(ReadBytes(dir + "/c.json"));
  EXPECT_EQ(report["seam_vertices_merged"], 16);
  EXPECT_EQ(report["vertices"], 8);
  EXPECT_EQ(report["faces"], 12);
  EXPECT_EQ(report["reached_target"], true);
}

// Without --quiet the summary prints the seconds of every stage: the
// report's values, and together no more than the whole fit (the stages run
// one after the other).
TEST(FitCliTest, SummaryPrintsTheStageTimesOfTheReport) {
  const std::string dir = FreshTestDir();
  const RunResult r =
      RunSdcb({"fit", MeshPath("blobby.off"), "-o", dir + "/b.sdcb", "--rmse",
               "0.1", "--max-rounds", "2", "--json", dir + "/report.json"},
              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t =
      nlohmann::json::parse(ReadBytes(dir + "/report.json"))["timings"];
  const size_t at = r.out.find("  stages: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  double printed[6];
  ASSERT_EQ(std::sscanf(r.out.c_str() + at,
                        "  stages: parameterization %lf s, knot placement %lf "
                        "s, configurations %lf s, basis %lf s, solve %lf s, "
                        "measure %lf s",
                        &printed[0], &printed[1], &printed[2], &printed[3],
                        &printed[4], &printed[5]),
            6)
      << r.out;
  double sum = 0.0;
  int i = 0;
  for (const char* key : {"parameterization", "knot_placement",
                          "configurations", "basis", "solve", "measure"}) {
    const double seconds = t[key];
    EXPECT_NEAR(printed[i++], seconds, 0.005 + 1e-9) << key;
    EXPECT_GE(seconds, 0.0) << key;
    sum += seconds;
  }
  EXPECT_GT(t["parameterization"].get<double>(), 0.0);
  EXPECT_LE(sum, t["total"].get<double>() + 1e-6);
}

// A target the rounds cannot reach: the model is still written (exit 0), and
// the warning on stderr gives the report's reason.
TEST(FitCliTest, AMissedTargetWarnsWithTheReportsReason) {
  const std::string dir = FreshTestDir();
  const RunResult r = RunSdcb(
      {"fit", MeshPath("blobby.off"), "-o", dir + "/b.sdcb", "--rmse", "0.001",
       "--max-rounds", "1", "--json", dir + "/report.json", "--quiet"},
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/b.sdcb"));
  const auto j = nlohmann::json::parse(ReadBytes(dir + "/report.json"));
  ASSERT_EQ(j["reached_target"], false);
  const std::string reason = j["shortfall"];
  EXPECT_FALSE(reason.empty());
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
  // No fold in the returned surface: no picture to look at.
  EXPECT_EQ(j["final"]["folded_area_percent"], 0.0);
  EXPECT_EQ(r.err.find("--picture"), std::string::npos) << r.err;
  // A returned surface that folds (cactus's first round): the warning says
  // how to see where.
  const RunResult folded =
      RunSdcb({"fit", MeshPath("cactus.off"), "-o", dir + "/c.sdcb", "--rmse",
               "0.1", "--max-rounds", "1", "--accept-folds", "--quiet"},
              dir);
  ASSERT_EQ(folded.exit_code, 0) << folded.err;
  EXPECT_NE(folded.err.find("`sdcb compare " + dir + "/c.sdcb " +
                            MeshPath("cactus.off") +
                            " --picture folds.ply` shows where (blue)"),
            std::string::npos)
      << folded.err;
}

// --accept-folds changes which round is returned, so the model records it.
TEST(FitCliTest, AcceptFoldsIsRecordedInTheModel) {
  const std::string dir = FreshTestDir();
  for (bool accept : {false, true}) {
    const std::string model = dir + (accept ? "/a.sdcb" : "/b.sdcb");
    std::vector<std::string> args = {"fit",    MeshPath("blobby.off"), "-o",
                                     model,    "--max-rounds",         "1",
                                     "--quiet"};
    if (accept) args.push_back("--accept-folds");
    ASSERT_EQ(RunSdcb(args, dir).exit_code, 0);
    ASSERT_EQ(RunSdcb({"dump", model, "-o", model + ".json"}, dir).exit_code,
              0);
    const auto dump = nlohmann::json::parse(ReadBytes(model + ".json"));
    EXPECT_EQ(dump["statistics"]["options"]["fallback_accepts_folds"], accept);
  }
}

TEST(FitCliTest, EvalAtTheStoredParametersReproducesTheReportedErrors) {
  const std::string dir = FreshTestDir();
  const std::string model = FitBlobby(dir, "2", {"--store-parameters"});
  ASSERT_EQ(RunSdcb({"dump", model, "-o", dir + "/dump.json"}, dir).exit_code,
            0);
  const auto dump = nlohmann::json::parse(ReadBytes(dir + "/dump.json"));
  std::ostringstream points;
  points.precision(17);
  for (const auto& p : dump["parameters"]) {
    points << p[0].get<double>() << " " << p[1].get<double>() << " "
           << p[2].get<double>() << "\n";
  }
  WriteBytes(dir + "/points.txt", points.str());
  const RunResult r = RunSdcb(
      {"eval", model, "-i", dir + "/points.txt", "-o", dir + "/values.txt"},
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Independent error computation from the input mesh.
  auto mesh = ReadMesh(MeshPath("blobby.off"));
  ASSERT_TRUE(mesh.ok());
  std::istringstream values(ReadBytes(dir + "/values.txt"));
  const Eigen::RowVector3d lo = mesh->vertices.colwise().minCoeff();
  const Eigen::RowVector3d hi = mesh->vertices.colwise().maxCoeff();
  const double side = (hi - lo).maxCoeff();
  double sum = 0, max = 0;
  for (int v = 0; v < mesh->num_vertices(); ++v) {
    Eigen::RowVector3d f;
    ASSERT_TRUE(values >> f[0] >> f[1] >> f[2]);
    const double e = 100 * (f - mesh->vertices.row(v)).norm() / side;
    sum += e * e;
    max = std::max(max, e);
  }
  const auto report = nlohmann::json::parse(ReadBytes(dir + "/report.json"));
  const double rmse = std::sqrt(sum / mesh->num_vertices());
  EXPECT_NEAR(rmse, report["final"]["vertex_rmse_percent"].get<double>(), 1e-7);
  EXPECT_NEAR(max, report["final"]["vertex_max_error_percent"].get<double>(),
              1e-7);
}

// `sdcb compare` measures the fitted model against its mesh as the fit's
// final measurement did (same method, its own lattice and closest points,
// the mesh's side inside its triangles too), and the numbers are consistent
// with each other; `--mesh-samples 0` measures the mesh's side at its
// vertices only, a subset, with a bound that is valid but loose.
TEST(FitCliTest, CompareAgreesWithTheFitReport) {
  const std::string dir = FreshTestDir();
  const std::string model = FitBlobby(dir, "3");
  const RunResult r =
      RunSdcb({"compare", model, MeshPath("blobby.off"), "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto c = nlohmann::json::parse(r.out);
  const RunResult vertices_run =
      RunSdcb({"compare", model, MeshPath("blobby.off"), "--mesh-samples", "0",
               "--json", "-"},
              dir);
  ASSERT_EQ(vertices_run.exit_code, 0) << vertices_run.err;
  const auto vertices = nlohmann::json::parse(vertices_run.out);
  EXPECT_EQ(vertices["mesh_samples"].get<int>(), 2027);
  EXPECT_EQ(vertices["mesh_sample_spacing_percent"].get<double>(), 0.0);
  EXPECT_LE(vertices["mesh_to_surface_max_percent"].get<double>(),
            c["mesh_to_surface_max_percent"].get<double>());
  EXPECT_GE(vertices["mesh_to_surface_max_bound_percent"].get<double>(),
            c["mesh_to_surface_max_percent"].get<double>());
  EXPECT_EQ(vertices["surface_to_mesh_max_percent"].get<double>(),
            c["surface_to_mesh_max_percent"].get<double>());
  const auto report = nlohmann::json::parse(ReadBytes(dir + "/report.json"));
  ASSERT_EQ(report["reached_target"], true);
  EXPECT_EQ(report["options"]["final_mesh_samples"], 100000);
  const double fit_rms = report["final"]["rmse_percent"].get<double>();
  const double fit_max = report["final"]["max_error_percent"].get<double>();
  EXPECT_NEAR(c["rmse_percent"].get<double>(), fit_rms, 0.05 * fit_rms);
  EXPECT_NEAR(c["hausdorff_percent"].get<double>(), fit_max, 0.05 * fit_max);
  EXPECT_EQ(c["folded_area_percent"].get<double>(), 0.0);
  EXPECT_GE(c["surface_samples"].get<int>(), 100000);
  // About 100,000 mesh samples, and the points its bound added: the bound
  // within 1 % of the maximum unless they reached their budget (a fifth of
  // the samples asked).
  EXPECT_GT(c["mesh_samples"].get<int>(), 90000);
  EXPECT_LT(c["mesh_samples"].get<int>(), 150000);
  const double m2s = c["mesh_to_surface_max_percent"].get<double>();
  const double bound = c["mesh_to_surface_max_bound_percent"].get<double>();
  EXPECT_GE(bound, m2s);
  EXPECT_LE(c["mesh_bound_samples"].get<int>(), 20000);
  if (c["mesh_bound_samples"].get<int>() < 20000) {
    EXPECT_LE(bound, 1.01 * m2s);
  }
  // Two-sided: the larger of the one-sided maxima, rms between them.
  const double s2m = c["surface_to_mesh_max_percent"].get<double>();
  EXPECT_EQ(c["hausdorff_percent"].get<double>(), std::max(s2m, m2s));
  // A mesh moved by 1 % of its largest side along x: the distance grows.
  auto mesh = ReadMesh(MeshPath("blobby.off"));
  ASSERT_TRUE(mesh.ok());
  const double side = (mesh->vertices.colwise().maxCoeff() -
                       mesh->vertices.colwise().minCoeff())
                          .maxCoeff();
  TriangleMesh moved_mesh = *mesh;
  moved_mesh.vertices.col(0).array() += 0.01 * side;
  ASSERT_TRUE(WriteMesh(moved_mesh, dir + "/moved.off").ok());
  const RunResult moved =
      RunSdcb({"compare", model, dir + "/moved.off", "--json", "-"}, dir);
  ASSERT_EQ(moved.exit_code, 0) << moved.err;
  const auto cm = nlohmann::json::parse(moved.out);
  EXPECT_GT(cm["hausdorff_percent"].get<double>(), 0.5);
  EXPECT_LT(cm["hausdorff_percent"].get<double>(), 1.0 + fit_max);
  // Bad input: exit 1, one line naming the file, no output.
  const RunResult missing =
      RunSdcb({"compare", dir + "/none.sdcb", MeshPath("blobby.off"), "--json",
               dir + "/c.json"},
              dir);
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("none.sdcb"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir + "/c.json"));
  EXPECT_EQ(RunSdcb({"compare", model}, dir).exit_code, 2);
}

// An ASCII PLY of `sdcb compare --picture`: vertices with their colors, and
// the face count.
struct Picture {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> colors;
  int faces = 0;
};
Picture ReadPicture(const std::string& path) {
  std::istringstream in(ReadBytes(path));
  Picture p;
  std::string line;
  int vertices = 0;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string a, b;
    int n = 0;
    if (words >> a >> b >> n && a == "element") {
      (b == "vertex" ? vertices : p.faces) = n;
    }
  }
  for (int v = 0; v < vertices; ++v) {
    Eigen::Vector3d x;
    std::array<int, 3> c;
    in >> x.x() >> x.y() >> x.z() >> c[0] >> c[1] >> c[2];
    p.points.push_back(x);
    p.colors.push_back(c);
  }
  return p;
}

// `sdcb compare --picture` writes the measured surface: a vertex per surface
// sample at F in the input's coordinates, white (0) to red (the largest
// distance), folded samples blue. Against the mesh the vertices' colors
// follow their distances to it (brute force over its triangles), none is
// blue; against the mesh with its faces reversed every sample is folded.
TEST(FitCliTest, ComparePictureShowsTheDistancesAndTheFolds) {
  const std::string dir = FreshTestDir();
  const std::string model = FitBlobby(dir, "2");
  const RunResult r = RunSdcb(
      {"compare", model, MeshPath("blobby.off"), "--samples", "5000",
       "--mesh-samples", "0", "--picture", dir + "/p.ply", "--json", "-"},
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto c = nlohmann::json::parse(r.out);
  EXPECT_EQ(c["picture"], dir + "/p.ply");
  EXPECT_EQ(c["folded_area_percent"].get<double>(), 0.0);
  const Picture p = ReadPicture(dir + "/p.ply");
  ASSERT_EQ(static_cast<int64_t>(p.points.size()),
            c["surface_samples"].get<int64_t>());
  EXPECT_GT(p.faces, static_cast<int>(p.points.size()));
  auto mesh = ReadMesh(MeshPath("blobby.off"));
  ASSERT_TRUE(mesh.ok());
  const double side = (mesh->vertices.colwise().maxCoeff() -
                       mesh->vertices.colwise().minCoeff())
                          .maxCoeff();
  const double max = c["surface_to_mesh_max_percent"].get<double>();
  int reddest = 0;
  for (size_t v = 0; v < p.points.size(); v += 13) {
    const double d =
        100 * testing::BruteForceDistance(*mesh, p.points[v]) / side;
    const int green = static_cast<int>(std::lround(255 * (1 - d / max)));
    EXPECT_EQ(p.colors[v][0], 255);
    EXPECT_NEAR(p.colors[v][1], green, 1) << v;
    EXPECT_EQ(p.colors[v][1], p.colors[v][2]);
  }
  for (size_t v = 0; v < p.points.size(); ++v) {
    if (p.colors[v][1] != 0) continue;
    ++reddest;
    EXPECT_NEAR(100 * testing::BruteForceDistance(*mesh, p.points[v]) / side,
                max, 0.005 * max);
  }
  EXPECT_GE(reddest, 1);

  TriangleMesh reversed_mesh = *mesh;
  reversed_mesh.faces.col(1).swap(reversed_mesh.faces.col(2));
  ASSERT_TRUE(WriteMesh(reversed_mesh, dir + "/reversed.off").ok());
  const RunResult reversed = RunSdcb(
      {"compare", model, dir + "/reversed.off", "--samples", "5000",
       "--mesh-samples", "0", "--picture", dir + "/r.ply", "--json", "-"},
      dir);
  ASSERT_EQ(reversed.exit_code, 0) << reversed.err;
  EXPECT_GT(
      nlohmann::json::parse(reversed.out)["folded_area_percent"].get<double>(),
      99.9);
  const Picture folded = ReadPicture(dir + "/r.ply");
  ASSERT_EQ(folded.points.size(), p.points.size());
  for (const auto& color : folded.colors) {
    EXPECT_EQ(color, (std::array<int, 3>{0, 64, 255}));
  }
  // Not a PLY: a usage error before any work, nothing written.
  EXPECT_EQ(RunSdcb({"compare", model, MeshPath("blobby.off"), "--picture",
                     dir + "/p.obj"},
                    dir)
                .exit_code,
            2);
  EXPECT_FALSE(fs::exists(dir + "/p.obj"));
}

TEST(FitCliTest, DumpedConfigurationsAreConfirmedByBruteForce) {
  const std::string dir = FreshTestDir();
  const std::string model = FitBlobby(dir, "1");  // one round: 100 knots
  ASSERT_EQ(RunSdcb({"dump", model, "-o", dir + "/dump.json"}, dir).exit_code,
            0);
  const auto dump = nlohmann::json::parse(ReadBytes(dir + "/dump.json"));
  const int degree = dump["degree"];
  Eigen::MatrixX3d knots(dump["knots"].size(), 3);
  for (size_t i = 0; i < dump["knots"].size(); ++i) {
    for (int k = 0; k < 3; ++k) knots(i, k) = dump["knots"][i][k];
  }
  const DelaunayConfigurations oracle =
      testing::BruteForceConfigurations(knots, degree);
  ASSERT_EQ(dump["basis"].size(), oracle.sets.size());
  for (size_t i = 0; i < oracle.sets.size(); ++i) {
    EXPECT_EQ(dump["basis"][i]["knots"].get<std::vector<int>>(),
              oracle.sets[i].knots);
    std::vector<std::array<int, 3>> boundaries;
    for (const auto& b : dump["basis"][i]["configurations"]) {
      boundaries.push_back({b[0].get<int>(), b[1].get<int>(), b[2].get<int>()});
    }
    EXPECT_EQ(boundaries, oracle.sets[i].boundaries);
  }
}

TEST(FitCliTest, TwoRunsGiveByteIdenticalModels) {
  const std::string a = FreshTestDir() + "/a";
  const std::string b = a + "_b";
  fs::create_directories(a);
  fs::create_directories(b);
  EXPECT_EQ(ReadBytes(FitBlobby(a, "2")), ReadBytes(FitBlobby(b, "2")));
}

TEST(FitCliTest, InfoReadsTheModel) {
  const std::string dir = FreshTestDir();
  const std::string model = FitBlobby(dir, "1");
  const RunResult r = RunSdcb({"info", model, "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["degree"], 4);
  EXPECT_EQ(j["knots"], 70);  // one round of the default 70 knots
  EXPECT_EQ(j["source"]["vertices"], 2027);
  EXPECT_EQ(j["format_version"], 2);
  EXPECT_EQ(j["file_bytes"], fs::file_size(model));
  const auto report = nlohmann::json::parse(ReadBytes(dir + "/report.json"));
  EXPECT_EQ(report["output_bytes"], fs::file_size(model));
  // Parameters only on request; lossless by default.
  EXPECT_EQ(j["has_parameters"], false);
  EXPECT_EQ(j["quantization_bits"], 0);
  EXPECT_FALSE(report.contains("quantization_error_bound_percent"));
  const RunResult text = RunSdcb({"info", model}, dir);
  EXPECT_NE(text.out.find("format version         2 ("), std::string::npos)
      << text.out;
  // A version 1 file reads and says so.
  const RunResult v1 = RunSdcb(
      {"info", testing::TestDataPath("cow_round0_v1.sdcb"), "--json", "-"},
      dir);
  ASSERT_EQ(v1.exit_code, 0) << v1.err;
  const auto j1 = nlohmann::json::parse(v1.out);
  EXPECT_EQ(j1["format_version"], 1);
  EXPECT_EQ(j1["has_parameters"], true);
}

TEST(FitCliTest, QuantizedModelStaysWithinTheStatedBound) {
  const std::string exact_dir = FreshTestDir() + "/exact";
  const std::string quantized_dir = exact_dir + "_quantized";
  fs::create_directories(exact_dir);
  fs::create_directories(quantized_dir);
  // --quantize fits with the knots on a 16-bit grid: the exact model of the
  // same fit is the one with --knot-grid 16.
  const std::string exact = FitBlobby(exact_dir, "1", {"--knot-grid", "16"});
  const std::string quantized =
      FitBlobby(quantized_dir, "1", {"--quantize", "10"});
  const auto report =
      nlohmann::json::parse(ReadBytes(quantized_dir + "/report.json"));
  ASSERT_TRUE(report.contains("quantization_error_bound_percent"));
  EXPECT_EQ(report["quantization_bits"], 10);
  const double bound_percent =
      report["quantization_error_bound_percent"].get<double>();
  EXPECT_GT(bound_percent, 0.0);
  EXPECT_LT(fs::file_size(quantized), fs::file_size(exact));
  const RunResult r = RunSdcb({"info", quantized, "--json", "-"}, exact_dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto info = nlohmann::json::parse(r.out);
  EXPECT_EQ(info["quantization_bits"], 10);
  EXPECT_EQ(info["quantization_error_bound_percent"].get<double>(),
            bound_percent);
  // Both surfaces at 3000 directions: within the bound, in percent of the
  // largest side of the input's bounding box, and not far below it.
  std::ostringstream points;
  points.precision(17);
  std::mt19937 rng(4);
  std::normal_distribution<double> gauss;
  for (int i = 0; i < 3000; ++i) {
    points << gauss(rng) << " " << gauss(rng) << " " << gauss(rng) << "\n";
  }
  WriteBytes(exact_dir + "/points.txt", points.str());
  const Eigen::MatrixX3d a = Eval(exact, exact_dir + "/points.txt", exact_dir);
  const Eigen::MatrixX3d b =
      Eval(quantized, exact_dir + "/points.txt", exact_dir);
  ASSERT_EQ(a.rows(), 3000);
  ASSERT_EQ(b.rows(), 3000);
  auto mesh = ReadMesh(MeshPath("blobby.off"));
  ASSERT_TRUE(mesh.ok());
  const double side = (mesh->vertices.colwise().maxCoeff() -
                       mesh->vertices.colwise().minCoeff())
                          .maxCoeff();
  const double moved = 100 * (a - b).rowwise().norm().maxCoeff() / side;
  EXPECT_LE(moved, bound_percent * (1 + 1e-9));
  EXPECT_GE(moved, 0.2 * bound_percent);
  EXPECT_EQ(info["knot_grid_bits"], 16);
  // auto: the coarsest grid whose bound is within half the fit's rms.
  const std::string automatic =
      FitBlobby(quantized_dir, "1", {"--quantize", "auto"});
  const auto auto_report =
      nlohmann::json::parse(ReadBytes(quantized_dir + "/report.json"));
  EXPECT_LE(auto_report["quantization_error_bound_percent"].get<double>(),
            0.5 * auto_report["final"]["rmse_percent"].get<double>());
  EXPECT_GE(auto_report["quantization_bits"].get<int>(), 8);
  // Bits outside 8..30 are a usage error.
  for (const char* bits : {"7", "31", "x"}) {
    EXPECT_EQ(RunSdcb({"fit", MeshPath("blobby.off"), "-o",
                       exact_dir + "/z.sdcb", "--quantize", bits},
                      exact_dir)
                  .exit_code,
              2)
        << bits;
  }
}

TEST(FitCliTest, BadInputIsExitOneWithoutPartialOutput) {
  const std::string dir = FreshTestDir();
  // Genus 3.
  RunResult r =
      RunSdcb({"fit", MeshPath("elephant.off"), "-o", dir + "/e.sdcb"}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("genus 3"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/e.sdcb"));
  // Unwritable output.
  r = RunSdcb({"fit", MeshPath("blobby.off"), "-o", dir + "/missing/x.sdcb",
               "--max-rounds", "1", "--quiet"},
              dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("x.sdcb"), std::string::npos) << r.err;
  // Corrupt and truncated models to info / eval / dump.
  const std::string model = FitBlobby(dir, "1");
  const std::string bytes = ReadBytes(model);
  std::string corrupt = bytes;
  corrupt[corrupt.size() / 2] ^= 0x5a;
  WriteBytes(dir + "/corrupt.sdcb", corrupt);
  WriteBytes(dir + "/truncated.sdcb", bytes.substr(0, bytes.size() / 3));
  WriteBytes(dir + "/points.txt", "0 0 1\n1 0 0\n");
  for (const char* name : {"corrupt.sdcb", "truncated.sdcb"}) {
    SCOPED_TRACE(name);
    const std::string path = dir + "/" + name;
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"info", path},
             {"eval", path, "-i", dir + "/points.txt", "-o", dir + "/v.txt"},
             {"dump", path, "-o", dir + "/d.json"}}) {
      r = RunSdcb(args, dir);
      EXPECT_EQ(r.exit_code, 1) << args[0];
      EXPECT_FALSE(r.crashed);
      EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir + "/v.txt"));
    EXPECT_FALSE(fs::exists(dir + "/d.json"));
  }
  // Bad points file.
  WriteBytes(dir + "/bad_points.txt", "0 0 1\n0 0 0\n");
  r = RunSdcb(
      {"eval", model, "-i", dir + "/bad_points.txt", "-o", dir + "/v.txt"},
      dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("line 2"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/v.txt"));
  // Usage.
  EXPECT_EQ(RunSdcb({"fit", MeshPath("blobby.off")}, dir).exit_code, 2);
  EXPECT_EQ(RunSdcb({"fit", MeshPath("blobby.off"), "-o", dir + "/y.sdcb",
                     "--degree", "9"},
                    dir)
                .exit_code,
            2);
}

}  // namespace
}  // namespace sdcb
