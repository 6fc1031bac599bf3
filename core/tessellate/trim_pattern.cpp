#include "sdcb/core/tessellate/trim_pattern.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/sphere/point_kd_tree.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/knot_hull.h"

namespace sdcb {
namespace {

// Icosahedron vertices nearer a trim than this (radians) are left out: they
// would make slivers against the trim.
constexpr double kClearance = 0.15;
// A loop's centre is added when it is at least this far (radians) from
// every trim side and added point.
constexpr double kCentreClearance = 1e-4;
// A side piece shorter than this (chord) that is still not an edge means
// another trim point lies on it, up to rounding.
constexpr double kShortestPiece = 1e-7;
constexpr int kMaxRounds = 40;

double Angle(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  return std::atan2(p.cross(q).norm(), p.dot(q));
}

// Angle from unit vector p to the shorter great-circle arc a -> b.
double AngleToArc(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                  const Eigen::Vector3d& b) {
  const Eigen::Vector3d n = a.cross(b).normalized();
  const Eigen::Vector3d q = p - n * p.dot(n);
  if (q.norm() > 0.0 && a.cross(q).dot(n) >= 0.0 && q.cross(b).dot(n) >= 0.0) {
    return std::asin(std::min(1.0, std::abs(p.dot(n))));
  }
  return std::min(Angle(p, a), Angle(p, b));
}

Status CheckLoops(const std::vector<TrimLoop>& loops) {
  if (loops.empty()) return InvalidArgumentError("no trim loops");
  for (size_t l = 0; l < loops.size(); ++l) {
    const Eigen::MatrixX3d& p = loops[l].points;
    const std::string name = "trim loop " + std::to_string(l + 1);
    if (p.rows() < 3) {
      return InvalidArgumentError(name + " has fewer than 3 points");
    }
    if (!AllUnitRows(p)) {
      return InvalidArgumentError(name + " has a point that is not a unit " +
                                  "vector");
    }
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      const Eigen::Vector3d a = p.row(i), b = p.row((i + 1) % p.rows());
      if (!(a.cross(b).norm() > 0.0)) {
        return InvalidArgumentError(name + " has two consecutive points " +
                                    "equal or antipodal");
      }
    }
  }
  return Status::Ok();
}

// Points graded away from each loop: rings of every 2nd, 4th, 8th ... trim
// point, each moved off the loop on both sides by half the ring's spacing
// (the local spacing of the loop times the step), until that reaches
// kClearance. Without them a dense loop (a scan's boundary) is triangulated
// by long slivers from its points to the far points, which the refinement
// then splits into a dense strip all the way along them. A ring point nearer
// than 0.6 of its offset to a trim point (a concave bend, another loop) is
// left out.
std::vector<Eigen::Vector3d> GradedPoints(
    const std::vector<TrimLoop>& loops,
    const std::vector<Eigen::Vector3d>& trim_points) {
  Eigen::MatrixX3d all(trim_points.size(), 3);
  for (size_t i = 0; i < trim_points.size(); ++i) {
    all.row(i) = trim_points[i].transpose();
  }
  const PointKdTree tree(all);
  std::vector<Eigen::Vector3d> out;
  int first = 0;
  for (const TrimLoop& loop : loops) {
    const int n = static_cast<int>(loop.points.rows());
    bool wide = false;
    for (int step = 2; !wide && 3 * step <= n; step *= 2) {
      for (int i = 0; i < n; i += step) {
        const Eigen::Vector3d& p = trim_points[first + i];
        const Eigen::Vector3d& prev = trim_points[first + (i + n - 1) % n];
        const Eigen::Vector3d& next = trim_points[first + (i + 1) % n];
        Eigen::Vector3d t = next - prev;
        t -= p * p.dot(t);
        if (!(t.norm() > 0.0)) continue;
        const Eigen::Vector3d left = p.cross(t.normalized());
        const double h = 0.5 * ((next - p).norm() + (p - prev).norm());
        const double offset = 0.5 * step * h;
        if (offset > kClearance) {
          wide = true;
          break;
        }
        for (const double side : {1.0, -1.0}) {
          const Eigen::Vector3d q =
              (p * std::cos(offset) + side * std::sin(offset) * left)
                  .normalized();
          const PointKdTree::Neighbor near = tree.Nearest(q);
          if (std::sqrt(near.squared_distance) >= 0.6 * offset) {
            out.push_back(q);
          }
        }
      }
    }
    first += n;
  }
  return out;
}

}  // namespace

