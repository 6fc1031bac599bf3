// sdcb param MESH -o SPHERE_MESH [--lambda L] [--json FILE]
//            [--colors angle|area] [--threads T] [--quiet]
// Spherical parameterization (paper Sec. 4.3): writes the mesh with every
// vertex moved to its point on S^2, same vertex order and faces.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/param/parameterization_distortion.h"
#include "sdcb/core/param/spherical_parameterization.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/mesh/mesh_writer.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {
namespace {

constexpr const char* kParamUsage =
    "usage: sdcb param MESH -o SPHERE_MESH [--lambda L] [--json FILE] "
    "[--colors angle|area] [--threads T] [--quiet]";

// Diverging color of a distortion value: 2 (none) is blue, 3 white, 4 or
// more red (linear in log2(value / 2) between).
Eigen::Matrix<std::uint8_t, 1, 3> DistortionColor(double value) {
  const double t = std::clamp(std::log2(std::max(value, 2.0) / 2.0), 0.0, 1.0);
  auto to_byte = [](double x) {
    return static_cast<std::uint8_t>(std::lround(255.0 * x));
  };
  if (t < 0.5) {
    const double s = t / 0.5;  // blue -> white
    return {to_byte(s), to_byte(s), 255};
  }
  const double s = (t - 0.5) / 0.5;  // white -> red
  return {255, to_byte(1.0 - s), to_byte(1.0 - s)};
}

// Per vertex: area-weighted mean of its faces' values, then colored.
VertexColors VertexDistortionColors(const TriangleMesh& mesh,
                                    const std::vector<double>& face_values,
                                    const std::vector<double>& face_areas) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(mesh.num_vertices());
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(mesh.num_vertices());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const double area = face_areas[f];
    const double value = std::isfinite(face_values[f]) ? face_values[f] : 1e30;
    for (int i = 0; i < 3; ++i) {
      sum[mesh.faces(f, i)] += area * value;
      weight[mesh.faces(f, i)] += area;
    }
  }
  VertexColors colors(mesh.num_vertices(), 3);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    colors.row(v) = DistortionColor(weight[v] > 0.0 ? sum[v] / weight[v] : 2.0);
  }
  return colors;
}

}  // namespace

int RunParam(const std::vector<std::string>& argv) {
  const Args args(
      argv, Concat({"lambda", "json", "colors", "threads"}, kMeshValueOptions),
      {"quiet"});
  args.RequirePositionals(1, std::string("MESH (") + kParamUsage + ")");
  if (!args.Has("output"))
    throw UsageError{std::string("missing -o SPHERE_MESH (") + kParamUsage +
                     ")"};
  const std::string& path = args.positionals()[0];
  const std::string output = args.Get("output");
  SphericalParameterizationOptions options;
  options.lambda = args.GetDouble("lambda", options.lambda, 0.0, 1000.0);
  if (!(options.lambda > 0.0)) throw UsageError{"--lambda must be > 0"};
  options.threads = args.GetInt("threads", 0, 0, 1024);
  const std::string colors = args.Get("colors", "");
  if (args.Has("colors")) {
    if (colors != "angle" && colors != "area") {
      throw UsageError{"--colors takes 'angle' or 'area', not '" + colors +
                       "'"};
    }
    const std::string ext =
        output.size() >= 4 ? output.substr(output.size() - 4) : "";
    if (ext != ".ply" && ext != ".PLY") {
      throw UsageError{"--colors needs a .ply output file"};
    }
  }
  const bool show_progress = !args.Has("quiet") && isatty(STDERR_FILENO);
  if (show_progress) {
    options.progress = [](const std::string& stage, double fraction) {
      std::fprintf(stderr, "\rsdcb param: %-10s %5.1f%%", stage.c_str(),
                   100.0 * fraction);
      std::fflush(stderr);
    };
  }

  const Status outputs = PrepareOutputs({output, args.Get("json")});
  if (!outputs.ok()) return ReportError(outputs);
  StatusOr<TriangleMesh> mesh = ReadFittableMesh(args, path);
  if (!mesh.ok()) return ReportError(mesh.status());
  SelfIntersectionsBeside intersections(*mesh);

  const auto start = std::chrono::steady_clock::now();
  StatusOr<SphericalParameterization> param =
      ParameterizeOnSphere(*mesh, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  if (show_progress) std::fprintf(stderr, "\n");
  intersections.Warn(path);
  if (!param.ok()) return ReportError(param.status().WithPrefix(path));
  StatusOr<ParameterizationDistortion> distortion =
      MeasureParameterizationDistortion(*mesh, param->sphere);
  if (!distortion.ok())
    return ReportError(distortion.status().WithPrefix(path));
  const ParameterizationDistortion& d = *distortion;

  MeshWriteOptions write_options;
  if (colors == "angle") {
    write_options.colors = VertexDistortionColors(
        *mesh, d.face_angle_distortion, d.face_mesh_area);
  } else if (colors == "area") {
    write_options.colors =
        VertexDistortionColors(*mesh, d.face_area_distortion, d.face_mesh_area);
  }
  const TriangleMesh sphere_mesh{param->sphere, mesh->faces};
  const Status written = WriteMesh(sphere_mesh, output, write_options);
  if (!written.ok()) return ReportError(written);

  if (args.Has("json")) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["output"] = output;
    j["vertices"] = mesh->num_vertices();
    j["faces"] = mesh->num_faces();
    j["lambda"] = options.lambda;
    j["flipped_triangles"] = d.flipped_triangles;
    j["angle_distortion_max"] = d.angle_distortion_max;
    j["angle_distortion_avg"] = d.angle_distortion_avg;
    j["area_distortion_max"] = d.area_distortion_max;
    j["area_distortion_avg"] = d.area_distortion_avg;
    j["energy"] = param->energy;
    j["levels"] = param->levels;
    j["base_vertices"] = param->base_vertices;
    j["seconds"] = seconds;
    const Status json_written =
        WriteTextOutput(args.Get("json"), j.dump(2) + "\n");
    if (!json_written.ok()) return ReportError(json_written);
  }
  if (!args.Has("quiet") && args.Get("json") != "-") {
    std::printf(
        "%s -> %s: %d flipped triangles, E_angle avg %.4f max %.4g, "
        "E_area avg %.4f max %.4g, %.2f s\n",
        path.c_str(), output.c_str(), d.flipped_triangles,
        d.angle_distortion_avg, d.angle_distortion_max, d.area_distortion_avg,
        d.area_distortion_max, seconds);
  }
  return kExitOk;
}

}  // namespace sdcb::cli
