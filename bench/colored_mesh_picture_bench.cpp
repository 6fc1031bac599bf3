// A picture of a mesh with vertex colours, such as `sdcb compare --picture`
// writes (distance white to red, folded samples blue): shaded by its vertex
// normals, colours interpolated (bench/picture.h), written as a PNG.
//
//   colored_mesh_picture_bench MESH.ply OUT.png [SIZE] [YAW_DEGREES]
//                              [PITCH_DEGREES] [X Y Z RADIUS]
//
// MESH.ply: ASCII, vertices "x y z red green blue", triangles. The view is
// orthographic, along -z after turning the mesh by YAW about y and then
// PITCH about x; with X Y Z RADIUS only the triangles with a corner within
// RADIUS of (X, Y, Z) are drawn, and the picture frames them.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench/picture.h"

int main(int argc, char** argv) {
  if (argc < 3 || (argc > 6 && argc != 10)) {
    std::fprintf(stderr,
                 "usage: colored_mesh_picture_bench MESH.ply OUT.png [SIZE] "
                 "[YAW_DEGREES] [PITCH_DEGREES] [X Y Z RADIUS]\n");
    return 2;
  }
  const sdcb::bench::View v = sdcb::bench::ViewFromArgs(argc, argv, 3);
  const int size = v.size;
  const Eigen::Matrix3d& view = v.rotation;
  const bool crop = argc == 10;
  const Eigen::Vector3d centre =
      crop ? Eigen::Vector3d(std::atof(argv[6]), std::atof(argv[7]),
                             std::atof(argv[8]))
           : Eigen::Vector3d::Zero();
  const double radius = crop ? std::atof(argv[9]) : 0.0;

  std::ifstream in(argv[1]);
  std::string line;
  int vertices = 0, faces = 0;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string element, name;
    int n = 0;
    if (words >> element >> name >> n && element == "element") {
      (name == "vertex" ? vertices : faces) = n;
    }
  }
  std::vector<Eigen::Vector3d> points(vertices), colours(vertices);
  for (int v = 0; v < vertices; ++v) {
    int r = 0, g = 0, b = 0;
    in >> points[v].x() >> points[v].y() >> points[v].z() >> r >> g >> b;
    colours[v] = Eigen::Vector3d(r, g, b) / 255.0;
  }
  std::vector<std::array<int, 3>> triangles(faces);
  for (auto& t : triangles) {
    int corners = 0;
    in >> corners >> t[0] >> t[1] >> t[2];
    if (!in || corners != 3) {
      std::fprintf(stderr, "%s: not an ASCII triangle PLY\n", argv[1]);
      return 1;
    }
  }
  std::vector<Eigen::Vector3d> normals(vertices, Eigen::Vector3d::Zero());
  for (const auto& t : triangles) {
    const Eigen::Vector3d n =
        (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
    for (const int v : t) normals[v] += n;
  }
  std::vector<std::array<int, 3>> drawn;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& t : triangles) {
    bool near = !crop;
    for (const int v : t) near = near || (points[v] - centre).norm() <= radius;
    if (!near) continue;
    drawn.push_back(t);
    for (const int v : t) {
      lo = lo.cwiseMin(view * points[v]);
      hi = hi.cwiseMax(view * points[v]);
    }
  }
  if (drawn.empty()) {
    std::fprintf(stderr, "%s: no triangle to draw\n", argv[1]);
    return 1;
  }
  sdcb::bench::Canvas canvas(size, lo, hi);
  for (const auto& t : drawn) {
    Eigen::Vector3d p[3], n[3], c[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = view * points[t[k]];
      n[k] = (view * normals[t[k]]).normalized();
      c[k] = colours[t[k]];
    }
    canvas.Triangle(p, n, c, /*flat=*/false);
  }
  std::ofstream(argv[2], std::ios::binary) << canvas.Png();
  std::printf("%s: %zu of %d triangles -> %s (%d x %d)\n", argv[1],
              drawn.size(), faces, argv[2], size, size);
  return 0;
}
