// Bytes at equal error (bench/bytes_at_equal_error.sh drives it): the size
// of a stored surface next to its dense two-sided distance from the INPUT
// mesh, for the three ways to ship a shape:
//   equal_error_bench sdcb MESH MODEL.sdcb [BITS|auto[:FRACTION]] ...
//     the model written as an .sdcb (no sphere parameters), lossless (0) or
//     quantized (SdcbWriteOptions), read back and measured as `sdcb compare`
//     measures (core/measure/surface_deviation.h) with 200,000 samples each
//     way; prints the file's bytes, its chunks' bytes and the stated bound.
//   equal_error_bench mesh MESH CANDIDATE ...
//     any triangle mesh (a decoded gltfpack file), measured against MESH
//     with 200,000 area-weighted samples on each (bench/garland_heckbert.h).
//   equal_error_bench draco MESH TARGET_RMS_PCT [QP ...]
//     Draco (edgebreaker, speed 0 = level 10) of MESH decimated by CGAL's
//     Garland-Heckbert edge collapse: for each position quantization QP
//     (default 8..14, 16) the fewest faces whose DECODED mesh is within
//     TARGET_RMS_PCT rms of MESH (bisection on the faces), then the
//     smallest file of all QP.
// Distances in percent of MESH's largest bounding-box side. One line per
// candidate: "KIND ... bytes N rms_percent R max_percent M".
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "bench/garland_heckbert.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"

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
  sdcb::DeviationOptions options;
  options.length_unit = LargestSide(input) / model.transform.scale;
  options.min_surface_samples = kSamples;
  options.mesh_samples = kSamples;
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

std::unique_ptr<draco::Mesh> ToDraco(const sdcb::TriangleMesh& m) {
  auto mesh = std::make_unique<draco::Mesh>();
  const auto n = static_cast<uint32_t>(m.vertices.rows());
  mesh->set_num_points(n);
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3,
                draco::DT_FLOAT32, false, 3 * sizeof(float), 0);
  const int id = mesh->AddAttribute(position, true, n);
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

// Encodes `m` at `qp` bits (level 10) and decodes it: the bytes and the
// mesh a reader gets.
sdcb::TriangleMesh DracoRoundTrip(const sdcb::TriangleMesh& m, int qp,
                                  size_t* bytes) {
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, qp);
  encoder.SetSpeedOptions(0, 0);
  draco::EncoderBuffer buffer;
  if (!encoder.EncodeMeshToBuffer(*ToDraco(m), &buffer).ok()) std::exit(1);
  *bytes = buffer.size();
  draco::DecoderBuffer in;
  in.Init(buffer.data(), buffer.size());
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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(
        stderr,
        "usage: equal_error_bench sdcb MESH MODEL.sdcb [BITS|auto] "
        "...\n       equal_error_bench mesh MESH CANDIDATE ...\n"
        "       equal_error_bench draco MESH TARGET_RMS_PCT [QP ...]\n");
    return 2;
  }
  const std::string kind = argv[1];
  const sdcb::TriangleMesh input = OrDie(sdcb::ReadMesh(argv[2]));
  if (kind == "sdcb") return RunSdcb(input, argc, argv);
  if (kind == "mesh") return RunMesh(input, argc, argv);
  if (kind == "draco") return RunDraco(input, argc, argv);
  std::fprintf(stderr, "unknown kind %s\n", kind.c_str());
  return 2;
}