StatusOr<SphereTriangulation> TrimmedPattern(
    const std::vector<TrimLoop>& loops) {
  SDCB_RETURN_IF_ERROR(CheckLoops(loops));
  std::vector<Eigen::Vector3d> points;
  std::vector<int> vertex_arc;
  // Per side: its vertices along the arc, from its start to its end.
  std::vector<std::vector<int>> chains;
  for (const TrimLoop& loop : loops) {
    const int first = static_cast<int>(points.size());
    const int n = static_cast<int>(loop.points.rows());
    for (int i = 0; i < n; ++i) {
      points.push_back(loop.points.row(i).transpose().normalized());
      vertex_arc.push_back(SphereTriangulation::kCornerVertex);
      chains.push_back({first + i, first + (i + 1) % n});
    }
  }
  const int trim_points = static_cast<int>(points.size());
  for (const Eigen::Vector3d& q : GradedPoints(loops, points)) {
    points.push_back(q);
    vertex_arc.push_back(SphereTriangulation::kFreeVertex);
  }
  const TriangleMesh ico = MakeIcosphere(1);
  for (Eigen::Index v = 0; v < ico.vertices.rows(); ++v) {
    const Eigen::Vector3d p = ico.vertices.row(v).transpose().normalized();
    bool clear = true;
    for (int s = 0; clear && s < trim_points; ++s) {
      clear = AngleToArc(p, points[chains[s][0]], points[chains[s][1]]) >=
              kClearance;
    }
    if (clear) {
      points.push_back(p);
      vertex_arc.push_back(SphereTriangulation::kFreeVertex);
    }
  }
  // Each loop's centre (its points' normalized mean) when it is at least
  // kCentreClearance from every trim side and added point: without it a
  // small loop's disk is triangulated by its own points alone (slivers
  // across it when they are nearly cocircular).
  for (size_t l = 0; l < loops.size(); ++l) {
    const Eigen::Vector3d c = loops[l].points.colwise().sum().transpose();
    if (!(c.norm() > 0.0)) continue;
    const Eigen::Vector3d p = c.normalized();
    double clearance = kClearance;
    for (int s = 0; s < trim_points; ++s) {
      clearance = std::min(
          clearance, AngleToArc(p, points[chains[s][0]], points[chains[s][1]]));
    }
    for (size_t q = trim_points; q < points.size(); ++q) {
      clearance = std::min(clearance, Angle(p, points[q]));
    }
    if (clearance >= kCentreClearance) {
      points.push_back(p);
      vertex_arc.push_back(SphereTriangulation::kFreeVertex);
    }
  }
  const size_t max_points = 16 * points.size() + 100000;
  KnotHull hull;
  for (int round = 0;; ++round) {
    Eigen::MatrixX3d matrix(points.size(), 3);
    for (size_t i = 0; i < points.size(); ++i) {
      matrix.row(i) = points[i].transpose();
    }
    StatusOr<KnotHull> computed = ComputeKnotHull(matrix);
    if (!computed.ok()) {
      return InvalidInputError(
          "trim points lie too close together to triangulate (" +
          computed.status().message() + ")");
    }
    hull = std::move(computed).value();
    bool conforming = true;
    for (int s = 0; s < trim_points; ++s) {
      std::vector<int>& chain = chains[s];
      std::vector<int> refined = {chain[0]};
      for (size_t i = 0; i + 1 < chain.size(); ++i) {
        const int u = chain[i], v = chain[i + 1];
        const std::vector<int>& near = hull.neighbors[u];
        if (!std::binary_search(near.begin(), near.end(), v)) {
          conforming = false;
          if ((points[u] - points[v]).norm() < kShortestPiece ||
              round == kMaxRounds || points.size() >= max_points) {
            return InvalidInputError(
                "trim side " + std::to_string(s + 1) +
                " cannot be made an edge of the tessellation: another trim "
                "point lies on it or within rounding of it");
          }
          refined.push_back(static_cast<int>(points.size()));
          points.push_back((points[u] + points[v]).normalized());
          vertex_arc.push_back(s);
        }
        refined.push_back(v);
      }
      chain = std::move(refined);
    }
    if (conforming) break;
  }
  Eigen::MatrixX3d directions(points.size(), 3);
  for (size_t i = 0; i < points.size(); ++i) {
    directions.row(i) = points[i].transpose();
  }
  Eigen::MatrixX3i faces(hull.facets.size(), 3);
  for (size_t f = 0; f < hull.facets.size(); ++f) {
    const auto& t = hull.facets[f];
    // A facet whose plane does not pass the origin on its inner side would
    // not be a spherical triangle (the points all in a half-space).
    if (Det3Sign(points[t[0]], points[t[1]], points[t[2]]) <= 0) {
      return InvalidInputError(
          "the trim points do not surround the sphere's centre; "
          "the trimmed pattern has a degenerate face");
    }
    faces.row(f) << t[0], t[1], t[2];
  }
  SDCB_ASSIGN_OR_RETURN(SphereTriangulation pattern,
                        SphereTriangulation::FromFaces(directions, faces));
  std::vector<std::array<int, 2>> arc_ends(trim_points);
  for (int s = 0; s < trim_points; ++s) {
    arc_ends[s] = {chains[s].front(), chains[s].back()};
  }
  pattern.SetFeatures(std::move(arc_ends), std::move(vertex_arc));
  return pattern;
}

