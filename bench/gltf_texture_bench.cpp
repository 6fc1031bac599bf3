// The colours and shape of a glTF asset written back by `sdcb export`
// against its input, per primitive (matched by mesh and primitive index):
// points sampled on the output's triangles (area-weighted, fixed seed),
// their colour (the base colour texture at the interpolated TEXCOORD_0,
// times COLOR_0) against the input's colour at the closest input point
// (CGAL's AABB tree, core/mesh/mesh_distance.h), both in the world frame
// of the first node that shows the primitive's mesh (gltfpack's quantized
// positions come with a dequantizing node transform): the
// 50th / 90th / 99th percentiles of the largest RGB difference in sRGB
// /255; and the dense two-sided distance (samples both ways, the largest
// and the rms) in percent of the input primitive's largest bounding-box
// side. Usage: gltf_texture_bench INPUT.gl(b|tf) OUTPUT.glb [SAMPLES]
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "sdcb/converters/gltf/gltf_import.h"
#include "sdcb/converters/gltf/texture_bake.h"
#include "sdcb/core/mesh/mesh_distance.h"

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
  std::printf("%-24s %9s %9s %9s %6s %6s %6s %9s %9s\n", "primitive",
              "in_faces", "out_faces", "textured", "p50", "p90", "p99", "max_%",
              "rms_%");
  for (const GltfPrimitive& local_in : in->primitives) {
    const GltfPrimitive* found = nullptr;
    for (const GltfPrimitive& q : out->primitives) {
      if (q.mesh == local_in.mesh && q.primitive == local_in.primitive) {
        found = &q;
      }
    }
    if (found == nullptr) {
      std::printf("%-24s missing in the output\n", local_in.name.c_str());
      continue;
    }
    const GltfPrimitive in_world = InWorld(*in, local_in);
    const GltfPrimitive out_world = InWorld(*out, *found);
    const GltfPrimitive& pi = in_world;
    const GltfPrimitive* po = &out_world;
    StatusOr<GltfTexture> ti = LoadBaseColorTexture(in->document, pi.material);
    StatusOr<GltfTexture> to =
        LoadBaseColorTexture(out->document, po->material);
    if (!ti.ok() || !to.ok()) {
      std::fprintf(stderr, "%s\n",
                   (!ti.ok() ? ti.status() : to.status()).message().c_str());
      return 1;
    }
    const bool colored =
        (ti->width > 0 && pi.texcoords.rows() > 0) || pi.colors.rows() > 0;
    const bool textured_out =
        (to->width > 0 && po->texcoords.rows() > 0) || po->colors.rows() > 0;
    StatusOr<MeshDistance> din = MeshDistance::Create(pi.triangles);
    StatusOr<MeshDistance> dout = MeshDistance::Create(po->triangles);
    if (!din.ok() || !dout.ok()) return 1;
    const double side = (pi.triangles.vertices.colwise().maxCoeff() -
                         pi.triangles.vertices.colwise().minCoeff())
                            .maxCoeff();
    Eigen::MatrixX3d points;
    std::vector<int> faces;
    std::vector<Eigen::Vector3d> weights;
    Sample(po->triangles, samples, &points, &faces, &weights);
    std::vector<double> diff;
    double max_d = 0, sum2 = 0;
    for (int i = 0; i < samples; ++i) {
      const MeshDistance::Closest c = din->Find(points.row(i).transpose());
      max_d = std::max(max_d, c.distance);
      sum2 += c.distance * c.distance;
      if (!colored) continue;
      const Eigen::Vector3d a = Color(*po, *to, faces[i], weights[i]);
      const Eigen::Vector3d b =
          Color(pi, *ti, c.face, Weights(pi.triangles, c.face, c.point));
      diff.push_back((a - b).cwiseAbs().maxCoeff());
    }
    Eigen::MatrixX3d back;
    std::vector<int> back_faces;
    std::vector<Eigen::Vector3d> back_weights;
    Sample(pi.triangles, samples, &back, &back_faces, &back_weights);
    for (int i = 0; i < samples; ++i) {
      const double d = dout->Find(back.row(i).transpose()).distance;
      max_d = std::max(max_d, d);
      sum2 += d * d;
    }
    const double rms = std::sqrt(sum2 / (2.0 * samples));
    std::printf("%-24s %9d %9d %9s %6.1f %6.1f %6.1f %9.3f %9.4f\n",
                pi.name.c_str(), pi.triangles.num_faces(),
                po->triangles.num_faces(),
                colored ? (textured_out ? "yes" : "LOST") : "no",
                Percentile(diff, 0.5), Percentile(diff, 0.9),
                Percentile(diff, 0.99), 100 * max_d / side, 100 * rms / side);
  }
  return 0;
}
