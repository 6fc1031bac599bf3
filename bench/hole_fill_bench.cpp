// FillHoles (core/mesh/hole_filling.h) on CGAL's open genus-0 meshes, and
// TrimRegion::Contains (core/sphere/trim_region.h) on a synthetic loop.
// Prints per mesh: vertices, faces, boundary loops, the longest loop's
// edges, the fill's faces, the fill methods used and seconds; then the
// time of 1,000,000 Contains queries against one 5,000-point loop, and of
// 100,000 DistanceToTrim queries, uniform and near the loop.
// Usage: hole_fill_bench [mesh.off | wavy-disk-M ...] (default: the meshes
// of issue 54, from data/meshes, missing ones skipped with a note, then
// wavy-disk-1000 and wavy-disk-4000: a disk of 10 rings whose wavy rim,
// z = 0.3 r sin(5 phi), is one non-planar loop of M edges).
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "sdcb/core/common/stopwatch.h"
#include "sdcb/core/mesh/hole_filling.h"
#include "sdcb/core/sphere/trim_region.h"
#include "sdcb/io/mesh/mesh_reader.h"

namespace {

using sdcb::TriangleMesh;

// `mesh` without the vertices no face uses (FillHoles wants a part).
TriangleMesh DropUnreferenced(const TriangleMesh& mesh) {
  std::vector<int> row(mesh.num_vertices(), -1);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) row[mesh.faces(f, k)] = 0;
  }
  int next = 0;
  for (int& r : row) {
    if (r == 0) r = next++;
  }
  TriangleMesh out;
  out.vertices.resize(next, 3);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (row[v] >= 0) out.vertices.row(row[v]) = mesh.vertices.row(v);
  }
  out.faces.resize(mesh.num_faces(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) out.faces(f, k) = row[mesh.faces(f, k)];
  }
  return out;
}

// A disk of `rings` rings of `m` vertices around a centre, its rim wavy
// (z = 0.3 r sin(5 phi)): one boundary loop of m edges that no plane fits.
TriangleMesh WavyDisk(int m, int rings) {
  TriangleMesh disk;
  disk.vertices.resize(1 + m * rings, 3);
  disk.vertices.row(0).setZero();
  for (int k = 1; k <= rings; ++k) {
    const double r = double(k) / rings;
    for (int i = 0; i < m; ++i) {
      const double phi = 2 * M_PI * i / m;
      disk.vertices.row(1 + (k - 1) * m + i) << r * std::cos(phi),
          r * std::sin(phi), 0.3 * r * std::sin(5 * phi);
    }
  }
  auto at = [m](int k, int i) { return 1 + (k - 1) * m + (i % m); };
  std::vector<Eigen::Vector3i> faces;
  for (int i = 0; i < m; ++i) faces.emplace_back(0, at(1, i), at(1, i + 1));
  for (int k = 1; k < rings; ++k) {
    for (int i = 0; i < m; ++i) {
      faces.emplace_back(at(k, i), at(k + 1, i), at(k + 1, i + 1));
      faces.emplace_back(at(k, i), at(k + 1, i + 1), at(k, i + 1));
    }
  }
  disk.faces.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) {
    disk.faces.row(f) = faces[f].transpose();
  }
  return disk;
}

void FillTable(const std::vector<std::string>& paths) {
  std::printf("%-22s %8s %8s %5s %7s %8s  %-26s %7s\n", "mesh", "vertices",
              "faces", "loops", "longest", "fill", "methods", "seconds");
  for (const std::string& path : paths) {
    const std::string name = path.substr(path.find_last_of('/') + 1);
    TriangleMesh part;
    if (name.rfind("wavy-disk-", 0) == 0) {
      part = WavyDisk(std::stoi(name.substr(10)), 10);
    } else {
      sdcb::StatusOr<TriangleMesh> read = sdcb::ReadMesh(path);
      if (!read.ok()) {
        std::printf("%-22s skipped: %s\n", name.c_str(),
                    read.status().message().c_str());
        continue;
      }
      part = DropUnreferenced(*read);
    }
    sdcb::Stopwatch watch;
    const sdcb::StatusOr<sdcb::FilledMesh> filled = sdcb::FillHoles(part);
    const double seconds = watch.Seconds();
    if (!filled.ok()) {
      std::printf("%-22s %8d %8d  failed after %.2f s: %s\n", name.c_str(),
                  part.num_vertices(), part.num_faces(), seconds,
                  filled.status().message().c_str());
      continue;
    }
    size_t longest = 0;
    for (const std::vector<int>& loop : filled->boundary_loops) {
      longest = std::max(longest, loop.size());
    }
    std::map<std::string, int> methods;
    for (sdcb::HoleFillMethod m : filled->fill_methods) {
      ++methods[sdcb::HoleFillMethodName(m)];
    }
    std::string method_text;
    for (const auto& [method, count] : methods) {
      if (!method_text.empty()) method_text += ",";
      method_text += std::to_string(count) + " " + method;
    }
    std::printf("%-22s %8d %8d %5zu %7zu %8d  %-26s %7.2f\n", name.c_str(),
                part.num_vertices(), part.num_faces(),
                filled->boundary_loops.size(), longest,
                filled->mesh.num_faces() - filled->input_faces,
                method_text.c_str(), seconds);
  }
}

