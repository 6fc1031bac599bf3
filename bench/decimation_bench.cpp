// The spline against what a user would ship instead: the input mesh itself
// or decimated by CGAL's Garland-Heckbert (plane quadrics) edge collapse
// (bench/garland_heckbert.h), Draco- or meshopt-encoded, each measured
// against the INPUT mesh. One mode per question:
//
//   decimation_bench count MESH MODEL.sdcb [SAMPLES]
//     Equal count (docs/FITTING.md, "Against the decimated mesh a user would
//     keep"): MESH decimated to as many vertices as the spline has control
//     points; both objects' dense two-sided distance to MESH, measured the
//     same way (SAMPLES, default 200,000, area-weighted samples of each
//     surface, the input's triangles included; rms the root of the mean of
//     the two mean squares, max the Hausdorff distance). One line.
//   decimation_bench glb MESH MODEL.sdcb TOLERANCE_PCT [OUT_DIR]
//     Equal distance, GLB bytes (docs/EXPORT.md, "Bytes at equal measured
//     error"): the spline's adaptive tessellation at TOLERANCE_PCT (x 0.9,
//     as `sdcb export --draco`) against MESH decimated (bisection on the
//     faces) to the fewest faces within the tessellation's distance to MESH;
//     both written as Draco and meshopt GLBs (OUT_DIR, default
//     out/decimation_bench). Distance here: the max over MESH's vertices of
//     the distance to the candidate, and over the candidate's vertices and
//     face centroids of the distance to MESH. A Markdown table.
//   decimation_bench sdcb MESH MODEL.sdcb [BITS|auto[:FRACTION]] ...
//     Bytes at equal error, the .sdcb side (docs/FORMAT.md, "Bytes at equal
//     error"): the model written without sphere parameters, lossless (0) or
//     quantized (default "0 16"), read back and measured as `sdcb compare`
//     measures (core/measure/surface_deviation.h, 200,000 samples each way);
//     the file's bytes, its chunks' bytes and the stated bound.
//   decimation_bench mesh MESH CANDIDATE ...
//     Any triangle mesh (a decoded gltfpack file) against MESH, 200,000
//     area-weighted samples on each.
//   decimation_bench draco MESH TARGET_RMS_PCT [QP ...]
//     Draco (edgebreaker, speed 0 = level 10) of MESH decimated: for each
//     position quantization QP (default 8..14, 16) the fewest faces whose
//     DECODED mesh is within TARGET_RMS_PCT rms of MESH (bisection on the
//     faces), then the smallest file of all QP.
//   decimation_bench draco-input MESH [QUANTIZATION_BITS]
//     MESH itself, undecimated, by Draco (docs/FORMAT.md, "Sizes"):
//     positions at QUANTIZATION_BITS (default 14), edgebreaker, at
//     draco_encoder's default level 7 (speed 3) and its best, 10 (speed 0).
//     One line "draco MESH: V vertices, F faces, qp Q: cl7 N bytes, cl10 N
//     bytes".
//
// Distances in percent of MESH's largest bounding-box side. Modes sdcb, mesh
// and draco print one line per candidate, "KIND ... bytes N rms_percent R
// max_percent M" (bench/decimation_tables.sh reads them).
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/garland_heckbert.h"
#include "sdcb/converters/gltf/gltf_export.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"

namespace {

constexpr int kSamples = 200000;

template <typename T>
T OrDie(sdcb::StatusOr<T> s) {
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.status().message().c_str());
    std::exit(1);
  }
  return std::move(s).value();
}

double LargestSide(const sdcb::TriangleMesh& m) {
  return (m.vertices.colwise().maxCoeff() - m.vertices.colwise().minCoeff())
      .maxCoeff();
}

