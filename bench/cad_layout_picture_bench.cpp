// A picture of the CAD network's face layout (docs/CAD.md): fits the
// network as `sdcb export OUT.step` does, then draws its faces, each in its
// own colour, shaded, with the faces' borders in black and their knot
// lines in a darker shade, by a z-buffer rasterizer written here, and
// writes a PNG (zlib and the CRC of sdcb's io layer).
//
//   cad_layout_picture_bench MODEL.sdcb OUT.png [SIZE] [YAW_DEGREES]
//                            [PITCH_DEGREES]
//
// The view is orthographic, along -z after turning the model by YAW about
// y and then PITCH about x (the model's normalized frame).
#include <zlib.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "sdcb/converters/cad_network.h"
#include "sdcb/io/crc32.h"
#include "sdcb/io/sdcb_file.h"

namespace {

void Chunk(std::string* png, const char* type, const std::string& data) {
  const uint32_t n = static_cast<uint32_t>(data.size());
  const char length[4] = {char(n >> 24), char(n >> 16), char(n >> 8), char(n)};
  png->append(length, 4);
  const std::string body = std::string(type, 4) + data;
  png->append(body);
  const uint32_t crc = sdcb::Crc32(body);
  const char c[4] = {char(crc >> 24), char(crc >> 16), char(crc >> 8),
                     char(crc)};
  png->append(c, 4);
}

// An 8-bit RGB PNG of `rgb` (size x size x 3, rows top first).
std::string EncodePng(const std::vector<unsigned char>& rgb, int size) {
  std::string raw;
  for (int y = 0; y < size; ++y) {
    raw.push_back(0);  // filter: none
    raw.append(reinterpret_cast<const char*>(rgb.data()) + 3 * size * y,
               3 * size);
  }
  uLongf bound = compressBound(raw.size());
  std::string packed(bound, '\0');
  compress2(reinterpret_cast<Bytef*>(packed.data()), &bound,
            reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 9);
  packed.resize(bound);
  std::string png = "\x89PNG\r\n\x1a\n";
  std::string header(13, '\0');
  for (int k = 0; k < 2; ++k) {
    header[4 * k] = char(size >> 24);
    header[4 * k + 1] = char(size >> 16);
    header[4 * k + 2] = char(size >> 8);
    header[4 * k + 3] = char(size);
  }
  header[8] = 8;  // bit depth
  header[9] = 2;  // RGB
  Chunk(&png, "IHDR", header);
  Chunk(&png, "IDAT", packed);
  Chunk(&png, "IEND", "");
  return png;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: cad_layout_picture_bench MODEL.sdcb OUT.png [SIZE] "
                 "[YAW_DEGREES] [PITCH_DEGREES]\n");
    return 2;
  }
  const int size = argc > 3 ? std::atoi(argv[3]) : 900;
  const double yaw = (argc > 4 ? std::atof(argv[4]) : 0.0) * M_PI / 180.0;
  const double pitch = (argc > 5 ? std::atof(argv[5]) : 0.0) * M_PI / 180.0;
  auto model = sdcb::ReadSdcbFile(argv[1]);
  if (!model.ok()) return 1;
  auto spline = sdcb::SurfaceFromModel(*model);
  if (!spline.ok()) return 1;
  auto net = sdcb::FitCadNetwork(*spline, sdcb::CadNetworkOptions());
  if (!net.ok()) return 1;
  const Eigen::Matrix3d view =
      (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
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
  const double scale = 0.92 * size / std::max(hi.x() - lo.x(), hi.y() - lo.y());
  const Eigen::Vector3d mid = 0.5 * (lo + hi);
  std::vector<double> depth(size * size, -1e30);
  std::vector<unsigned char> rgb(3 * size * size, 255);
  const Eigen::Vector3d light = Eigen::Vector3d(-0.4, 0.5, 1.0).normalized();
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
        const bool line = l[a].line;
        for (int t = 0; t < 2; ++t) {
          const Vertex* v[3] = {&l[quad[0]], &l[quad[1 + t]], &l[quad[2 + t]]};
          Eigen::Vector2d s[3];
          for (int k = 0; k < 3; ++k) {
            s[k] = Eigen::Vector2d((v[k]->p.x() - mid.x()) * scale + size / 2,
                                   size / 2 - (v[k]->p.y() - mid.y()) * scale);
          }
          const double area = (s[1] - s[0]).x() * (s[2] - s[0]).y() -
                              (s[1] - s[0]).y() * (s[2] - s[0]).x();
          if (area == 0.0) continue;
          const int x0 = std::max(
              0, int(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
          const int x1 = std::min(
              size - 1,
              int(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
          const int y0 = std::max(
              0, int(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
          const int y1 = std::min(
              size - 1,
              int(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
          for (int py = y0; py <= y1; ++py) {
            for (int px = x0; px <= x1; ++px) {
              const Eigen::Vector2d q(px + 0.5, py + 0.5);
              double w[3];
              for (int k = 0; k < 3; ++k) {
                const Eigen::Vector2d& b = s[(k + 1) % 3];
                const Eigen::Vector2d& c = s[(k + 2) % 3];
                w[k] = ((c - b).x() * (q - b).y() - (c - b).y() * (q - b).x()) /
                       area;
              }
              if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
              const double z =
                  w[0] * v[0]->p.z() + w[1] * v[1]->p.z() + w[2] * v[2]->p.z();
              double& d = depth[py * size + px];
              if (z <= d) continue;
              d = z;
              const Eigen::Vector3d n =
                  (w[0] * v[0]->n + w[1] * v[1]->n + w[2] * v[2]->n)
                      .normalized();
              const double shade = 0.25 + 0.75 * std::abs(n.dot(light));
              Eigen::Vector3d colour = shade * base;
              if (line) colour *= 0.72;
              if (border) colour = Eigen::Vector3d::Constant(0.05);
              for (int k = 0; k < 3; ++k) {
                rgb[3 * (py * size + px) + k] = static_cast<unsigned char>(
                    std::clamp(colour[k], 0.0, 1.0) * 255.0 + 0.5);
              }
            }
          }
        }
      }
    }
  }
  std::ofstream(argv[2], std::ios::binary) << EncodePng(rgb, size);
  std::printf("%s: %zu faces, %d control points -> %s (%d x %d)\n", argv[1],
              net->faces.size(), net->control_points, argv[2], size, size);
  return 0;
}
