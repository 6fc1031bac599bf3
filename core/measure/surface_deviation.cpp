#include "sdcb/core/measure/surface_deviation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "sdcb/core/measure/closest_surface_points.h"
#include "sdcb/core/measure/sample_lattice.h"
#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/measure/triangle_distance.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/design_matrix.h"

namespace sdcb {
namespace {

// Lattice points are pulled toward their knot triangle's centroid by this
// (relative): see BuildLattice.
constexpr double kInset = 1e-6;
// A spline point farther than this times the distance to the lattice's image
// starts a closest-point search on the spline.
constexpr double kRefineRatio = 1.01;
// Points at or above this share of the largest distance are searched too.
constexpr double kSearchedShareOfMax = 0.5;
// The measurement evaluates the spline through its polynomials when it has
// at least this many points to evaluate per control point
// (MakeSplineSampler).
constexpr double kPolynomialPointsPerControlPoint = 32;
// The mesh's side is split for at most this many times the samples asked.
constexpr int64_t kMaxSampleRatio = 8;
// The mesh -> surface maximum is refined until no piece of the mesh can hold
// a distance more than this (relative) above it, in at most kMaxBoundRounds
// rounds that measure at most max(kMinBoundSamples, mesh samples /
// kBoundSampleDivisor) more points in all.
constexpr double kBoundTolerance = 0.01;
constexpr int kMaxBoundRounds = 40;
constexpr int64_t kMinBoundSamples = 10000;
constexpr int64_t kBoundSampleDivisor = 5;

// The lattice of level L over every knot triangle (TriangleLattice,
// counter-clockwise in (i, j), weights i / L of the second corner and j / L
// of the third): sphere points (one row per lattice vertex; vertices on
// shared edges appear once per triangle) and its triangles (three rows of
// `points` each).
struct Lattice {
  int level = 0;
  Eigen::MatrixX3d points;
  Eigen::MatrixX3i triangles;
  std::vector<int> knot_triangle;  // per point
};

Lattice BuildLattice(const Eigen::MatrixX3d& knots,
                     const DelaunayConfigurations& triangles, int level) {
  const TriangleLattice lattice(level, LatticeOrientation::kIJ);
  const int per_triangle_points = static_cast<int>(lattice.points.size());
  const int per_triangle_faces = static_cast<int>(lattice.triangles.size());
  const int n = static_cast<int>(triangles.sets.size());
  Lattice out;
  out.level = level;
  out.points.resize(static_cast<Eigen::Index>(n) * per_triangle_points, 3);
  out.triangles.resize(static_cast<Eigen::Index>(n) * per_triangle_faces, 3);
  out.knot_triangle.resize(out.points.rows());
  for (int t = 0; t < n; ++t) {
    const ConfigurationSet& set = triangles.sets[t];
    // Counter-clockwise seen from outside, as the sphere's orientation.
    const Eigen::Vector3d a = knots.row(set.knots[0]);
    Eigen::Vector3d b = knots.row(set.knots[1]);
    Eigen::Vector3d c = knots.row(set.knots[2]);
    if (Det3Sign(a, b, c) < 0) std::swap(b, c);
    const Eigen::Index base =
        static_cast<Eigen::Index>(t) * per_triangle_points;
    for (int k = 0; k < per_triangle_points; ++k) {
      const int i = lattice.points[k][0], j = lattice.points[k][1];
      // Pulled toward the centroid by kInset (relative): no sample lies
      // exactly on a knot or on the great circle through two knots, where
      // the basis's exact predicates would need exact arithmetic; the
      // images of neighbouring knot triangles still meet within ~1e-6.
      const double wb = kInset + (1.0 - 3.0 * kInset) * i / level;
      const double wc = kInset + (1.0 - 3.0 * kInset) * j / level;
      out.points.row(base + k) =
          ((1.0 - wb - wc) * a + wb * b + wc * c).normalized().transpose();
      out.knot_triangle[base + k] = t;
    }
    const Eigen::Index face = static_cast<Eigen::Index>(t) * per_triangle_faces;
    for (int f = 0; f < per_triangle_faces; ++f) {
      out.triangles.row(face + f) =
          (lattice.triangles[f].array() + static_cast<int>(base))
              .matrix()
              .transpose();
    }
  }
  return out;
}

// Fails where F is not finite at the points [begin, end): where I = sum B_i
// is 0 (outside every basis support: a hole the basis's sampled coverage
// check missed) the surface is 0 / 0.
Status CheckDefined(const Eigen::MatrixX3d& points,
                    const Eigen::MatrixX3d& image, Eigen::Index begin,
                    Eigen::Index end) {
  for (Eigen::Index i = begin; i < end; ++i) {
    if (image.row(i).allFinite()) continue;
    const Eigen::RowVector3d p = points.row(i);
    return InvalidInputError(
        "the surface is undefined near (" + std::to_string(p.x()) + ", " +
        std::to_string(p.y()) + ", " + std::to_string(p.z()) +
        "): I = sum B_i = 0 there, a hole between the basis supports");
  }
  return Status::Ok();
}

// Adds a third of the area of each image triangle in [begin, end) (rows of
// `triangles` over the points `image`) to its vertices' weights, and its
// area-weighted normal to their normals.
void AddImageAreasAndNormals(const Eigen::MatrixX3d& image,
                             const Eigen::MatrixX3i& triangles,
                             Eigen::Index begin, Eigen::Index end,
                             Eigen::VectorXd* weight,
                             Eigen::MatrixX3d* normal) {
  for (Eigen::Index f = begin; f < end; ++f) {
    const Eigen::Vector3d a = image.row(triangles(f, 0));
    const Eigen::Vector3d b = image.row(triangles(f, 1));
    const Eigen::Vector3d c = image.row(triangles(f, 2));
    const Eigen::Vector3d n = 0.5 * (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) {
      (*weight)[triangles(f, k)] += n.norm() / 3;
      normal->row(triangles(f, k)) += n.transpose();
    }
  }
}

// Surface -> mesh at surface sample i of `out` (its sphere point and F
// there set): its distance to the mesh, closest point and triangle; returns
// whether it is folded. The lattice's normal (`lattice_normal`) is only a
// hint where it is coarse: a suspected fold is confirmed with the spline's
// own normal. The search starts from the closest point `near` (a lattice
// neighbour's, or this sample's before the surface moved) when it has one
// (face >= 0).
bool MeasureSurfaceSample(const SurfaceSampler& evaluator,
                          const MeshDistance& to_mesh, double to_percent,
                          const Eigen::Vector3d& lattice_normal,
                          const MeshDistance::Closest& near, Eigen::Index i,
                          SurfaceDeviation* out) {
  if (!out->surface_sample_kept.empty() && !out->surface_sample_kept[i]) {
    // Outside the kept region: not measured.
    out->surface_sample_distance_percent[i] = 0;
    out->surface_sample_mesh_face[i] = -1;
    out->surface_sample_mesh_point.row(i) =
        out->surface_sample_positions.row(i);
    return false;
  }
  const Eigen::Vector3d position =
      out->surface_sample_positions.row(i).transpose();
  const MeshDistance::Closest c = near.face >= 0
                                      ? to_mesh.FindNear(position, near)
                                      : to_mesh.Find(position);
  out->surface_sample_distance_percent[i] = to_percent * c.distance;
  out->surface_sample_mesh_face[i] = c.face;
  out->surface_sample_mesh_point.row(i) = c.point.transpose();
  return to_mesh.Opposes(c, lattice_normal) &&
         to_mesh.Opposes(c, evaluator.EvaluateNormal(
                                out->surface_sample_points.row(i).transpose()));
}

// The surface -> mesh figures of `out` from its samples' distances, weights
// and folds.
void SummarizeSurfaceToMesh(SurfaceDeviation* out) {
  double area = 0, sum_squares = 0, folded_area = 0, max = 0;
  const Eigen::VectorXd& weight = out->surface_sample_weight;
  const std::vector<bool>& kept = out->surface_sample_kept;
  for (Eigen::Index i = 0; i < weight.size(); ++i) {
    if (!kept.empty() && !kept[i]) continue;
    const double d = out->surface_sample_distance_percent[i];
    area += weight[i];
    sum_squares += weight[i] * d * d;
    if (out->surface_sample_folded[i]) folded_area += weight[i];
    max = std::max(max, d);
  }
  out->surface_area = area;
  out->surface_to_mesh_max_percent = max;
  out->surface_to_mesh_rms_percent =
      area > 0 ? std::sqrt(sum_squares / area) : 0;
  out->folded_area_percent = area > 0 ? 100.0 * folded_area / area : 0;
}

// The distance from points of the mesh to the spline (length units), each
// the distance to a point of the spline found (never below the true one).
struct SplineDistance {
  const SphericalSpline& surface;   // its basis orders the points
  const SurfaceSampler& evaluator;  // evaluates
  const Lattice& lattice;
  const TriangleMesh& image;  // F at the lattice's points
  const MeshDistance& to_image;
  const DeviationOptions& options;