// The deviation options that measure a spline against `input` as `sdcb
// compare` does, `samples` each way, in percent of the input's largest side.
sdcb::DeviationOptions CompareOptions(const sdcb::TriangleMesh& input,
                                      const sdcb::SplineModel& model,
                                      int samples) {
  sdcb::DeviationOptions options;
  options.length_unit = LargestSide(input) / model.transform.scale;
  options.min_surface_samples = samples;
  options.mesh_samples = samples;  // the input's triangles too
  return options;
}

// --- Draco ------------------------------------------------------------------

// The mesh as a Draco mesh, point i = vertex i (no merging of vertices that
// share a position: the same mesh the fit reads).
std::unique_ptr<draco::Mesh> ToDraco(const sdcb::TriangleMesh& m) {
  auto mesh = std::make_unique<draco::Mesh>();
  const auto n = static_cast<uint32_t>(m.vertices.rows());
  mesh->set_num_points(n);
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3,
                draco::DT_FLOAT32, false, 3 * sizeof(float), 0);
  const int id = mesh->AddAttribute(position, /*identity_mapping=*/true, n);
  for (uint32_t v = 0; v < n; ++v) {
    const float xyz[3] = {static_cast<float>(m.vertices(v, 0)),
                          static_cast<float>(m.vertices(v, 1)),
                          static_cast<float>(m.vertices(v, 2))};
    mesh->attribute(id)->SetAttributeValue(draco::AttributeValueIndex(v), xyz);
  }
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    mesh->AddFace({draco::PointIndex(m.faces(f, 0)),
                   draco::PointIndex(m.faces(f, 1)),
                   draco::PointIndex(m.faces(f, 2))});
  }
  return mesh;
}

// `mesh` encoded with positions at `bits` and Draco's encoding and decoding
// speed `speed` (0 = level 10, 3 = level 7); exits on an encoder error.
std::unique_ptr<draco::EncoderBuffer> EncodeDraco(const draco::Mesh& mesh,
                                                  int bits, int speed) {
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, bits);
  encoder.SetSpeedOptions(speed, speed);
  auto buffer = std::make_unique<draco::EncoderBuffer>();
  const draco::Status s = encoder.EncodeMeshToBuffer(mesh, buffer.get());
  if (!s.ok()) {
    std::fprintf(stderr, "draco: %s\n", s.error_msg());
    std::exit(1);
  }
  return buffer;
}

// Encodes `m` at `qp` bits (level 10) and decodes it: the bytes and the
// mesh a reader gets.
sdcb::TriangleMesh DracoRoundTrip(const sdcb::TriangleMesh& m, int qp,
                                  size_t* bytes) {
  const auto buffer = EncodeDraco(*ToDraco(m), qp, 0);
  *bytes = buffer->size();
  draco::DecoderBuffer in;
  in.Init(buffer->data(), buffer->size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  if (!decoded.ok()) std::exit(1);
  const draco::Mesh& d = *decoded.value();
  const draco::PointAttribute* p =
      d.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  sdcb::TriangleMesh out;
  out.vertices.resize(d.num_points(), 3);
  for (uint32_t i = 0; i < d.num_points(); ++i) {
    float xyz[3];
    p->GetMappedValue(draco::PointIndex(i), xyz);
    out.vertices.row(i) << xyz[0], xyz[1], xyz[2];
  }
  out.faces.resize(d.num_faces(), 3);
  for (uint32_t f = 0; f < d.num_faces(); ++f) {
    const auto& face = d.face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k)
      out.faces(f, k) = static_cast<int>(face[k].value());
  }
  return out;
}

// --- count ------------------------------------------------------------------

