// The colours and shape of a glTF asset written back by `sdcb export`
// against its input, per primitive (matched by mesh and primitive index; a
// primitive the export split, its kept triangles in place and its fitted
// parts in a primitive appended to the mesh, is measured as its pieces
// together, each appended primitive the piece of the input primitive of its
// mesh nearest its vertices): points sampled on the output's triangles
// (area-weighted, fixed seed), their colour (the base colour texture at the
// interpolated TEXCOORD_0, times COLOR_0) against the input's colour at the
// closest input point (CGAL's AABB tree, core/mesh/mesh_distance.h), both
// in the world frame of the first node that shows the primitive's mesh
// (gltfpack's quantized positions come with a dequantizing node
// transform): the 50th / 90th / 99th percentiles of the largest RGB
// difference in sRGB /255; and the dense two-sided distance (samples both
// ways, the largest and the rms) in percent of the input primitive's
// largest bounding-box side. Usage: gltf_texture_bench INPUT.gl(b|tf)
// OUTPUT.glb [SAMPLES]
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "sdcb/converters/gltf/gltf_import.h"
#include "sdcb/converters/gltf/texture_bake.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace {

using namespace sdcb;

// Area-weighted points on `m` (#S by 3) and, per point, its face and
// barycentric weights.
void Sample(const TriangleMesh& m, int n, Eigen::MatrixX3d* points,
            std::vector<int>* faces, std::vector<Eigen::Vector3d>* weights) {
  std::vector<double> area(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.vertices.row(m.faces(f, 0));
    const Eigen::Vector3d b = m.vertices.row(m.faces(f, 1));
    const Eigen::Vector3d c = m.vertices.row(m.faces(f, 2));
    area[f] = 0.5 * (b - a).cross(c - a).norm();
  }
  std::mt19937_64 rng(1);
  std::discrete_distribution<int> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> u01(0, 1);
  points->resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const int f = pick(rng);
    double s = u01(rng), t = u01(rng);
    if (s + t > 1) {
      s = 1 - s;
      t = 1 - t;
    }
    const Eigen::Vector3d w(1 - s - t, s, t);
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      p += w[k] * m.vertices.row(m.faces(f, k)).transpose();
    points->row(i) = p;
    faces->push_back(f);
    weights->push_back(w);
  }
}

// Planar barycentric weights of `p` (on triangle f of m).
Eigen::Vector3d Weights(const TriangleMesh& m, int f,
                        const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = m.vertices.row(m.faces(f, 0));
  const Eigen::Vector3d b = m.vertices.row(m.faces(f, 1));
  const Eigen::Vector3d c = m.vertices.row(m.faces(f, 2));
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double d = n.squaredNorm();
  if (d == 0) return Eigen::Vector3d(1, 0, 0);
  const double wb = (p - a).cross(c - a).dot(n) / d;
  const double wc = (b - a).cross(p - a).dot(n) / d;
  return Eigen::Vector3d(1 - wb - wc, wb, wc);
}

// The sRGB colour (0..255) of primitive `p` at face f, weights w.
Eigen::Vector3d Color(const GltfPrimitive& p, const GltfTexture& texture, int f,
                      const Eigen::Vector3d& w) {
  Eigen::Vector4d c = Eigen::Vector4d::Ones();
  if (texture.width > 0 && p.texcoords.rows() > 0) {
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    for (int k = 0; k < 3; ++k)
      uv += w[k] * p.texcoords.row(3 * f + k).transpose();
    c = SampleTexture(texture, uv);
  }
  if (p.colors.rows() > 0) {
    Eigen::Vector4d v = Eigen::Vector4d::Zero();
    for (int k = 0; k < 3; ++k) v += w[k] * p.colors.row(3 * f + k).transpose();
    c = c.cwiseProduct(v);
  }
  return Eigen::Vector3d(255 * LinearToSrgb(c[0]), 255 * LinearToSrgb(c[1]),
                         255 * LinearToSrgb(c[2]));
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
}