  // For points[first..]: first the spline point of the lattice image's
  // closest point (or candidates' row, when closer), then Gauss-Newton
  // steps on the spline where that is farther than the image suggests and,
  // with `floor_weights` (area weights of those points), at or above the
  // weighted rms of those first distances. Adds the searched points to
  // `searched`.
  std::vector<double> Distances(const std::vector<Eigen::Vector3d>& points,
                                size_t first,
                                const Eigen::MatrixX3d* candidates,
                                const Eigen::VectorXd* floor_weights,
                                int64_t* searched) const {
    const Eigen::Index n = static_cast<Eigen::Index>(points.size() - first);
    // The sphere points, then the spline there in the basis's locality
    // order (several times faster than point order; each result the same).
    Eigen::MatrixX3d start(n, 3);
    Eigen::VectorXd image_distance(n);
    tbb::parallel_for(
        tbb::blocked_range<Eigen::Index>(0, n, 64),
        [&](const tbb::blocked_range<Eigen::Index>& range) {
          for (Eigen::Index i = range.begin(); i < range.end(); ++i) {
            const MeshDistance::Closest c = to_image.Find(points[first + i]);
            const Eigen::Vector3d bary = ClampedTriangleCoordinates(
                c.point, image.vertices.row(lattice.triangles(c.face, 0)),
                image.vertices.row(lattice.triangles(c.face, 1)),
                image.vertices.row(lattice.triangles(c.face, 2)));
            Eigen::Vector3d p = Eigen::Vector3d::Zero();
            for (int k = 0; k < 3; ++k) {
              p += bary[k] *
                   lattice.points.row(lattice.triangles(c.face, k)).transpose();
            }
            start.row(i) = p.normalized().transpose();
            image_distance[i] = c.distance;
          }
        });
    Eigen::VectorXd distance(n);
    surface.basis().ParallelForEachPoint(start, [&](Eigen::Index i) {
      const Eigen::Vector3d& x = points[first + i];
      double d = (evaluator.Evaluate(start.row(i).transpose()) - x).norm();
      const Eigen::Index row = static_cast<Eigen::Index>(first) + i;
      if (candidates && row < candidates->rows()) {
        d = std::min(d, (candidates->row(row).transpose() - x).norm());
      }
      distance[i] = d;
    });
    const double floor =
        floor_weights ? std::sqrt(floor_weights->dot(distance.cwiseAbs2()) /
                                  std::max(floor_weights->sum(), 1e-300))
                      : 0.0;
    // Beyond the rule above, the points near the largest distance are
    // searched whatever the image says (again, until the largest is a
    // searched one): where the lattice's image cuts across a tight fillet,
    // the image and its spline point are both far from a mesh point that
    // lies on the spline.
    std::vector<char> refined(n, 0);
    const auto search = [&](Eigen::Index i) {
      distance[i] = std::min(
          distance[i], ClosestSurfacePoint(evaluator, points[first + i],
                                           start.row(i).transpose(),
                                           options.closest_point_iterations));
      refined[i] = 1;
    };
    surface.basis().ParallelForEachPoint(start, [&](Eigen::Index i) {
      const double d = distance[i];
      if (d >= floor &&
          d > kRefineRatio * image_distance[i] + 1e-9 * options.length_unit) {
        search(i);
      }
    });
    while (n > 0) {
      Eigen::Index largest;
      const double top = kSearchedShareOfMax * distance.maxCoeff(&largest);
      if (refined[largest]) break;
      surface.basis().ParallelForEachPoint(start, [&](Eigen::Index i) {
        if (!refined[i] && distance[i] >= top) search(i);
      });
    }
    for (char r : refined) *searched += r;
    return std::vector<double>(distance.data(), distance.data() + n);
  }
};

// The mesh's side as pieces, triangles of points of the mesh that cover it
// exactly, with the distance to the spline at every point.
class MeshSamples {
 public:
  explicit MeshSamples(const TriangleMesh& pieces) {
    points.resize(static_cast<size_t>(pieces.vertices.rows()));
    for (Eigen::Index i = 0; i < pieces.vertices.rows(); ++i) {
      points[static_cast<size_t>(i)] = pieces.vertices.row(i).transpose();
    }
    distance.assign(points.size(), 0.0);
    pieces_.resize(static_cast<size_t>(pieces.faces.rows()));
    radius_.resize(pieces_.size());
    for (size_t f = 0; f < pieces_.size(); ++f) {
      pieces_[f] = pieces.faces.row(static_cast<Eigen::Index>(f)).transpose();
      radius_[f] = Radius(pieces_[f]);
    }
  }

