// Bytes at equal measured error: the Draco and meshopt GLBs of an adaptive
// tessellation of a fitted spline against the same encoders on the input
// mesh decimated with CGAL's Garland-Heckbert (plane quadrics) edge collapse
// to the same two-sided distance from the input mesh.
//   decimation_bytes_bench MESH MODEL.sdcb TOLERANCE_PCT [OUT_DIR]
// Distances (percent of the largest side): max over the input's vertices of
// the distance to the candidate mesh, and over the candidate's vertices and
// face centroids of the distance to the input (CGAL AABB trees).
#include <cstdio>
#include <filesystem>

#include "bench/garland_heckbert.h"
#include "sdcb/converters/gltf_export.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/tessellate/adaptive_tessellation.h"
#include "sdcb/io/mesh_reader.h"
#include "sdcb/io/sdcb_file.h"

namespace {

// Two-sided distance between `a` and the input (see the header comment).
double Distance(const sdcb::TriangleMesh& a, const sdcb::TriangleMesh& input,
                const sdcb::MeshDistance& to_input) {
  const sdcb::MeshDistance to_a = sdcb::MeshDistance::Create(a).value();
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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: decimation_bytes_bench MESH MODEL.sdcb TOLERANCE_PCT "
                 "[OUT_DIR]\n");
    return 2;
  }
  const std::string out_dir = argc > 4 ? argv[4] : "out/decimation_bench";
  std::filesystem::create_directories(out_dir);
  auto input = sdcb::ReadMesh(argv[1]);
  auto model = sdcb::ReadSdcbFile(argv[2]);
  if (!input.ok() || !model.ok()) {
    std::fprintf(stderr, "cannot read the inputs\n");
    return 1;
  }
  auto spline = sdcb::SurfaceFromModel(*model);
  const sdcb::PiecewiseSurface pieces(*spline);
  const sdcb::PiecewiseSplineSampler sampler(*spline, pieces);
  const double scale = model->transform.scale;
  const double tolerance = std::atof(argv[3]) / 100.0;
  sdcb::TessellationOptions options;
  options.tolerance = 0.9 * tolerance;  // as `sdcb export --draco`
  auto t = sdcb::TessellateAdaptively(sampler, options);
  if (!t.ok()) return 1;
  sdcb::TriangleMesh tess;
  tess.vertices = model->transform.ToInput(t->positions);
  tess.faces = t->faces;
  const sdcb::MeshDistance to_input =
      sdcb::MeshDistance::Create(*input).value();
  const double target = Distance(tess, *input, to_input);
  // The decimation with the fewest faces within the same distance.
  int lo = 4, hi = static_cast<int>(input->faces.rows());
  sdcb::TriangleMesh best = *input;
  for (int it = 0; it < 14 && hi - lo > std::max(8, hi / 200); ++it) {
    const int mid = (lo + hi) / 2;
    // Closed triangle meshes: E = 3F / 2.
    sdcb::TriangleMesh d = sdcb_bench::DecimateToEdges(
        *input, 3 * static_cast<std::size_t>(mid) / 2);
    if (Distance(d, *input, to_input) <= target) {
      hi = mid;
      best = std::move(d);
    } else {
      lo = mid;
    }
  }
  const double best_distance = Distance(best, *input, to_input);
  const int bits =
      sdcb::PositionBitsFor(tess.vertices, 0.1 * tolerance * scale, 16);
  std::printf("input %s: %lld faces; tolerance %.4g%%; quantization %d bits\n",
              argv[1], static_cast<long long>(input->faces.rows()),
              100 * tolerance, bits);
  std::printf(
      "| mesh | triangles | distance to input %% | Draco GLB bytes | meshopt "
      "GLB bytes |\n|---|---|---|---|---|\n");
  for (int which = 0; which < 2; ++which) {
    const sdcb::TriangleMesh& m = which == 0 ? tess : best;
    sdcb::SurfaceMesh s = WithNormals(m);
    if (which == 0) {
      s.normals = t->normals;
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
