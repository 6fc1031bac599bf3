#include "sdcb/converters/cad_patches.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "sdcb/converters/cad_patch_cache.h"
#include "sdcb/converters/stopwatch.h"
#include "sdcb/core/spline/piecewise_surface.h"

namespace sdcb {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Patches are refined until their measured distance is within this share of
// the tolerance: a margin for the distance between lattice points.
constexpr double kTargetShare = 0.95;

uint64_t EdgeKey(int a, int b) {
  const auto lo = static_cast<uint64_t>(std::min(a, b));
  const auto hi = static_cast<uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

// The edges of a quad layout: each edge's two vertices (lower index first)
// and, per face and local edge k, the edge index and whether the face runs
// along it from the lower to the higher vertex.
struct LayoutEdges {
  std::vector<std::array<int, 2>> vertices;
  std::vector<std::array<int, 2>> faces;       // (face, local edge) x 2
  std::vector<std::array<int, 2>> face_local;  // local edge of each side
  std::vector<std::array<int, 4>> face_edge;
  std::vector<std::array<bool, 4>> face_forward;
};

StatusOr<LayoutEdges> BuildEdges(const SphereCage& layout) {
  LayoutEdges e;
  std::unordered_map<uint64_t, int> index;
  const int nf = layout.num_faces();
  e.face_edge.resize(nf);
  e.face_forward.resize(nf);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 4; ++k) {
      const int a = layout.faces[f][k];
      const int b = layout.faces[f][(k + 1) % 4];
      const auto [it, inserted] =
          index.emplace(EdgeKey(a, b), static_cast<int>(e.vertices.size()));
      if (inserted) {
        e.vertices.push_back({std::min(a, b), std::max(a, b)});
        e.faces.push_back({f, -1});
        e.face_local.push_back({k, -1});
      } else {
        if (e.faces[it->second][1] != -1) {
          return InternalError("CAD layout edge shared by more than 2 faces");
        }
        e.faces[it->second][1] = f;
        e.face_local[it->second][1] = k;
      }
      e.face_edge[f][k] = it->second;
      e.face_forward[f][k] = a < b;
    }
  }
  for (const auto& sides : e.faces) {
    if (sides[1] == -1) return InternalError("CAD layout is not closed");
  }
  return e;
}

Eigen::Vector3d UnitNormal(const BicubicPatch& patch, double u, double v) {
  Eigen::Vector3d du, dv;
  patch.Evaluate(u, v, &du, &dv);
  const Eigen::Vector3d n = du.cross(dv);
  const double norm = n.norm();
  return norm > 0.0 ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::Zero();
}

double MaxNormalJump(const std::vector<BicubicPatch>& patches,
                     const LayoutEdges& edges, int samples) {
  std::vector<double> worst(edges.vertices.size(), 0.0);
  tbb::parallel_for(size_t{0}, edges.vertices.size(), [&](size_t e) {
    for (int m = 0; m <= samples; ++m) {
      const double t = double(m) / samples;
      Eigen::Vector3d normals[2];
      for (int side = 0; side < 2; ++side) {
        const int f = edges.faces[e][side];
        const int k = edges.face_local[e][side];
        const double s = edges.face_forward[f][k] ? t : 1.0 - t;
        const Eigen::Vector2d uv = QuadEdgeParameter(k, s);
        normals[side] = UnitNormal(patches[f], uv.x(), uv.y());
      }
      const double c = std::clamp(normals[0].dot(normals[1]), -1.0, 1.0);
      worst[e] = std::max(worst[e], std::acos(c) * 180.0 / kPi);
    }
  });
  return worst.empty() ? 0.0 : *std::max_element(worst.begin(), worst.end());
}

}  // namespace

