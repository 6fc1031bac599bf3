// Pictures for the docs, drawn by the benches: an orthographic z-buffer
// rasterizer of shaded triangles and an 8-bit RGB PNG encoder (zlib and the
// CRC of sdcb's io layer).
#ifndef SDCB_BENCH_PICTURE_H_
#define SDCB_BENCH_PICTURE_H_

#include <zlib.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/io/sdcb/crc32.h"

namespace sdcb::bench {

inline void PngChunk(std::string* png, const char* type,
                     const std::string& data) {
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
inline std::string EncodePng(const std::vector<unsigned char>& rgb, int size) {
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
  PngChunk(&png, "IHDR", header);
  PngChunk(&png, "IDAT", packed);
  PngChunk(&png, "IEND", "");
  return png;
}

// The arguments [SIZE] [YAW_DEGREES] [PITCH_DEGREES] from argv[first] on:
// the picture's side in pixels (default 900) and the view, which turns the
// scene by YAW about y and then PITCH about x and looks along -z.
struct View {
  int size = 900;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};
inline View ViewFromArgs(int argc, char** argv, int first) {
  View view;
  if (argc > first) view.size = std::atoi(argv[first]);
  const auto radians = [&](int i) {
    return argc > i ? std::atof(argv[i]) * kPi / 180.0 : 0.0;
  };
  view.rotation =
      (Eigen::AngleAxisd(radians(first + 2), Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(radians(first + 1), Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  return view;
}

// A square white canvas of `size` pixels showing the view-space box [lo, hi]
// (x right, y up, larger z nearer) in 92 % of its width, orthographically.
class Canvas {
 public:
  Canvas(int size, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi)
      : size_(size),
        scale_(0.92 * size / std::max(hi.x() - lo.x(), hi.y() - lo.y())),
        mid_(0.5 * (lo + hi)),
        depth_(size * size, -1e30),
        rgb_(3 * size * size, 255) {}

  // The triangle with corners p (view space), normals n and colours c
  // (0..1), each interpolated; shaded by 0.25 + 0.75 |n . light| unless
  // `flat` (the colour as it is).
  void Triangle(const Eigen::Vector3d* p, const Eigen::Vector3d* n,
                const Eigen::Vector3d* c, bool flat) {
    Eigen::Vector2d s[3];
    for (int k = 0; k < 3; ++k) {
      s[k] = Eigen::Vector2d((p[k].x() - mid_.x()) * scale_ + size_ / 2,
                             size_ / 2 - (p[k].y() - mid_.y()) * scale_);
    }
    const double area = (s[1] - s[0]).x() * (s[2] - s[0]).y() -
                        (s[1] - s[0]).y() * (s[2] - s[0]).x();
    if (area == 0.0) return;
    const int x0 =
        std::max(0, int(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
    const int x1 = std::min(
        size_ - 1, int(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
    const int y0 =
        std::max(0, int(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
    const int y1 = std::min(
        size_ - 1, int(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
    const Eigen::Vector3d light = Eigen::Vector3d(-0.4, 0.5, 1.0).normalized();
    for (int py = y0; py <= y1; ++py) {
      for (int px = x0; px <= x1; ++px) {
        const Eigen::Vector2d q(px + 0.5, py + 0.5);
        double w[3];
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d& b = s[(k + 1) % 3];
          const Eigen::Vector2d& c2 = s[(k + 2) % 3];
          w[k] =
              ((c2 - b).x() * (q - b).y() - (c2 - b).y() * (q - b).x()) / area;
        }
        if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
        const double z = w[0] * p[0].z() + w[1] * p[1].z() + w[2] * p[2].z();
        double& d = depth_[py * size_ + px];
        if (z <= d) continue;
        d = z;
        Eigen::Vector3d colour = w[0] * c[0] + w[1] * c[1] + w[2] * c[2];
        if (!flat) {
          const Eigen::Vector3d normal =
              (w[0] * n[0] + w[1] * n[1] + w[2] * n[2]).normalized();
          colour *= 0.25 + 0.75 * std::abs(normal.dot(light));
        }
        for (int k = 0; k < 3; ++k) {
          rgb_[3 * (py * size_ + px) + k] = static_cast<unsigned char>(
              std::clamp(colour[k], 0.0, 1.0) * 255.0 + 0.5);
        }
      }
    }
  }

  std::string Png() const { return EncodePng(rgb_, size_); }

 private:
  int size_;
  double scale_;
  Eigen::Vector3d mid_;
  std::vector<double> depth_;
  std::vector<unsigned char> rgb_;
};

}  // namespace sdcb::bench

#endif  // SDCB_BENCH_PICTURE_H_