int RunCount(const sdcb::TriangleMesh& input, int argc, char** argv) {
  const sdcb::SplineModel model = OrDie(sdcb::ReadSdcbFile(argv[3]));
  const int samples = argc > 4 ? std::atoi(argv[4]) : kSamples;
  const double side = LargestSide(input);
  const int target = static_cast<int>(model.control_points.rows());
  const auto start = std::chrono::steady_clock::now();
  // A closed genus-0 mesh with V vertices has 3V - 6 edges.
  const sdcb::TriangleMesh decimated =
      sdcb_bench::DecimateToEdges(input, std::max(6, 3 * target - 6));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  const sdcb::MeshDistance to_input = OrDie(sdcb::MeshDistance::Create(input));
  const sdcb::MeshDistance to_decimated =
      OrDie(sdcb::MeshDistance::Create(decimated));
  const sdcb_bench::TwoSidedDistance two_sided = sdcb_bench::MeasureTwoSided(
      decimated, to_decimated, input, to_input, samples);

  // The spline, measured by the library against the same input.
  const sdcb::SphericalSpline surface = OrDie(sdcb::SurfaceFromModel(model));
  sdcb::TriangleMesh normalized = input;
  normalized.vertices = model.transform.ToNormalized(input.vertices);
  const sdcb::SurfaceDeviation d = OrDie(sdcb::MeasureSurfaceDeviation(
      surface, normalized, CompareOptions(input, model, samples)));
  std::printf(
      "%s: spline %d control points: rms %.4f%% Hausdorff %.3f%% | "
      "Garland-Heckbert %d vertices (%d faces, %.2f s): rms %.4f%% Hausdorff "
      "%.3f%%\n",
      argv[2], target, d.rms_percent, d.hausdorff_percent,
      decimated.num_vertices(), decimated.num_faces(), seconds,
      100 * two_sided.rms / side, 100 * two_sided.max / side);
  return 0;
}

// --- glb --------------------------------------------------------------------

// Two-sided distance between `a` and the input, from vertices and face
// centroids (the glb mode's measure, see the header comment).
double VertexDistance(const sdcb::TriangleMesh& a,
                      const sdcb::TriangleMesh& input,
                      const sdcb::MeshDistance& to_input) {
  const sdcb::MeshDistance to_a = OrDie(sdcb::MeshDistance::Create(a));
  double d = to_a.Distances(input.vertices).maxCoeff();
  Eigen::MatrixX3d probes(a.vertices.rows() + a.faces.rows(), 3);
  probes.topRows(a.vertices.rows()) = a.vertices;
  for (Eigen::Index f = 0; f < a.faces.rows(); ++f) {
    probes.row(a.vertices.rows() + f) =
        (a.vertices.row(a.faces(f, 0)) + a.vertices.row(a.faces(f, 1)) +
         a.vertices.row(a.faces(f, 2))) /
        3.0;
  }
  return std::max(d, to_input.Distances(probes).maxCoeff());
}

// `m` with area-weighted vertex normals, for the GLB writer.
sdcb::SurfaceMesh WithNormals(const sdcb::TriangleMesh& m) {
  sdcb::SurfaceMesh s;
  s.positions = m.vertices;
  s.faces = m.faces;
  s.normals = Eigen::MatrixX3d::Zero(m.vertices.rows(), 3);
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    const Eigen::Vector3d a = m.vertices.row(m.faces(f, 0)),
                          b = m.vertices.row(m.faces(f, 1)),
                          c = m.vertices.row(m.faces(f, 2));
    for (int k = 0; k < 3; ++k)
      s.normals.row(m.faces(f, k)) += (b - a).cross(c - a).transpose();
  }
  for (Eigen::Index v = 0; v < s.normals.rows(); ++v) {
    const double n = s.normals.row(v).norm();
    s.normals.row(v) = n > 0 ? Eigen::RowVector3d(s.normals.row(v) / n)
                             : Eigen::RowVector3d(0, 0, 1);
  }
  return s;
}

