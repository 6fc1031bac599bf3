// sdcb export MODEL.sdcb -o OUT.{obj,ply,stl,gltf,glb} [--tolerance PCT]
//   [--angle DEG] [--uniform N] [--draco [--qp BITS] [--cl LEVEL]]
//   [--meshopt] [--colors none|error|curvature|gaussian] [--mesh MESH]
//   [--json FILE] [--quiet]
#include <Eigen/Dense>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>

#include "sdcb/converters/color_ramp.h"
#include "sdcb/converters/gltf_export.h"
#include "sdcb/converters/mesh_export.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"
#include "sdcb/core/tessellate/optimal_triangle_count.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace sdcb::cli {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Fraction of the tolerance given to position quantization when a
// compressed glTF is written; the tessellation gets the rest.
constexpr double kQuantizationShare = 0.1;

// Largest quantization error of 16-bit positions over the surface's
// bounding box (normalized frame): sqrt(3) / 2 steps of its largest side
// / (2^16 - 1). The box comes from 40,962 surface points, widened by 1 %
// (more than a sampled box can miss); a tessellation's vertices lie on the
// surface, so their box is no larger.
double SixteenBitQuantizationError(const SurfaceSampler& surface) {
  Eigen::MatrixX3d positions;
  surface.Sample(MakeIcosphere(6).vertices, &positions, nullptr);
  const double side =
      (positions.colwise().maxCoeff() - positions.colwise().minCoeff())
          .maxCoeff();
  return std::sqrt(3.0) / 2.0 * 1.01 * side / (std::pow(2.0, 16) - 1.0);
}

// Largest distances between the tessellation and the spline, measured
// independently of the tessellator's lattice certificate (normalized frame):
//   spline -> mesh: `per_face` random points of each face's domain triangle
//     (fixed seed), mapped by the spline, to the mesh (CGAL AABB tree);
//   mesh -> spline: the centroid of each flat face to the spline, by
//     Gauss-Newton foot-point iterations from the face's domain centroid
//     (finite-difference Jacobian); a local foot point, so an upper bound.
struct Measured {
  double spline_to_mesh = 0.0;
  double mesh_to_spline = 0.0;
};