StatusOr<CadPatchSet> FitCadPatches(const SphericalSpline& spline,
                                    const CadPatchOptions& options) {
  if (!(options.tolerance_percent > 0.0) || !(options.length_unit > 0.0) ||
      !(options.angle_degrees > 0.0) || options.max_faces < 96 ||
      options.initial_levels < 0 || options.initial_levels > 8 ||
      options.fit_samples_per_side < 3 || options.check_samples_per_side < 1 ||
      options.max_rounds < 1 ||
      !(options.fine_share >= 0.0 && options.fine_share <= 1.0)) {
    return InvalidArgumentError(
        "CAD patches need a positive tolerance, angle and length unit, at "
        "least 96 patches, 0..8 initial levels, at least 3 fit samples per "
        "side and a fine share in [0, 1]");
  }
  const PiecewiseSurface surface(spline);
  const double percent_per_unit = 100.0 / options.length_unit;
  const double tolerance = options.tolerance_percent / percent_per_unit;
  SphereCageTopology topology =
      SphereCageTopology::Create(CageCellShape::kQuad, options.initial_levels);
  PatchCache cache(surface, options);
  CadPatchSet result;
  double progress = 0.0;
  for (int round = 1;; ++round) {
    const SphereCage& layout = topology.cage();
    const int nf = layout.num_faces();
    Stopwatch t0;
    const std::vector<FaceRecord*> records = cache.Update(layout);
    result.fit_seconds += t0.Seconds();
    t0.Restart();
    const int n = std::max(
        options.check_samples_per_side,
        static_cast<int>(std::ceil(
            std::sqrt(static_cast<double>(options.measure_samples) / nf))));
    std::vector<int> coarse, fine;
    for (int f = 0; f < nf; ++f) {
      if (records[f]->lattice != n) coarse.push_back(f);
    }
    cache.Measure(layout, coarse, records, n, /*fine=*/false);
    // Within on the coarse lattice but near a limit: the fine one decides.
    for (int f = 0; f < nf; ++f) {
      const FaceRecord& r = *records[f];
      const bool within = r.max_distance <= kTargetShare * tolerance &&
                          r.max_angle <= options.angle_degrees;
      if (within && !r.fine &&
          (r.max_distance > options.fine_share * tolerance ||
           r.max_angle > options.fine_share * options.angle_degrees)) {
        fine.push_back(f);
      }
    }
    cache.Measure(layout, fine, records, n, /*fine=*/true);
    result.measure_seconds += t0.Seconds();

    std::vector<int> cells;
    double max_distance = 0.0;
    for (int f = 0; f < nf; ++f) {
      const FaceRecord& r = *records[f];
      max_distance = std::max(max_distance, r.Distance());
      if (r.Distance() > kTargetShare * tolerance ||
          r.Angle() > options.angle_degrees) {
        cells.push_back(layout.face_cell[f]);
      }
    }
    if (options.progress) {
      // The share of the tolerance reached, never going back.
      progress = std::max(progress, std::min(1.0, tolerance / max_distance));
      options.progress("round " + std::to_string(round) + ", " +
                           std::to_string(nf) + " patches",
                       progress);
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    std::string stop;
    if (cells.empty()) {
      stop = "tolerance";  // within 95 % of it
    } else if (round >= options.max_rounds) {
      stop = "rounds";
    } else if (static_cast<int64_t>(nf) +
                   4 * static_cast<int64_t>(cells.size()) >
               options.max_faces) {
      stop = "patch budget";
    }
    if (stop.empty()) {
      topology.Refine(cells);
      continue;
    }
    SDCB_ASSIGN_OR_RETURN(const LayoutEdges edges, BuildEdges(layout));
    double squares = 0.0, area = 0.0, max_angle = 0.0;
    result.patches.resize(nf);
    result.face_max_distance_percent.resize(nf);
    result.face_max_normal_angle_degrees.resize(nf);
    result.measured_points = 0;
    result.fine_faces = 0;
    for (int f = 0; f < nf; ++f) {
      const FaceRecord& r = *records[f];
      result.patches[f] = r.patch;
      result.face_max_distance_percent[f] = r.Distance() * percent_per_unit;
      result.face_max_normal_angle_degrees[f] = r.Angle();
      squares += r.sum_squares;
      area += r.sum_area;
      max_angle = std::max(max_angle, r.Angle());
      result.measured_points += (n + 1) * (n + 1);
      if (r.fine) {
        result.measured_points += (3 * n + 1) * (3 * n + 1);
        ++result.fine_faces;
      }
    }
    result.layout = layout;
    result.max_distance_percent = max_distance * percent_per_unit;
    result.max_normal_angle_degrees = max_angle;
    result.rms_distance_percent =
        area > 0.0 ? std::sqrt(squares / area) * percent_per_unit : 0.0;
    result.max_normal_jump_degrees = MaxNormalJump(result.patches, edges, 32);
    result.rounds = round;
    result.within_tolerance =
        result.max_distance_percent <= options.tolerance_percent &&
        result.max_normal_angle_degrees <= options.angle_degrees;
    result.stop_reason = stop;
    return result;
  }
}

}  // namespace sdcb