  Eigen::Index num_points() const {
    return static_cast<Eigen::Index>(points.size());
  }

  // The points and the pieces as a mesh (the same surface as the input's).
  TriangleMesh AsMesh() const {
    TriangleMesh out;
    out.vertices.resize(num_points(), 3);
    for (Eigen::Index i = 0; i < num_points(); ++i) {
      out.vertices.row(i) = points[static_cast<size_t>(i)].transpose();
    }
    out.faces.resize(static_cast<Eigen::Index>(pieces_.size()), 3);
    for (size_t f = 0; f < pieces_.size(); ++f) {
      out.faces.row(static_cast<Eigen::Index>(f)) = pieces_[f].transpose();
    }
    return out;
  }

  // The largest distance to the spline that a point of the piece can have.
  double Bound(size_t f) const {
    const Eigen::Vector3i& t = pieces_[f];
    return std::max({distance[t[0]], distance[t[1]], distance[t[2]]}) +
           radius_[f];
  }
  double MaxBound() const {
    double bound = 0.0;
    for (size_t f = 0; f < pieces_.size(); ++f) {
      bound = std::max(bound, Bound(f));
    }
    return bound;
  }

  // Halves every piece whose bound exceeds `goal` at its longest edge (one
  // new point per edge, shared by the pieces that halve it), the largest
  // bounds first while there are fewer than `max_points` points; the new
  // points' distances are to be appended. false when no piece is halved.
  bool HalvePiecesAbove(double goal, Eigen::Index max_points) {
    std::vector<std::pair<double, size_t>> above;
    for (size_t f = 0; f < pieces_.size(); ++f) {
      const double bound = Bound(f);
      if (bound > goal) above.emplace_back(-bound, f);
    }
    std::sort(above.begin(), above.end());
    const size_t room = static_cast<size_t>(
        std::max<Eigen::Index>(max_points - num_points(), 0));
    if (above.size() > room) above.resize(room);
    if (above.empty()) return false;
    for (const auto& [negative_bound, f] : above) {
      const Eigen::Vector3i t = pieces_[f];
      int longest = 0;
      for (int k = 1; k < 3; ++k) {
        if ((points[t[(k + 1) % 3]] - points[t[k]]).squaredNorm() >
            (points[t[(longest + 1) % 3]] - points[t[longest]]).squaredNorm()) {
          longest = k;
        }
      }
      const int a = t[longest], b = t[(longest + 1) % 3],
                c = t[(longest + 2) % 3];
      const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) |
                           static_cast<uint32_t>(std::max(a, b));
      const auto [it, inserted] =
          midpoint_.emplace(key, static_cast<int>(points.size()));
      if (inserted) points.push_back(0.5 * (points[a] + points[b]));
      const int m = it->second;
      pieces_[f] = Eigen::Vector3i(a, m, c);
      radius_[f] = Radius(pieces_[f]);
      pieces_.emplace_back(m, b, c);
      radius_.push_back(Radius(pieces_.back()));
    }
    return true;
  }