Measured MeasureDistance(const SurfaceSampler& surface, const Tessellation& t,
                         int per_face) {
  Measured m;
  const Eigen::Index nf = t.faces.rows();
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::MatrixX3d directions(nf * per_face, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    for (int s = 0; s < per_face; ++s) {
      double a = uniform(rng), b = uniform(rng);
      if (a + b > 1.0) {
        a = 1.0 - a;
        b = 1.0 - b;
      }
      directions.row(f * per_face + s) =
          (a * t.directions.row(t.faces(f, 0)) +
           b * t.directions.row(t.faces(f, 1)) +
           (1.0 - a - b) * t.directions.row(t.faces(f, 2)))
              .normalized();
    }
  }
  Eigen::MatrixX3d points;
  surface.Sample(directions, &points, nullptr);
  TriangleMesh mesh;
  mesh.vertices = t.positions;
  mesh.faces = t.faces;
  // A tessellation without a usable triangle cannot be measured: infinite.
  const StatusOr<MeshDistance> distance = MeshDistance::Create(mesh);
  if (!distance.ok()) {
    m.spline_to_mesh = std::numeric_limits<double>::infinity();
  } else if (points.rows() > 0) {
    m.spline_to_mesh = distance->Distances(points).maxCoeff();
  }

  // Mesh -> spline: Gauss-Newton on |S(u) - x|^2 over the tangent plane.
  Eigen::MatrixX3d x(nf, 3), u(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    x.row(f) =
        (t.positions.row(t.faces(f, 0)) + t.positions.row(t.faces(f, 1)) +
         t.positions.row(t.faces(f, 2))) /
        3.0;
    u.row(f) =
        (t.directions.row(t.faces(f, 0)) + t.directions.row(t.faces(f, 1)) +
         t.directions.row(t.faces(f, 2)))
            .normalized();
  }
  const double h = 1e-6;
  Eigen::VectorXd best = Eigen::VectorXd::Constant(nf, 1e300);
  for (int iteration = 0; iteration < 4; ++iteration) {
    Eigen::MatrixX3d probe(3 * nf, 3), eu(nf, 3), ev(nf, 3);
    for (Eigen::Index f = 0; f < nf; ++f) {
      Eigen::Vector3d a, b;
      TangentFrame(u.row(f).transpose(), &a, &b);
      eu.row(f) = a;
      ev.row(f) = b;
      probe.row(3 * f) = u.row(f);
      probe.row(3 * f + 1) = (u.row(f).transpose() + h * a).normalized();
      probe.row(3 * f + 2) = (u.row(f).transpose() + h * b).normalized();
    }
    Eigen::MatrixX3d s;
    surface.Sample(probe, &s, nullptr);
    for (Eigen::Index f = 0; f < nf; ++f) {
      const Eigen::Vector3d s0 = s.row(3 * f).transpose();
      const Eigen::Vector3d r = x.row(f).transpose() - s0;
      best[f] = std::min(best[f], r.norm());
      Eigen::Matrix<double, 3, 2> j;
      j.col(0) = (s.row(3 * f + 1).transpose() - s0) / h;
      j.col(1) = (s.row(3 * f + 2).transpose() - s0) / h;
      const Eigen::Vector2d step =
          (j.transpose() * j).ldlt().solve(j.transpose() * r);
      if (!step.allFinite() || step.norm() > 0.5) continue;
      u.row(f) = (u.row(f).transpose() + step[0] * eu.row(f).transpose() +
                  step[1] * ev.row(f).transpose())
                     .normalized();
    }
  }
  {
    Eigen::MatrixX3d s;
    surface.Sample(u, &s, nullptr);
    for (Eigen::Index f = 0; f < nf; ++f) {
      best[f] = std::min(best[f], (x.row(f) - s.row(f)).norm());
    }
  }
  if (nf > 0) m.mesh_to_spline = best.maxCoeff();
  return m;
}

// Unit normals for every vertex: the analytic one, or where the surface is
// singular (zero normal) the area-weighted normal of the adjacent faces.
Eigen::MatrixX3d CompleteNormals(const Tessellation& t) {
  Eigen::MatrixX3d normals = t.normals;
  Eigen::MatrixX3d face_sum = Eigen::MatrixX3d::Zero(t.positions.rows(), 3);
  for (Eigen::Index f = 0; f < t.faces.rows(); ++f) {
    const Eigen::Vector3d a = t.positions.row(t.faces(f, 0)),
                          b = t.positions.row(t.faces(f, 1)),
                          c = t.positions.row(t.faces(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) face_sum.row(t.faces(f, k)) += n.transpose();
  }
  for (Eigen::Index v = 0; v < normals.rows(); ++v) {
    if (std::abs(normals.row(v).norm() - 1.0) < 1e-9) continue;
    const double len = face_sum.row(v).norm();
    normals.row(v) = len > 0 ? Eigen::RowVector3d(face_sum.row(v) / len)
                             : Eigen::RowVector3d(0, 0, 1);
  }
  return normals;
}

double Percentile(Eigen::VectorXd values, double q) {
  std::vector<double> v;
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) v.push_back(std::abs(values[i]));
  }
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)))];
}

}  // namespace

const CommandOptions& ExportOptionNames() {
  static const CommandOptions names = {
      {"output", "tolerance", "angle", "uniform", "qp", "cl", "colors", "mesh",
       "json", "measure-samples", "max-patches"},
      {"draco", "meshopt", "quiet", "no-optimize", "no-simplify",
       "no-relocate"}};
  return names;
}

bool IsExportExtension(const std::string& ext) {
  return ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".gltf" ||
         ext == ".glb";
}