int RunGlb(const sdcb::TriangleMesh& input, int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "glb needs TOLERANCE_PCT\n");
    return 2;
  }
  const sdcb::SplineModel model = OrDie(sdcb::ReadSdcbFile(argv[3]));
  const std::string out_dir = argc > 5 ? argv[5] : "out/decimation_bench";
  std::filesystem::create_directories(out_dir);
  const sdcb::SphericalSpline spline = OrDie(sdcb::SurfaceFromModel(model));
  const sdcb::PiecewiseSurface pieces(spline);
  const sdcb::PiecewiseSplineSampler sampler(spline, pieces);
  const double scale = model.transform.scale;
  const double tolerance = std::atof(argv[4]) / 100.0;
  sdcb::TessellationOptions options;
  options.tolerance = 0.9 * tolerance;  // as `sdcb export --draco`
  const auto t = OrDie(sdcb::TessellateAdaptively(sampler, options));
  sdcb::TriangleMesh tess;
  tess.vertices = model.transform.ToInput(t.positions);
  tess.faces = t.faces;
  const sdcb::MeshDistance to_input = OrDie(sdcb::MeshDistance::Create(input));
  const double target = VertexDistance(tess, input, to_input);
  // The decimation with the fewest faces within the same distance.
  int lo = 4, hi = static_cast<int>(input.faces.rows());
  sdcb::TriangleMesh best = input;
  for (int it = 0; it < 14 && hi - lo > std::max(8, hi / 200); ++it) {
    const int mid = (lo + hi) / 2;
    // Closed triangle meshes: E = 3F / 2.
    sdcb::TriangleMesh d = sdcb_bench::DecimateToEdges(
        input, 3 * static_cast<std::size_t>(mid) / 2);
    if (VertexDistance(d, input, to_input) <= target) {
      hi = mid;
      best = std::move(d);
    } else {
      lo = mid;
    }
  }
  const double best_distance = VertexDistance(best, input, to_input);
  const int bits =
      sdcb::PositionBitsFor(tess.vertices, 0.1 * tolerance * scale, 16);
  std::printf("input %s: %lld faces; tolerance %.4g%%; quantization %d bits\n",
              argv[2], static_cast<long long>(input.faces.rows()),
              100 * tolerance, bits);
  std::printf(
      "| mesh | triangles | distance to input %% | Draco GLB bytes | meshopt "
      "GLB bytes |\n|---|---|---|---|---|\n");
  for (int which = 0; which < 2; ++which) {
    const sdcb::TriangleMesh& m = which == 0 ? tess : best;
    sdcb::SurfaceMesh s = WithNormals(m);
    if (which == 0) {
      s.normals = t.normals;
      for (Eigen::Index v = 0; v < s.normals.rows(); ++v) {
        if (std::abs(s.normals.row(v).norm() - 1) > 1e-6)
          s.normals.row(v) << 0, 0, 1;
      }
    }
    int64_t bytes[2];
    for (int c = 0; c < 2; ++c) {
      sdcb::GltfExportOptions o;
      o.compression = c == 0 ? sdcb::GltfCompression::kDraco
                             : sdcb::GltfCompression::kMeshopt;
      o.position_bits = bits;
      auto r = sdcb::WriteGltf(s, o,
                               out_dir + "/" +
                                   (which ? "decimated" : "tessellation") +
                                   (c ? ".meshopt.glb" : ".draco.glb"));
      bytes[c] = r.ok() ? r->bytes : -1;
    }
    std::printf("| %s | %lld | %.4f | %lld | %lld |\n",
                which == 0 ? "spline tessellation"
                           : "input decimated (Garland-Heckbert)",
                static_cast<long long>(m.faces.rows()),
                100 * (which == 0 ? target : best_distance) / scale,
                static_cast<long long>(bytes[0]),
                static_cast<long long>(bytes[1]));
  }
  return 0;
}

// --- sdcb -------------------------------------------------------------------

// "TYPE:bytes ..." of the chunks of a version >= 2 file (payload bytes).
std::string ChunkBytes(const std::string& file) {
  std::string out;
  size_t at = 12;
  while (at + 16 <= file.size()) {
    uint64_t length = 0;
    for (int i = 0; i < 8; ++i) {
      length |= uint64_t{static_cast<uint8_t>(file[at + 4 + i])} << (8 * i);
    }
    out += file.substr(at, 4) + ":" + std::to_string(length) + " ";
    at += 16 + length;
  }
  return out;
}

