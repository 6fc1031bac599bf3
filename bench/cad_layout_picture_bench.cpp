// A picture of the CAD network's face layout (docs/CAD.md): fits the
// network as `sdcb export OUT.step` does, then draws its faces, each in its
// own colour, shaded, with the faces' borders in black and their knot
// lines in a darker shade (bench/picture.h), and writes a PNG.
//
//   cad_layout_picture_bench MODEL.sdcb OUT.png [SIZE] [YAW_DEGREES]
//                            [PITCH_DEGREES]
//
// The view is orthographic, along -z after turning the model by YAW about
// y and then PITCH about x (the model's normalized frame).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "bench/picture.h"
#include "sdcb/converters/cad/cad_network.h"
#include "sdcb/io/sdcb/sdcb_file.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: cad_layout_picture_bench MODEL.sdcb OUT.png [SIZE] "
                 "[YAW_DEGREES] [PITCH_DEGREES]\n");
    return 2;
  }
  const sdcb::bench::View v = sdcb::bench::ViewFromArgs(argc, argv, 3);
  const int size = v.size;
  const Eigen::Matrix3d& view = v.rotation;
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) return 1;
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  auto net = sdcb::FitCadNetwork(*spline, sdcb::CadNetworkOptions());
  if (!net.ok()) return 1;
  // Every face on a lattice: points in view coordinates, colour per
  // lattice cell.
  constexpr int kN = 64;
  struct Vertex {
    Eigen::Vector3d p, n;
    bool line;
  };
  std::vector<std::vector<Vertex>> lattices;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const sdcb::BSplineFace& face : net->faces) {
    std::vector<Vertex> lattice;
    const double u0 = face.u_breaks.front(), u1 = face.u_breaks.back();
    const double v0 = face.v_breaks.front(), v1 = face.v_breaks.back();
    const auto on_knot = [](const sdcb::KnotBreaks& b, double x, double h) {
      for (const double k : b) {
        if (std::abs(x - k) < h) return true;
      }
      return false;
    };
    for (int j = 0; j <= kN; ++j) {
      for (int i = 0; i <= kN; ++i) {
        const double u = u0 + (u1 - u0) * i / kN, v = v0 + (v1 - v0) * j / kN;
        Eigen::Vector3d du, dv;
        Vertex x;
        x.p = view * face.Evaluate(u, v, &du, &dv);
        x.n = (view * du.cross(dv)).normalized();
        x.line = on_knot(face.u_breaks, u, 0.5 * (u1 - u0) / kN) ||
                 on_knot(face.v_breaks, v, 0.5 * (v1 - v0) / kN);
        lo = lo.cwiseMin(x.p);
        hi = hi.cwiseMax(x.p);
        lattice.push_back(x);
      }
    }
    lattices.push_back(std::move(lattice));
  }
  sdcb::bench::Canvas canvas(size, lo, hi);
  for (size_t f = 0; f < lattices.size(); ++f) {
    // A colour per face from its index (golden-ratio hues).
    const double hue = std::fmod(f * 0.618033988749895, 1.0) * 6.0;
    const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
    Eigen::Vector3d base = hue < 1   ? Eigen::Vector3d(1, x, 0)
                           : hue < 2 ? Eigen::Vector3d(x, 1, 0)
                           : hue < 3 ? Eigen::Vector3d(0, 1, x)
                           : hue < 4 ? Eigen::Vector3d(0, x, 1)
                           : hue < 5 ? Eigen::Vector3d(x, 0, 1)
                                     : Eigen::Vector3d(1, 0, x);
    base = 0.45 * base + Eigen::Vector3d::Constant(0.5);
    const std::vector<Vertex>& l = lattices[f];
    for (int j = 0; j < kN; ++j) {
      for (int i = 0; i < kN; ++i) {
        const int a = j * (kN + 1) + i;
        const int quad[4] = {a, a + 1, a + kN + 2, a + kN + 1};
        const bool border = i == 0 || j == 0 || i == kN - 1 || j == kN - 1;
        const Eigen::Vector3d colour =
            border ? Eigen::Vector3d::Constant(0.05)
                   : Eigen::Vector3d(l[a].line ? 0.72 * base : base);
        const Eigen::Vector3d c[3] = {colour, colour, colour};
        for (int t = 0; t < 2; ++t) {
          const Vertex* v[3] = {&l[quad[0]], &l[quad[1 + t]], &l[quad[2 + t]]};
          const Eigen::Vector3d p[3] = {v[0]->p, v[1]->p, v[2]->p};
          const Eigen::Vector3d n[3] = {v[0]->n, v[1]->n, v[2]->n};
          canvas.Triangle(p, n, c, /*flat=*/border);
        }
      }
    }
  }
  std::ofstream(argv[2], std::ios::binary) << canvas.Png();
  std::printf("%s: %zu faces, %d control points -> %s (%d x %d)\n", argv[1],
              net->faces.size(), net->control_points, argv[2], size, size);
  return 0;
}