  std::vector<Eigen::Vector3d> points;
  std::vector<double> distance;  // length units, one per point

 private:
  double Radius(const Eigen::Vector3i& t) const {
    return CoveringRadius(points[t[0]], points[t[1]], points[t[2]]);
  }

  std::vector<Eigen::Vector3i> pieces_;
  std::vector<double> radius_;  // CoveringRadius of each piece
  std::unordered_map<uint64_t, int> midpoint_;
};

// The two-sided figures from the two halves: the root of the mean of the
// mean squares, and the larger maximum.
void CombineHalves(SurfaceDeviation* d) {
  d->rms_percent = std::sqrt(
      0.5 * (d->surface_to_mesh_rms_percent * d->surface_to_mesh_rms_percent +
             d->mesh_to_surface_rms_percent * d->mesh_to_surface_rms_percent));
  d->hausdorff_percent =
      std::max(d->surface_to_mesh_max_percent, d->mesh_to_surface_max_percent);
}

// kInvalidArgument for options and candidates that do not fit together.
Status CheckOptions(const TriangleMesh& mesh, const DeviationOptions& options,
                    const Eigen::MatrixX3d* vertex_candidates) {
  if (!(options.length_unit > 0) || !std::isfinite(options.length_unit) ||
      options.min_surface_samples < 1 || options.closest_point_iterations < 0 ||
      options.mesh_samples < 0) {
    return InvalidArgumentError(
        "surface deviation: the length unit must be > 0, the sample counts "
        ">= 1 (mesh samples >= 0) and the iterations >= 0");
  }
  if (!options.closest_points && options.mesh_to_surface &&
      options.mesh_samples > 0) {
    return InvalidArgumentError(
        "surface deviation: without closest points the mesh side is measured "
        "at the vertices' candidates only");
  }
  if ((vertex_candidates &&
       vertex_candidates->rows() != mesh.vertices.rows()) ||
      (!vertex_candidates && !options.closest_points &&
       options.mesh_to_surface)) {
    return InvalidArgumentError(
        "surface deviation: one candidate point per mesh vertex is needed");
  }
  return Status::Ok();
}

// The lattice level L: (L + 1)(L + 2) / 2 points per knot triangle >=
// samples / triangles.
int LatticeLevel(const DelaunayConfigurations& knot_triangles,
                 const DeviationOptions& options) {
  const double triangles = static_cast<double>(knot_triangles.sets.size());
  int level = 1;
  while (TriangleLattice::NumPoints(level) * triangles <
         options.min_surface_samples) {
    ++level;
  }
  return level;
}

// Whether the measurement evaluates the spline through its polynomials:
// when the points to evaluate (the `lattice_points`, and a Gauss-Newton
// search: ~8 per mesh point) are many per control point, each region is
// built once for several points. Whole measurements on 2 cores, through the
// basis / the polynomials: bunny00's final one in its fit (~84 per control
// point) 1.94 / 1.18 s; `sdcb compare` on CGAL's dino (16K control points,
// every mesh point searched, ~61) 3.2 / 2.4 s; the dino fit's measurements
// (its final one ~13, a round's lattice ~2) 3.7 / 10.0 s.
bool ThroughPolynomials(const SphericalSpline& surface,
                        const TriangleMesh& mesh,
                        const DeviationOptions& options,
                        Eigen::Index lattice_points) {
  const double mesh_points =
      options.mesh_to_surface && options.closest_points
          ? static_cast<double>(
                std::max<int64_t>(mesh.vertices.rows(), options.mesh_samples))
          : 0.0;
  const double points = static_cast<double>(lattice_points) +
                        mesh_points * (options.search_all_vertices ? 8 : 1);
  return points >= kPolynomialPointsPerControlPoint *
                       static_cast<double>(surface.basis().size());
}

// Surface -> mesh at the lattice vertices (their images `image`), with
// folds: the surface sample fields and figures of `out`.
void MeasureSurfaceSide(const SurfaceSampler& evaluator,
                        const MeshDistance& to_mesh,
                        const DeviationOptions& options, const Lattice& lattice,
                        const TriangleMesh& image, SurfaceDeviation* out) {
  const Eigen::Index ns = lattice.points.rows();
  const double to_percent = 100.0 / options.length_unit;
  // Area and normal of the image around each lattice vertex: a third of the
  // area of each of its lattice triangles, the area-weighted normals summed.
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(ns);
  Eigen::MatrixX3d normal = Eigen::MatrixX3d::Zero(ns, 3);
  AddImageAreasAndNormals(image.vertices, lattice.triangles, 0,
                          lattice.triangles.rows(), &weight, &normal);
  out->lattice_level = lattice.level;
  out->surface_samples = ns;
  out->surface_sample_points = lattice.points;
  out->surface_sample_positions = image.vertices;
  out->surface_sample_triangles = lattice.triangles;
  out->surface_sample_knot_triangle = lattice.knot_triangle;
  out->surface_sample_distance_percent.resize(ns);
  out->surface_sample_mesh_face.resize(ns);
  out->surface_sample_mesh_point.resize(ns, 3);
  out->surface_sample_weight = std::move(weight);
  if (options.region != nullptr && !options.region->empty()) {
    std::vector<char> kept(ns, 0);
    tbb::parallel_for(
        tbb::blocked_range<Eigen::Index>(0, ns, 1024),
        [&](const tbb::blocked_range<Eigen::Index>& range) {
          for (Eigen::Index i = range.begin(); i < range.end(); ++i) {
            kept[i] =
                options.region->Contains(lattice.points.row(i).transpose());
          }
        });
    out->surface_sample_kept.assign(kept.begin(), kept.end());
  }
  // Knot triangle by knot triangle (blocks of the lattice), each sample's
  // search started from the previous one's closest point.
  const Eigen::Index per_triangle_points =
      TriangleLattice::NumPoints(lattice.level);
  std::vector<char> folded(ns, 0);
  tbb::parallel_for(
      tbb::blocked_range<Eigen::Index>(0, ns / per_triangle_points, 4),
      [&](const tbb::blocked_range<Eigen::Index>& range) {
        for (Eigen::Index t = range.begin(); t < range.end(); ++t) {
          MeshDistance::Closest near;
          for (Eigen::Index i = t * per_triangle_points;
               i < (t + 1) * per_triangle_points; ++i) {
            folded[i] =
                MeasureSurfaceSample(evaluator, to_mesh, to_percent,
                                     normal.row(i).transpose(), near, i, out);
            near.face = out->surface_sample_mesh_face[i];
            near.point = out->surface_sample_mesh_point.row(i).transpose();
          }
        }
      });
  out->surface_sample_folded.assign(folded.begin(), folded.end());
  SummarizeSurfaceToMesh(out);
}

// With mesh_samples: the mesh split until its edges are no longer than the
// spacing of that many points spread evenly over it (its first rows are the
// mesh's vertices); a mesh of long needles would ask for many more: then the
// spacing doubles until it has at most kMaxSampleRatio times as many. Sets
// `*spacing_percent`. Without: nothing (the mesh's vertices are the
// samples).
std::optional<TriangleMesh> SplitForSamples(const TriangleMesh& mesh,
                                            const DeviationOptions& options,
                                            double* spacing_percent) {
  std::optional<TriangleMesh> split;
  if (options.mesh_samples <= 0) return split;
  const double area = VertexAreas(mesh).sum();
  double spacing = SplitEdgeLengthFor(area, options.mesh_samples);
  while (!(split = SplitToEdgeLength(
               mesh, spacing,
               std::max<int64_t>(mesh.vertices.rows(),
                                 kMaxSampleRatio * options.mesh_samples)))) {
    spacing *= 2;
  }
  *spacing_percent = 100.0 / options.length_unit * spacing;
  return split;
}

// Mesh -> surface at the points of `samples` (the vertices of
// `sample_mesh`), by closest points on the spline; with mesh_samples, pieces
// are then halved where their bound asks for it (see the header).
void MeasureMeshSide(const SplineDistance& to_spline,
                     const TriangleMesh& sample_mesh,
                     const DeviationOptions& options,
                     const Eigen::MatrixX3d* vertex_candidates,
                     MeshSamples* samples, SurfaceDeviation* out) {
  // Unless all are searched, a search on the spline only from a point at
  // or above the mesh -> surface rms of the first distances (below it a
  // point barely moves the rms and cannot hold the maximum).
  const Eigen::VectorXd first_weights = VertexAreas(sample_mesh);
  samples->distance = to_spline.Distances(
      samples->points, 0, vertex_candidates,
      options.search_all_vertices ? nullptr : &first_weights,
      &out->refined_vertices);
  // Where the bound of a piece exceeds the largest distance found by more
  // than kBoundTolerance, the piece is halved and its new point measured,
  // until none does (or the budget of points is spent): the maximum then
  // holds within that of an upper bound of the true one.
  if (options.mesh_samples <= 0) return;
  const int64_t budget = std::max<int64_t>(
      kMinBoundSamples, options.mesh_samples / kBoundSampleDivisor);
  for (int round = 0; round < kMaxBoundRounds; ++round) {
    const double goal =
        (1.0 + kBoundTolerance) *
        *std::max_element(samples->distance.begin(), samples->distance.end());
    const Eigen::Index before = samples->num_points();
    if (!samples->HalvePiecesAbove(goal,
                                   before + budget - out->mesh_bound_samples)) {
      break;
    }
    out->mesh_bound_samples += samples->num_points() - before;
    const std::vector<double> added = to_spline.Distances(
        samples->points, before, nullptr, nullptr, &out->refined_vertices);
    samples->distance.insert(samples->distance.end(), added.begin(),
                             added.end());
  }
}

// The mesh -> surface fields and figures of `out` from the measured
// `samples` (the first `mesh_vertices` the mesh's vertices), and the
// two-sided ones.
void SummarizeMeshToSurface(const MeshSamples& samples,
                            Eigen::Index mesh_vertices, double to_percent,
                            SurfaceDeviation* out) {
  const TriangleMesh pieces = samples.AsMesh();
  const Eigen::VectorXd weights = VertexAreas(pieces);
  const Eigen::Map<const Eigen::VectorXd> distance(
      samples.distance.data(),
      static_cast<Eigen::Index>(samples.distance.size()));
  out->mesh_samples = samples.num_points();
  out->vertex_distance_percent = to_percent * distance.head(mesh_vertices);
  out->mesh_sample_points = pieces.vertices;
  out->mesh_sample_distance_percent = to_percent * distance;
  out->mesh_sample_weight = weights;
  const double mesh_area = weights.sum();
  out->mesh_to_surface_rms_percent =
      mesh_area > 0 ? to_percent * std::sqrt(weights.dot(distance.cwiseAbs2()) /
                                             mesh_area)
                    : 0;
  out->mesh_to_surface_max_percent =
      out->mesh_samples > 0 ? to_percent * distance.maxCoeff() : 0;
  out->mesh_to_surface_max_bound_percent = to_percent * samples.MaxBound();
  CombineHalves(out);
}

}  // namespace

