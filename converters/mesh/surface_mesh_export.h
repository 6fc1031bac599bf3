// `sdcb export MODEL.sdcb -o OUT.{obj,ply,stl,gltf,glb}` as one library call
// (docs/EXPORT.md): the model's surface tessellated within a tolerance
// (core/tessellate/adaptive_tessellation.h) or uniformly, its distance to the
// surface measured independently of the tessellator
// (converters/mesh/tessellation_deviation.h), normals completed where the
// surface is singular, optional vertex colors, and the file's bytes (OBJ, PLY,
// STL through converters/mesh/mesh_export.h; glTF, Draco, meshopt through
// converters/gltf/gltf_export.h), with a report of every figure.
//
// The tolerance budget: with a quantized encoding (Draco, meshopt) and no
// fixed position_bits, the positions' quantization gets 10 % of the
// tolerance and the tessellation the rest; meshopt's positions have at most
// 16 bits, so where those need more than that share they get what 16 bits
// need and the surface less, and more than half of the tolerance is refused.
//
// Lengths in options and report are percent of the largest side of the
// input's bounding box (1 in the model's normalized frame); the mesh and the
// file are in the input's coordinates.
#ifndef SDCB_CONVERTERS_MESH_SURFACE_MESH_EXPORT_H_
#define SDCB_CONVERTERS_MESH_SURFACE_MESH_EXPORT_H_

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sdcb/converters/gltf/gltf_export.h"
#include "sdcb/converters/mesh/surface_mesh.h"
#include "sdcb/core/common/progress.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/core/spline/spline_model.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"
#include "sdcb/core/tessellate/optimal_triangle_count.h"