// The world transform of the first node (depth first from the scene's
// roots) that shows mesh `mesh`; the identity when none does.
Eigen::Matrix4d WorldOfMesh(const GltfAsset& asset, int mesh) {
  std::vector<std::pair<int, Eigen::Matrix4d>> stack;
  for (auto r = asset.roots.rbegin(); r != asset.roots.rend(); ++r) {
    stack.emplace_back(*r, Eigen::Matrix4d::Identity());
  }
  while (!stack.empty()) {
    const auto [n, parent] = stack.back();
    stack.pop_back();
    const GltfNode& node = asset.nodes[n];
    const Eigen::Matrix4d world = parent * node.local;
    if (node.mesh == mesh) return world;
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) {
      stack.emplace_back(*c, world);
    }
  }
  return Eigen::Matrix4d::Identity();
}

// `p` with its positions in the world frame of WorldOfMesh.
GltfPrimitive InWorld(const GltfAsset& asset, GltfPrimitive p) {
  const Eigen::Matrix4d world = WorldOfMesh(asset, p.mesh);
  Eigen::MatrixX3d& v = p.triangles.vertices;
  v = ((v * world.topLeftCorner<3, 3>().transpose()).rowwise() +
       world.topRightCorner<3, 1>().transpose())
          .eval();
  return p;
}

// Area of the triangles of `m`.
double Area(const TriangleMesh& m) { return VertexAreas(m).sum(); }

// The primitives each mesh of `document` lists (points and lines too).
std::vector<int> PrimitivesPerMesh(const GltfDocument& document) {
  const nlohmann::json j = nlohmann::json::parse(document.json);
  std::vector<int> count;
  for (const nlohmann::json& mesh :
       j.value("meshes", nlohmann::json::array())) {
    count.push_back(static_cast<int>(mesh.at("primitives").size()));
  }
  return count;
}