void SetMeshToSurface(const Eigen::VectorXd& distance_percent,
                      const Eigen::VectorXd& weights, SurfaceDeviation* d) {
  const double area = weights.sum();
  d->mesh_samples = distance_percent.size();
  d->vertex_distance_percent.resize(0);
  d->mesh_sample_points.resize(0, 3);
  d->mesh_sample_distance_percent.resize(0);
  d->mesh_sample_weight.resize(0);
  d->mesh_to_surface_max_bound_percent = 0;
  d->mesh_sample_spacing_percent = 0;
  d->mesh_to_surface_rms_percent =
      area > 0 ? std::sqrt(weights.dot(distance_percent.cwiseAbs2()) / area)
               : 0;
  // A sample of no area (an open part's fill, which is not measured) does
  // not count in the maximum either.
  double max = 0;
  for (Eigen::Index i = 0; i < distance_percent.size(); ++i) {
    if (weights[i] > 0) max = std::max(max, distance_percent[i]);
  }
  d->mesh_to_surface_max_percent = max;
  CombineHalves(d);
}

StatusOr<SurfaceDeviation> MeasureSurfaceDeviation(
    const SphericalSpline& surface, const TriangleMesh& mesh,
    const DeviationOptions& options, const Eigen::MatrixX3d* vertex_candidates,
    const MeshDistance* mesh_distance) {
  SDCB_RETURN_IF_ERROR(CheckOptions(mesh, options, vertex_candidates));
  std::optional<MeshDistance> own_distance;
  if (mesh_distance == nullptr) {
    SDCB_ASSIGN_OR_RETURN(own_distance, MeshDistance::Create(mesh));
    mesh_distance = &*own_distance;
  }
  SDCB_ASSIGN_OR_RETURN(const DelaunayConfigurations knot_triangles,
                        ComputeDelaunayConfigurations(surface.knots(), 0));
  const int level = LatticeLevel(knot_triangles, options);
  const Lattice lattice = BuildLattice(surface.knots(), knot_triangles, level);
  const Eigen::Index ns = lattice.points.rows();
  const std::unique_ptr<SurfaceSampler> evaluator = MakeSplineSampler(
      surface, ThroughPolynomials(surface, mesh, options, ns));

  // The lattice's image: F at every lattice vertex.
  TriangleMesh image;
  evaluator->Sample(lattice.points, &image.vertices, nullptr);
  image.faces = lattice.triangles;
  SDCB_RETURN_IF_ERROR(CheckDefined(lattice.points, image.vertices, 0, ns));

  // The image's own AABB tree (for mesh -> surface) is built meanwhile: its
  // construction is sequential.
  std::optional<StatusOr<MeshDistance>> image_distance_or;
  tbb::task_group image_tree;
  if (options.closest_points && options.mesh_to_surface) {
    image_tree.run(
        [&] { image_distance_or.emplace(MeshDistance::Create(image)); });
  }
  SurfaceDeviation out;
  MeasureSurfaceSide(*evaluator, *mesh_distance, options, lattice, image, &out);
  image_tree.wait();
  if (!options.mesh_to_surface) {
    out.rms_percent = out.surface_to_mesh_rms_percent;
    out.hausdorff_percent = out.surface_to_mesh_max_percent;
    return out;
  }

  const std::optional<TriangleMesh> split =
      SplitForSamples(mesh, options, &out.mesh_sample_spacing_percent);
  MeshSamples samples(split ? *split : mesh);
  if (!options.closest_points) {
    for (Eigen::Index i = 0; i < samples.num_points(); ++i) {
      samples.distance[i] =
          (vertex_candidates->row(i) - samples.points[i].transpose()).norm();
    }
  } else {
    SDCB_ASSIGN_OR_RETURN(const MeshDistance to_image,
                          std::move(*image_distance_or));
    const SplineDistance to_spline{surface, *evaluator, lattice,
                                   image,   to_image,   options};
    MeasureMeshSide(to_spline, split ? *split : mesh, options,
                    vertex_candidates, &samples, &out);
  }
  SummarizeMeshToSurface(samples, mesh.vertices.rows(),
                         100.0 / options.length_unit, &out);
  return out;
}