namespace sdcb {

enum class ExportFormat { kObj, kPly, kStl, kGltf, kGlb };

// The format of a file extension with its dot, any case (".glb"); false if
// it names none.
bool ExportFormatOfExtension(const std::string& extension,
                             ExportFormat* format);

enum class VertexColoring {
  kNone,
  kMeanCurvature,      // diverging ramp, 1/length
  kGaussianCurvature,  // diverging ramp, 1/length^2
  kDistanceToMesh,     // sequential ramp, to SurfaceMeshExportOptions::mesh
};

struct SurfaceMeshExportOptions {
  ExportFormat format = ExportFormat::kGlb;
  // Largest distance between the written mesh (quantization included) and
  // the surface, percent; > 0.
  double tolerance_percent = 0.1;
  // Largest angle between a face's normal and the surface normals over it,
  // degrees, in (0, 180]; 180 disables it.
  double angle_degrees = 20.0;
  // > 0: the uniform icosahedral tessellation of about this many vertices
  // (TessellateUniformly) instead of the adaptive one.
  int64_t uniform_vertices = 0;
  // glTF formats only.
  GltfCompression compression = GltfCompression::kNone;
  // Quantized positions' bits (Draco 1..30, meshopt 1..16); 0 derives them
  // from the tolerance (above).
  int position_bits = 0;
  int draco_level = 7;  // 0..10
  // PLY and glTF formats only.
  VertexColoring colors = VertexColoring::kNone;
  // kDistanceToMesh: the mesh to compare with, in the input's coordinates
  // (not owned; must outlive the call), and the name the report gives it.
  const TriangleMesh* mesh = nullptr;
  std::string mesh_name;
  // Random points per face of the independent surface -> mesh measurement.
  int measure_samples_per_face = 4;
  // The tessellator's other settings; its tolerance and angle_degrees are
  // set from the fields above.
  TessellationOptions tessellation;
  // Called with a stage name and the finished fraction of the whole export
  // in [0, 1], from the calling thread.
  ProgressCallback progress;
};

// Every figure of the export; lengths in percent (above).
struct SurfaceMeshExportReport {
  std::string format;       // "obj", "ply", "stl", "gltf", "glb"
  std::string compression;  // "none", "draco", "meshopt"
  std::string mode;         // "adaptive", "uniform"
  int64_t triangles = 0;
  int64_t vertices = 0;
  int64_t bytes = 0;
  double tolerance_percent = 0.0;
  double surface_tolerance_percent = 0.0;  // the tessellation's share
  double angle_degrees = 0.0;
  // The tessellator's certificate (core/tessellate/adaptive_tessellation.h).
  double certified_distance_percent = 0.0;
  double max_normal_angle_degrees = 0.0;
  int uncertified_triangles = 0;
  // Creases the tessellation followed: the feature arcs the spline's knots
  // hold (core/knots/feature_knots.h FeatureArcsOfKnots), 0 if none.
  int feature_arcs = 0;
  // The independent measurement (converters/mesh/tessellation_deviation.h): the
  // larger of the two directions, and each.
  double max_distance_percent = 0.0;
  double spline_to_mesh_percent = 0.0;
  double mesh_to_spline_percent = 0.0;
  // max_distance_percent plus the quantization error.
  double total_error_bound_percent = 0.0;
  // The asymptotic optimum at the surface tolerance
  // (core/tessellate/optimal_triangle_count.h) and triangles / it.
  double optimal_triangles = 0.0;
  double triangles_vs_optimum = 0.0;
  CurvatureIntegrals curvature_integrals;  // in the normalized frame
  struct Quantization {
    // 0: float32 positions. meshopt's exponential positions (a glTF asset,
    // GltfMeshoptPositions::kExponential): their mantissa bits.
    int bits = 0;
    // Input units; exponential positions: the largest 2^exponent.
    double step = 0.0;
    double error_percent = 0.0;
    double float32_error_percent = 0.0;
  } quantization;
  struct Colors {
    std::string mode = "none";  // none, curvature, gaussian, error
    std::string quantity, unit, ramp, scale_rule, mesh;
    double min = 0.0, max = 0.0;  // the ramp's ends, in `unit`
  } colors;
  // The model's parts and their trim loops (a model of several parts adds
  // counts, and takes the largest of every distance, each in percent of its
  // own part's largest side; the colors' ramp is the first part's).
  int parts = 1;
  int trim_loops = 0;
  // A glTF asset written back (Model::asset): materials of fitted
  // primitives written without their textures (EncodeGltfAsset).
  int textureless_materials = 0;
  // glTF asset: fitted primitives written with a baked texture atlas, and
  // their vertices whose atlas coordinates were clamped
  // (EncodedGltfAsset's).
  int atlas_primitives = 0;
  int atlas_vertices_beyond_extent = 0;
  int64_t evaluations = 0;  // surface points the tessellator sampled
  int64_t samples = 0;      // surface samples the tessellation certified on
  struct Seconds {
    // tessellate = samples + simplify + verify (adaptive; 0 for uniform).
    double tessellate = 0.0, samples = 0.0, simplify = 0.0, verify = 0.0,
           measure = 0.0, optimum = 0.0, write = 0.0, total = 0.0;
  } seconds;
};

struct SurfaceMeshExport {
  // What the file holds, input coordinates: every part's mesh, one after
  // the other (glTF keeps them apart, one mesh per part).
  SurfaceMesh mesh;
  std::string bytes;  // the file
  SurfaceMeshExportReport report;
  // Per part, its first row in mesh.positions and in mesh.faces.
  std::vector<Eigen::Index> part_vertices, part_faces;
};

// Exports `model`'s surface. kInvalidArgument for options that do not go
// together (compression without glTF, colors without PLY or glTF, distance
// colors without a mesh, bits out of range) or a tolerance meshopt cannot
// keep; kInvalidInput for a model whose surface cannot be built or
// tessellated within the tessellator's face limit, or whose fit measured a
// folded area (the adaptive tessellation only: a uniform one is made).
// Deterministic: the same model and options give the same bytes for any thread
// count.
StatusOr<SurfaceMeshExport> ExportSurfaceMesh(
    const SplineModel& model, const SurfaceMeshExportOptions& options);

// Exports every part of `model`, each tessellated in its own normalized
// frame (the tolerance is percent of the part's own largest side) and
// mapped to input coordinates by its transform; a trimmed part's kept
// region only (TessellationOptions::trims), its trims as the mesh's
// boundary. A model of one closed part writes exactly the bytes of the
// SplineModel overload. Several parts: OBJ has "o NAME" before each part's
// faces (ExportPartName), PLY and STL one mesh of all parts, glTF one node
// and one mesh per part named alike (EncodeGltfParts). Errors as above,
// naming the part ("part 2: ..."); a trimmed part is refused with
// --uniform (kInvalidInput).
StatusOr<SurfaceMeshExport> ExportSurfaceMesh(
    const Model& model, const SurfaceMeshExportOptions& options);

// The name of part `part` (counted from 0) in the files: its own, or
// "part1", "part2", ... when it has none.
std::string ExportPartName(const Model& model, size_t part);

// ExportSurfaceMesh in the format of `path`'s extension (options.format is
// ignored), written to `path` atomically; the report's seconds.write and
// total include the write. Messages start with `path` where it is to blame.
StatusOr<SurfaceMeshExportReport> WriteSurfaceMeshExport(
    const SplineModel& model, const SurfaceMeshExportOptions& options,
    const std::string& path);
StatusOr<SurfaceMeshExportReport> WriteSurfaceMeshExport(
    const Model& model, const SurfaceMeshExportOptions& options,
    const std::string& path);

// The report as the JSON object of `sdcb export --json` (docs/CLI.md), keys
// in the order listed there, without the command line's "file" and
// "output"; "parts" and "trim_loops" only for a model of several parts or
// with trims.
nlohmann::ordered_json SurfaceMeshExportReportToJson(
    const SurfaceMeshExportReport& report);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_MESH_SURFACE_MESH_EXPORT_H_