// One output primitive measured as (part of) an input primitive.
struct Piece {
  GltfPrimitive world;  // InWorld
  GltfTexture texture;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s INPUT.glb OUTPUT.glb [SAMPLES]\n", argv[0]);
    return 2;
  }
  const int samples = argc > 3 ? std::atoi(argv[3]) : 200000;
  StatusOr<GltfAsset> in = ReadGltf(argv[1]);
  StatusOr<GltfAsset> out = ReadGltf(argv[2]);
  if (!in.ok() || !out.ok()) {
    std::fprintf(stderr, "%s\n",
                 (!in.ok() ? in.status() : out.status()).message().c_str());
    return 1;
  }
  std::vector<GltfPrimitive> in_world, out_world;
  for (const GltfPrimitive& p : in->primitives) {
    in_world.push_back(InWorld(*in, p));
  }
  for (const GltfPrimitive& p : out->primitives) {
    out_world.push_back(InWorld(*out, p));
  }
  std::vector<MeshDistance> in_distance;
  for (const GltfPrimitive& p : in_world) {
    StatusOr<MeshDistance> d = MeshDistance::Create(p.triangles);
    if (!d.ok()) return 1;
    in_distance.push_back(std::move(d).value());
  }
  // Per input primitive, the output primitives that are its pieces: the
  // one of its mesh and index, and each primitive appended to its mesh
  // (index past the input's) that lies nearest it (mean vertex distance).
  const std::vector<int> in_count = PrimitivesPerMesh(in->document);
  std::vector<std::vector<int>> pieces_of(in_world.size());
  for (size_t q = 0; q < out_world.size(); ++q) {
    const GltfPrimitive& o = out_world[q];
    const bool appended = o.mesh < static_cast<int>(in_count.size()) &&
                          o.primitive >= in_count[o.mesh];
    int best = -1;
    double best_mean = HUGE_VAL;
    for (size_t i = 0; i < in_world.size(); ++i) {
      if (in_world[i].mesh != o.mesh) continue;
      if (!appended) {
        if (in_world[i].primitive == o.primitive) best = static_cast<int>(i);
        continue;
      }
      double sum = 0;
      for (int v = 0; v < o.triangles.num_vertices(); ++v) {
        sum += in_distance[i]
                   .Find(o.triangles.vertices.row(v).transpose())
                   .distance;
      }
      const double mean = sum / std::max(1, o.triangles.num_vertices());
      if (mean < best_mean) {
        best_mean = mean;
        best = static_cast<int>(i);
      }
    }
    if (best >= 0) pieces_of[best].push_back(static_cast<int>(q));
  }
  std::printf("%-24s %9s %9s %6s %9s %6s %6s %6s %9s %9s\n", "primitive",
              "in_faces", "out_faces", "pieces", "textured", "p50", "p90",
              "p99", "max_%", "rms_%");
  for (size_t i = 0; i < in_world.size(); ++i) {
    const GltfPrimitive& pi = in_world[i];
    bool same_index = false;
    for (const int q : pieces_of[i]) {
      same_index |= out_world[q].primitive == pi.primitive;
    }
    if (!same_index) {
      std::printf("%-24s missing in the output\n", pi.name.c_str());
      continue;
    }
    StatusOr<GltfTexture> ti = LoadBaseColorTexture(in->document, pi.material);
    if (!ti.ok()) {
      std::fprintf(stderr, "%s\n", ti.status().message().c_str());
      return 1;
    }
    const bool colored =
        (ti->width > 0 && pi.texcoords.rows() > 0) || pi.colors.rows() > 0;
    std::vector<Piece> pieces;
    TriangleMesh all;  // the pieces' triangles together
    double total_area = 0;
    bool textured_out = true;
    for (const int q : pieces_of[i]) {
      StatusOr<GltfTexture> to =
          LoadBaseColorTexture(out->document, out_world[q].material);
      if (!to.ok()) {
        std::fprintf(stderr, "%s\n", to.status().message().c_str());
        return 1;
      }
      const GltfPrimitive& po = out_world[q];
      textured_out =
          textured_out &&
          ((to->width > 0 && po.texcoords.rows() > 0) || po.colors.rows() > 0);
      const int nv = all.num_vertices(), nf = all.num_faces();
      all.vertices.conservativeResize(nv + po.triangles.num_vertices(), 3);
      all.vertices.bottomRows(po.triangles.num_vertices()) =
          po.triangles.vertices;
      all.faces.conservativeResize(nf + po.triangles.num_faces(), 3);
      all.faces.bottomRows(po.triangles.num_faces()) =
          po.triangles.faces.array() + nv;
      total_area += Area(po.triangles);
      pieces.push_back({po, *to});
    }
    StatusOr<MeshDistance> dout = MeshDistance::Create(all);
    if (!dout.ok()) return 1;
    const double side = (pi.triangles.vertices.colwise().maxCoeff() -
                         pi.triangles.vertices.colwise().minCoeff())
                            .maxCoeff();
    // Output samples, each piece's share by its area.
    std::vector<double> diff;
    double max_d = 0, sum2 = 0;
    int left = samples;
    for (size_t k = 0; k < pieces.size(); ++k) {
      const GltfPrimitive& po = pieces[k].world;
      const int n =
          k + 1 == pieces.size()
              ? left
              : static_cast<int>(samples * Area(po.triangles) / total_area);
      left -= n;
      if (n <= 0 || po.triangles.num_faces() == 0) continue;
      Eigen::MatrixX3d points;
      std::vector<int> faces;
      std::vector<Eigen::Vector3d> weights;
      Sample(po.triangles, n, &points, &faces, &weights);
      for (int s = 0; s < n; ++s) {
        const MeshDistance::Closest c =
            in_distance[i].Find(points.row(s).transpose());
        max_d = std::max(max_d, c.distance);
        sum2 += c.distance * c.distance;
        if (!colored) continue;
        const Eigen::Vector3d a =
            Color(po, pieces[k].texture, faces[s], weights[s]);
        const Eigen::Vector3d b =
            Color(pi, *ti, c.face, Weights(pi.triangles, c.face, c.point));
        diff.push_back((a - b).cwiseAbs().maxCoeff());
      }
    }
    Eigen::MatrixX3d back;
    std::vector<int> back_faces;
    std::vector<Eigen::Vector3d> back_weights;
    Sample(pi.triangles, samples, &back, &back_faces, &back_weights);
    for (int s = 0; s < samples; ++s) {
      const double d = dout->Find(back.row(s).transpose()).distance;
      max_d = std::max(max_d, d);
      sum2 += d * d;
    }
    const double rms = std::sqrt(sum2 / (2.0 * samples));
    std::printf("%-24s %9d %9d %6zu %9s %6.1f %6.1f %6.1f %9.3f %9.4f\n",
                pi.name.c_str(), pi.triangles.num_faces(), all.num_faces(),
                pieces.size(), colored ? (textured_out ? "yes" : "LOST") : "no",
                Percentile(diff, 0.5), Percentile(diff, 0.9),
                Percentile(diff, 0.99), 100 * max_d / side, 100 * rms / side);
  }
  return 0;
}