Status RemeasureSurfaceToMesh(const SphericalSpline& surface,
                              const MeshDistance& mesh_distance,
                              const DeviationOptions& options,
                              const DesignMatrix& lattice_values,
                              const std::vector<int>& changed,
                              SurfaceDeviation* deviation) {
  SurfaceDeviation& d = *deviation;
  const int level = d.lattice_level;
  const Eigen::Index per_triangle_points = TriangleLattice::NumPoints(level);
  const Eigen::Index per_triangle_faces = level * level;
  const Eigen::Index ns = d.surface_sample_points.rows();
  if (options.mesh_to_surface || level < 1 || ns == 0 ||
      ns % per_triangle_points != 0 ||
      d.surface_sample_triangles.rows() !=
          ns / per_triangle_points * per_triangle_faces ||
      d.surface_sample_weight.size() != ns ||
      static_cast<Eigen::Index>(d.surface_sample_folded.size()) != ns) {
    return InvalidArgumentError(
        "surface deviation: a surface -> mesh measurement is needed to "
        "measure again");
  }
  const Eigen::Index m = surface.basis().size();
  if (lattice_values.rows() != ns || lattice_values.cols() != m) {
    return InvalidArgumentError(
        "surface deviation: the basis values are not the lattice's");
  }
  std::vector<char> is_changed(m, 0);
  for (const int j : changed) {
    if (j < 0 || j >= m) {
      return InvalidArgumentError(
          "surface deviation: a changed control point is out of range");
    }
    is_changed[j] = 1;
  }
  // The knot triangles (blocks of the lattice) with a sample that a changed
  // basis function reaches.
  const Eigen::Index triangles = ns / per_triangle_points;
  std::vector<Eigen::Index> touched;
  for (Eigen::Index t = 0; t < triangles; ++t) {
    bool reached = false;
    for (Eigen::Index i = t * per_triangle_points;
         i < (t + 1) * per_triangle_points && !reached; ++i) {
      for (DesignMatrix::InnerIterator e(lattice_values, i); e; ++e) {
        if (is_changed[e.col()]) {
          reached = true;
          break;
        }
      }
    }
    if (reached) touched.push_back(t);
  }

  const SplineSampler evaluator(surface);
  const double to_percent = 100.0 / options.length_unit;
  std::vector<char> folded(ns, 0);
  Eigen::MatrixX3d normal = Eigen::MatrixX3d::Zero(ns, 3);
  std::vector<Status> failed(touched.size());
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, touched.size(), 4),
      [&](const tbb::blocked_range<size_t>& range) {
        for (size_t k = range.begin(); k < range.end(); ++k) {
          const Eigen::Index begin = touched[k] * per_triangle_points;
          const Eigen::Index end = begin + per_triangle_points;
          d.surface_sample_positions.middleRows(begin, per_triangle_points) =
              lattice_values.middleRows(begin, per_triangle_points) *
              surface.control_points();
          failed[k] = CheckDefined(d.surface_sample_points,
                                   d.surface_sample_positions, begin, end);
          if (!failed[k].ok()) continue;
          d.surface_sample_weight.segment(begin, per_triangle_points).setZero();
          const Eigen::Index face = touched[k] * per_triangle_faces;
          AddImageAreasAndNormals(
              d.surface_sample_positions, d.surface_sample_triangles, face,
              face + per_triangle_faces, &d.surface_sample_weight, &normal);
          for (Eigen::Index i = begin; i < end; ++i) {
            MeshDistance::Closest before;
            before.face = d.surface_sample_mesh_face[i];
            before.point = d.surface_sample_mesh_point.row(i).transpose();
            folded[i] =
                MeasureSurfaceSample(evaluator, mesh_distance, to_percent,
                                     normal.row(i).transpose(), before, i, &d);
          }
        }
      });
  for (const Status& status : failed) SDCB_RETURN_IF_ERROR(status);
  for (const Eigen::Index t : touched) {
    for (Eigen::Index i = t * per_triangle_points;
         i < (t + 1) * per_triangle_points; ++i) {
      d.surface_sample_folded[i] = folded[i] != 0;
    }
  }
  SummarizeSurfaceToMesh(&d);
  d.rms_percent = d.surface_to_mesh_rms_percent;
  d.hausdorff_percent = d.surface_to_mesh_max_percent;
  return Status::Ok();
}

}  // namespace sdcb