int RunSdcb(const sdcb::TriangleMesh& input, int argc, char** argv) {
  const sdcb::SplineModel model = OrDie(sdcb::ReadSdcbFile(argv[3]));
  sdcb::TriangleMesh normalized = input;
  normalized.vertices = model.transform.ToNormalized(input.vertices);
  const sdcb::DeviationOptions options = CompareOptions(input, model, kSamples);
  std::vector<std::string> settings;
  for (int i = 4; i < argc; ++i) settings.push_back(argv[i]);
  if (settings.empty()) settings = {"0", "16"};
  for (const std::string& setting : settings) {
    sdcb::SdcbWriteOptions write;
    write.store_parameters = false;
    if (setting.rfind("auto", 0) == 0) {
      write.quantize_bits = sdcb::kQuantizeBitsAuto;
      if (setting.size() > 5) {
        write.quantize_fraction_of_rms = std::atof(setting.c_str() + 5);
      }
    } else {
      write.quantize_bits = std::atoi(setting.c_str());
    }
    sdcb::SdcbFileInfo info;
    const std::string file = OrDie(sdcb::SerializeSdcb(model, write, &info));
    const sdcb::SplineModel read = OrDie(sdcb::ParseSdcb(file));
    const sdcb::SphericalSpline surface = OrDie(sdcb::SurfaceFromModel(read));
    const sdcb::SurfaceDeviation d =
        OrDie(sdcb::MeasureSurfaceDeviation(surface, normalized, options));
    std::printf(
        "sdcb %s bits %d control_points %lld bytes %zu bound_percent %.6f "
        "rms_percent %.5f max_percent %.4f chunks %s\n",
        setting.c_str(), info.quantization.bits,
        static_cast<long long>(model.control_points.rows()), file.size(),
        info.quantization.surface_error_bound_percent(), d.rms_percent,
        d.hausdorff_percent, ChunkBytes(file).c_str());
  }
  return 0;
}

// --- mesh -------------------------------------------------------------------

int RunMesh(const sdcb::TriangleMesh& input, int argc, char** argv) {
  const double side = LargestSide(input);
  const sdcb::MeshDistance to_input = OrDie(sdcb::MeshDistance::Create(input));
  for (int i = 3; i < argc; ++i) {
    const sdcb::TriangleMesh m = OrDie(sdcb::ReadMesh(argv[i]));
    const sdcb::MeshDistance to_m = OrDie(sdcb::MeshDistance::Create(m));
    const sdcb_bench::TwoSidedDistance d =
        sdcb_bench::MeasureTwoSided(m, to_m, input, to_input, kSamples);
    std::printf("mesh %s triangles %lld rms_percent %.5f max_percent %.4f\n",
                argv[i], static_cast<long long>(m.faces.rows()),
                100 * d.rms / side, 100 * d.max / side);
  }
  return 0;
}

// --- draco ------------------------------------------------------------------