int RunExport(const std::vector<std::string>& argv) {
  const Clock::time_point start = Clock::now();
  // OpenMesh's writers log to stderr ("[OBJWriter] : write file"); the
  // command line owns the process, so it silences them.
  omlog().disable();
  omout().disable();
  const Args args(argv, ExportOptionNames().values, ExportOptionNames().flags);
  args.RequirePositionals(1,
                          "MODEL (usage: sdcb export MODEL.sdcb "
                          "-o OUT.{obj,ply,stl,gltf,glb,step,stp,igs,iges})");
  const std::string model_path = args.positionals()[0];
  const std::string output = args.Get("output");
  if (output.empty()) {
    throw UsageError{"missing -o OUT.{obj,ply,stl,gltf,glb,step,stp,igs,iges}"};
  }
  const std::string ext = LowercaseExtension(output);
  if (IsCadExtension(ext)) return RunCadExport(args, ext);
  if (args.Has("max-patches")) {
    throw UsageError{
        "--max-patches goes with a .step, .stp, .igs or .iges "
        "output"};
  }
  const bool gltf = ext == ".gltf" || ext == ".glb";
  if (!IsExportExtension(ext)) {
    throw UsageError{"unknown output extension '" + ext + "' in " + output +
                     " (use .obj, .ply, .stl, .gltf, .glb, .step, .stp, .igs "
                     "or .iges)"};
  }
  const bool draco = args.Has("draco"), meshopt = args.Has("meshopt");
  if (draco && meshopt)
    throw UsageError{"--draco and --meshopt exclude each other"};
  if ((draco || meshopt) && !gltf) {
    throw UsageError{"--draco and --meshopt need a .gltf or .glb output"};
  }
  if ((args.Has("qp") || args.Has("cl")) && !draco && !meshopt) {
    throw UsageError{
        "--qp and --cl go with --draco (--qp also with --meshopt)"};
  }
  if (args.Has("cl") && !draco) throw UsageError{"--cl goes with --draco"};
  const std::string colors = args.Get("colors", "none");
  if (colors != "none" && colors != "error" && colors != "curvature" &&
      colors != "gaussian") {
    throw UsageError{"--colors must be none, error, curvature or gaussian"};
  }
  if (colors == "error" && !args.Has("mesh")) {
    throw UsageError{
        "--colors error needs --mesh MESH (the mesh to compare with)"};
  }
  if (colors != "none" && (ext == ".obj" || ext == ".stl")) {
    throw UsageError{"--colors needs a .ply, .gltf or .glb output"};
  }
  const double tolerance_percent = args.GetDouble("tolerance", 0.1, 1e-6, 50.0);
  const double angle = args.GetDouble("angle", 20.0, 1e-3, 180.0);
  const int uniform = args.GetInt("uniform", 0, 0, 3000000);
  const int qp = args.GetInt("qp", 0, 1, meshopt ? 16 : 30);
  const int cl = args.GetInt("cl", 7, 0, 10);
  const int per_face = args.GetInt("measure-samples", 4, 0, 1000);
  const bool quiet = args.Has("quiet") || args.Get("json") == "-";

  StatusOr<SplineModel> model = ReadSdcbFile(model_path);
  if (!model.ok()) return ReportError(model.status());
  StatusOr<SphericalSpline> spline = SurfaceFromModel(*model);
  if (!spline.ok()) return ReportError(spline.status().WithPrefix(model_path));
  StatusOr<TriangleMesh> reference = TriangleMesh();
  if (colors == "error") {
    reference = ReadMesh(args.Get("mesh"));
    if (!reference.ok()) return ReportError(reference.status());
  }
  // Positions and normals from the per-piece polynomials (fast; equal to
  // the spline's to rounding), curvature from the spline.
  const PiecewiseSurface pieces(*spline);
  const PiecewiseSplineSampler sampler(*spline, pieces);
  const NormalizingTransform& transform = model->transform;

  // Tolerances in the normalized frame (largest side 1): PCT / 100.
  const double tolerance = tolerance_percent / 100.0;
  const bool quantized = draco || meshopt;
  // The positions' quantization gets a share of the tolerance, the surface
  // the rest. meshopt's positions have at most 16 bits
  // (KHR_mesh_quantization): where those cannot stay within the share, the
  // quantization gets what 16 bits need and the surface less.
  double quantization_budget =
      quantized && !args.Has("qp") ? kQuantizationShare * tolerance : 0.0;
  if (meshopt && !args.Has("qp")) {
    const double floor = SixteenBitQuantizationError(sampler);
    if (floor > 0.5 * tolerance) {
      char message[200];
      std::snprintf(message, sizeof message,
                    "--meshopt cannot keep --tolerance %g %%: its 16-bit "
                    "positions alone are off by up to %.3g %% (use --draco, "
                    "or --qp 16 to accept that)",
                    tolerance_percent, 100.0 * floor);
      throw UsageError{message};
    }
    quantization_budget = std::max(quantization_budget, floor);
  }
  const double surface_tolerance = tolerance - quantization_budget;
  Clock::time_point t0 = Clock::now();
  Tessellation t;
  if (uniform > 0) {
    t = TessellateUniformly(sampler, UniformLevelForVertices(uniform));
  } else {
    TessellationOptions options;
    options.tolerance = surface_tolerance;
    options.angle_degrees = angle;
    StatusOr<Tessellation> adaptive = TessellateAdaptively(sampler, options);
    if (!adaptive.ok()) {
      return ReportError(adaptive.status().WithPrefix(model_path));
    }
    t = std::move(adaptive).value();
  }
  const double tessellate_seconds = Since(t0);

  t0 = Clock::now();
  const Measured measured = MeasureDistance(sampler, t, per_face);
  const double measure_seconds = Since(t0);
  t0 = Clock::now();
  StatusOr<CurvatureIntegrals> integrals =
      IntegrateCurvatureOverSurface(sampler);
  if (!integrals.ok()) return ReportError(integrals.status());
  const double optimum = OptimalTriangleCount(*integrals, surface_tolerance);
  const double optimum_seconds = Since(t0);

  SurfaceMesh mesh;
  mesh.positions = transform.ToInput(t.positions);
  mesh.normals = CompleteNormals(t);
  mesh.faces = t.faces;
  nlohmann::ordered_json color_report;
  color_report["mode"] = colors;
  if (colors == "curvature" || colors == "gaussian") {
    Eigen::VectorXd gaussian, mean;
    sampler.SampleCurvature(t.directions, &gaussian, &mean);
    // Input units: curvature 1/length scales by 1/scale, K by 1/scale^2.
    const double s = transform.scale;
    Eigen::VectorXd values = colors == "curvature"
                                 ? Eigen::VectorXd(mean / s)
                                 : Eigen::VectorXd(gaussian / (s * s));
    const double range = Percentile(values, 0.95);
    mesh.colors = ColorRamp(values, -range, range, /*diverging=*/true);
    color_report["quantity"] =
        colors == "curvature" ? "mean_curvature" : "gaussian_curvature";
    color_report["unit"] = colors == "curvature" ? "1/length" : "1/length^2";
    color_report["ramp"] = "blue (min) - white (0) - red (max)";
    color_report["min"] = -range;
    color_report["max"] = range;
    color_report["scale_rule"] = "symmetric, 95th percentile of |value|";
  } else if (colors == "error") {
    const StatusOr<MeshDistance> distance = MeshDistance::Create(*reference);
    if (!distance.ok()) {
      return ReportError(distance.status().WithPrefix(args.Get("mesh")));
    }
    const Eigen::VectorXd d = distance->Distances(mesh.positions);
    const double top = d.size() ? d.maxCoeff() : 0.0;
    mesh.colors = ColorRamp(d, 0.0, top, /*diverging=*/false);
    color_report["quantity"] = "distance_to_mesh";
    color_report["mesh"] = args.Get("mesh");
    color_report["unit"] = "percent of the largest bounding-box side";
    color_report["ramp"] = "white (min) - red (max)";
    color_report["min"] = 0.0;
    color_report["max"] = 100.0 * top / transform.scale;
  }

  t0 = Clock::now();
  int64_t bytes = 0;
  GltfExportResult gltf_result;
  int bits = 0;
  if (gltf) {
    GltfExportOptions options;
    options.compression = draco     ? GltfCompression::kDraco
                          : meshopt ? GltfCompression::kMeshopt
                                    : GltfCompression::kNone;
    bits = qp;
    if (quantized && bits == 0) {
      bits =
          PositionBitsFor(mesh.positions, quantization_budget * transform.scale,
                          meshopt ? 16 : 30);
    }
    options.position_bits = std::max(bits, 1);
    options.draco_level = cl;
    StatusOr<GltfExportResult> r = WriteGltf(mesh, options, output);
    if (!r.ok()) return ReportError(r.status());
    gltf_result = *r;
    bytes = r->bytes;
  } else {
    const Status s = WriteSurfaceMesh(mesh, output);
    if (!s.ok()) return ReportError(s);
    std::error_code ec;
    bytes = static_cast<int64_t>(std::filesystem::file_size(output, ec));
  }
  const double write_seconds = Since(t0);

  const double to_percent = 100.0;
  const double measured_max =
      std::max(measured.spline_to_mesh, measured.mesh_to_spline);
  const double quantization_percent =
      100.0 * gltf_result.quantization_error / transform.scale;
  nlohmann::ordered_json j;
  j["file"] = model_path;
  j["output"] = output;
  j["format"] = ext.substr(1);
  j["compression"] = draco ? "draco" : meshopt ? "meshopt" : "none";
  j["mode"] = uniform > 0 ? "uniform" : "adaptive";
  j["triangles"] = t.faces.rows();
  j["vertices"] = t.positions.rows();
  j["bytes"] = bytes;
  j["tolerance_percent"] = tolerance_percent;
  j["surface_tolerance_percent"] = to_percent * surface_tolerance;
  j["angle_degrees"] = angle;
  j["certified_distance_percent"] = to_percent * t.certified_distance;
  j["max_normal_angle_degrees"] = t.max_normal_angle_degrees;
  j["uncertified_triangles"] = t.uncertified_faces;
  j["max_distance_percent"] = to_percent * measured_max;
  j["spline_to_mesh_percent"] = to_percent * measured.spline_to_mesh;
  j["mesh_to_spline_percent"] = to_percent * measured.mesh_to_spline;
  j["total_error_bound_percent"] =
      to_percent * measured_max + quantization_percent;
  j["optimal_triangles"] = optimum;
  j["triangles_vs_optimum"] = optimum > 0 ? t.faces.rows() / optimum : 0.0;
  j["curvature_integrals"] = {{"convex_sqrt_k", integrals->convex},
                              {"saddle_sqrt_abs_k", integrals->saddle},
                              {"area", integrals->area}};
  j["quantization"] = {{"bits", quantized ? bits : 0},
                       {"step", gltf_result.quantization_step},
                       {"error_percent", quantization_percent},
                       {"float32_error_percent",
                        100.0 * gltf_result.float32_error / transform.scale}};
  j["colors"] = color_report;
  j["evaluations"] = t.evaluations;
  j["seconds"] = {{"tessellate", tessellate_seconds},
                  {"measure", measure_seconds},
                  {"optimum", optimum_seconds},
                  {"write", write_seconds},
                  {"total", Since(start)}};
  if (args.Has("json")) {
    const Status s = WriteTextOutput(args.Get("json"), j.dump(2) + "\n");
    if (!s.ok()) return ReportError(s);
  }
  if (!quiet) {
    std::printf(
        "%s -> %s: %lld triangles, %lld vertices, %lld bytes\n"
        "  tolerance %.4g%%  measured max distance %.4g%%  %.2f x optimum  "
        "%.2f s\n",
        model_path.c_str(), output.c_str(),
        static_cast<long long>(t.faces.rows()),
        static_cast<long long>(t.positions.rows()),
        static_cast<long long>(bytes), tolerance_percent,
        to_percent * measured_max, optimum > 0 ? t.faces.rows() / optimum : 0.0,
        Since(start));
  }
  return kExitOk;
}

}  // namespace sdcb::cli