// A wavy 5,000-point loop around the north pole (a hole of latitude about
// 30 degrees with 20 waves); 1,000,000 uniform random query points.
void TrimTiming() {
  const int n = 5000;
  sdcb::TrimLoop loop;
  loop.points.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    // Clockwise seen from above, so that the cap around +z is the hole.
    const double phi = -2 * M_PI * i / n;
    const double theta = 0.5 + 0.1 * std::sin(20 * phi);
    loop.points.row(i) << std::sin(theta) * std::cos(phi),
        std::sin(theta) * std::sin(phi), std::cos(theta);
  }
  sdcb::Stopwatch build;
  sdcb::StatusOr<sdcb::TrimRegion> region = sdcb::TrimRegion::Create({loop});
  const double build_seconds = build.Seconds();
  if (!region.ok()) {
    std::printf("trim region: %s\n", region.status().message().c_str());
    return;
  }
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  const int queries = 1000000;
  std::vector<Eigen::Vector3d> points(queries);
  for (Eigen::Vector3d& p : points) {
    p = Eigen::Vector3d(normal(random), normal(random), normal(random))
            .normalized();
  }
  sdcb::Stopwatch watch;
  int kept = 0;
  for (const Eigen::Vector3d& p : points) kept += region->Contains(p);
  const double seconds = watch.Seconds();
  sdcb::Stopwatch distance_watch;
  double sum = 0;
  const int distance_queries = 100000;
  for (int i = 0; i < distance_queries; ++i) {
    sum += region->DistanceToTrim(points[i]);
  }
  const double distance_seconds = distance_watch.Seconds();
  // Points within about 0.05 radians of the loop, with that limit.
  std::vector<Eigen::Vector3d> near(distance_queries);
  std::uniform_int_distribution<int> row(0, n - 1);
  for (Eigen::Vector3d& p : near) {
    const Eigen::Vector3d on = loop.points.row(row(random));
    p = (on +
         0.03 * Eigen::Vector3d(normal(random), normal(random), normal(random)))
            .normalized();
  }
  sdcb::Stopwatch near_watch;
  double near_sum = 0;
  for (const Eigen::Vector3d& p : near) {
    near_sum += region->DistanceToTrim(p, 0.05);
  }
  const double near_seconds = near_watch.Seconds();
  std::printf(
      "\ntrim region, one loop of %d points: build %.4f s; %d Contains "
      "%.3f s (%.1f%% kept); %d DistanceToTrim %.3f s (mean %.4f rad); "
      "%d near the loop with limit 0.05: %.3f s (mean %.4f rad)\n",
      n, build_seconds, queries, seconds, 100.0 * kept / queries,
      distance_queries, distance_seconds, sum / distance_queries,
      distance_queries, near_seconds, near_sum / distance_queries);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) paths.push_back(argv[i]);
  if (paths.empty()) {
    for (const char* name :
         {"lion-head", "mannequin-devil", "nefertiti", "mushroom",
          "three_peaks", "cylinder", "blade", "ChineseDragon-10kv", "head",
          "mech-holes-shark", "holes", "lion", "pig", "patch-01", "plane"}) {
      paths.push_back(std::string(SDCB_MESH_DIR) + "/" + name + ".off");
    }
    // Synthetic: one non-planar loop of 1,000 and of 4,000 edges.
    paths.push_back("wavy-disk-1000");
    paths.push_back("wavy-disk-4000");
  }
  FillTable(paths);
  TrimTiming();
  return 0;
}