StatusOr<std::vector<char>> KeptFaceSlots(const SphereTriangulation& pattern) {
  const int nf = pattern.num_face_slots();
  // Per slot: -1 undecided, 0 removed, 1 kept; and its region's seed.
  std::vector<int> region(nf, -1);
  std::vector<char> kept(nf, 0);
  std::vector<int> stack;
  for (int start = 0; start < nf; ++start) {
    if (!pattern.alive(start) || region[start] >= 0) continue;
    // Flood the region across non-arc edges, collecting its arc sides.
    int side = -1;
    std::vector<int> members;
    stack.assign(1, start);
    region[start] = start;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      members.push_back(f);
      for (int e = 0; e < 3; ++e) {
        const int h = 3 * f + e;
        const int a = pattern.Origin(h), b = pattern.Target(h);
        const int arc = pattern.EdgeArc(a, b);
        if (arc < 0) {
          const int g = pattern.Twin(h) / 3;
          if (region[g] < 0) {
            region[g] = start;
            stack.push_back(g);
          }
          continue;
        }
        // Along the arc's circle, a -> b runs forward iff it moves toward
        // the arc's end: (b - a) . (end - start) > 0 for points of an arc
        // shorter than pi.
        const auto& ends = pattern.arc_ends()[arc];
        const Eigen::Vector3d along =
            pattern.vertex(ends[1]) - pattern.vertex(ends[0]);
        const int this_side =
            (pattern.vertex(b) - pattern.vertex(a)).dot(along) > 0.0 ? 1 : 0;
        if (side >= 0 && side != this_side) {
          return InvalidInputError(
              "the trim loops cross or are not oriented with the kept region "
              "on their left");
        }
        side = this_side;
      }
    }
    // A region without an arc (no trims at all) is kept.
    for (int f : members) kept[f] = side != 0;
  }
  return kept;
}

}  // namespace sdcb