int RunDraco(const sdcb::TriangleMesh& input, int argc, char** argv) {
  const double side = LargestSide(input);
  const double target = std::atof(argv[3]) / 100 * side;
  std::vector<int> qps;
  for (int i = 4; i < argc; ++i) qps.push_back(std::atoi(argv[i]));
  if (qps.empty()) qps = {8, 9, 10, 11, 12, 13, 14, 16};
  const sdcb::MeshDistance to_input = OrDie(sdcb::MeshDistance::Create(input));
  std::map<int, sdcb::TriangleMesh> decimated;  // by faces
  auto decimate = [&](int faces) -> const sdcb::TriangleMesh& {
    auto it = decimated.find(faces);
    if (it == decimated.end()) {
      it = decimated
               .emplace(faces, sdcb_bench::DecimateToEdges(
                                   input, 3 * static_cast<size_t>(faces) / 2))
               .first;
    }
    return it->second;
  };
  struct Candidate {
    int qp = 0, faces = 0;
    size_t bytes = 0;
    sdcb_bench::TwoSidedDistance d;
  };
  auto measure = [&](int faces, int qp) {
    Candidate c;
    c.qp = qp;
    c.faces = faces;
    const sdcb::TriangleMesh m = DracoRoundTrip(decimate(faces), qp, &c.bytes);
    const sdcb::MeshDistance to_m = OrDie(sdcb::MeshDistance::Create(m));
    c.d = sdcb_bench::MeasureTwoSided(m, to_m, input, to_input, kSamples);
    return c;
  };
  Candidate best;
  for (int qp : qps) {
    int lo = 4, hi = static_cast<int>(input.faces.rows());
    Candidate at_hi = measure(hi, qp);
    if (at_hi.d.rms > target) {
      std::printf("draco qp %d: the whole mesh misses the target (rms %.5f)\n",
                  qp, 100 * at_hi.d.rms / side);
      continue;
    }
    while (hi - lo > std::max(8, hi / 200)) {
      const int mid = lo + (hi - lo) / 2;
      Candidate c = measure(mid, qp);
      if (c.d.rms <= target) {
        hi = mid;
        at_hi = c;
      } else {
        lo = mid;
      }
    }
    std::printf(
        "draco qp %d faces %d bytes %zu rms_percent %.5f max_percent %.4f\n",
        qp, at_hi.faces, at_hi.bytes, 100 * at_hi.d.rms / side,
        100 * at_hi.d.max / side);
    if (best.bytes == 0 || at_hi.bytes < best.bytes) best = at_hi;
  }
  std::printf(
      "draco best qp %d faces %d bytes %zu rms_percent %.5f max_percent "
      "%.4f\n",
      best.qp, best.faces, best.bytes, 100 * best.d.rms / side,
      100 * best.d.max / side);
  return 0;
}

// --- draco-input ------------------------------------------------------------

int RunDracoInput(const sdcb::TriangleMesh& input, int argc, char** argv) {
  const int bits = argc > 3 ? std::atoi(argv[3]) : 14;
  const std::unique_ptr<draco::Mesh> d = ToDraco(input);
  std::printf(
      "draco %s: %d vertices, %d faces, qp %d: cl7 %zu bytes, cl10 %zu "
      "bytes\n",
      argv[2], input.num_vertices(), input.num_faces(), bits,
      EncodeDraco(*d, bits, 3)->size(), EncodeDraco(*d, bits, 0)->size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using Run = int (*)(const sdcb::TriangleMesh&, int, char**);
  const std::map<std::string, Run> modes = {
      {"count", RunCount}, {"glb", RunGlb},     {"sdcb", RunSdcb},
      {"mesh", RunMesh},   {"draco", RunDraco}, {"draco-input", RunDracoInput}};
  const std::string mode = argc > 1 ? argv[1] : "";
  const auto run = modes.find(mode);
  if (run == modes.end() || argc < (mode == "draco-input" ? 3 : 4)) {
    std::fprintf(
        stderr,
        "usage: decimation_bench count MESH MODEL.sdcb [SAMPLES]\n"
        "       decimation_bench glb MESH MODEL.sdcb TOLERANCE_PCT [OUT_DIR]\n"
        "       decimation_bench sdcb MESH MODEL.sdcb [BITS|auto[:F]] ...\n"
        "       decimation_bench mesh MESH CANDIDATE ...\n"
        "       decimation_bench draco MESH TARGET_RMS_PCT [QP ...]\n"
        "       decimation_bench draco-input MESH [QUANTIZATION_BITS]\n");
    return 2;
  }
  return run->second(OrDie(sdcb::ReadMesh(argv[2])), argc, argv);
}
