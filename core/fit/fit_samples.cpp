#include "sdcb/core/fit/fit_samples.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <mutex>

#include "sdcb/core/sphere/point_kd_tree.h"

namespace sdcb {

Eigen::VectorXd KnotSpacing(const Eigen::MatrixX3d& knots) {
  const PointKdTree tree(knots);
  Eigen::VectorXd spacing(knots.rows());
  for (Eigen::Index k = 0; k < knots.rows(); ++k) {
    const PointKdTree::Neighbor n = tree.Nearest(
        knots.row(k).transpose(), std::numeric_limits<double>::infinity(),
        static_cast<int>(k));
    spacing[k] = std::sqrt(n.squared_distance);
  }
  return spacing;
}

namespace {

// The factor on face f's area (FitSampleOptions::face_weights).
double FaceWeight(const FitSampleOptions& options, Eigen::Index f) {
  return options.face_weights ? (*options.face_weights)[f] : 1.0;
}

// A sub-triangle of a mesh triangle in barycentric coordinates (weights of
// corners 1 and 2; corner 0 gets the rest). Dyadic values: exact doubles.
struct Sub {
  Eigen::Vector2d v[3];
};

Eigen::Vector3d OnSphere(const Eigen::Vector2d& b, const Eigen::Vector3d s[3]) {
  return ((1.0 - b[0] - b[1]) * s[0] + b[0] * s[1] + b[1] * s[2]).normalized();
}

// Splits `t` by longest-edge bisection (lengths measured on the sphere)
// until every edge is at most `length(centroid)`; appends the leaves, each
// taking one from `*budget`. Returns false, early, when the budget runs out.
template <typename Length>
bool Bisect(const Sub& t, const Eigen::Vector3d s[3], const Length& length,
            int depth, int64_t* budget, std::vector<Sub>* leaves) {
  double longest = 0;
  int edge = 0;
  for (int e = 0; e < 3; ++e) {
    const double l =
        (OnSphere(t.v[(e + 1) % 3], s) - OnSphere(t.v[e], s)).norm();
    if (l > longest) {
      longest = l;
      edge = e;
    }
  }
  if (depth == 0 ||
      longest <= length(OnSphere((t.v[0] + t.v[1] + t.v[2]) / 3.0, s))) {
    if (*budget <= 0) return false;
    --*budget;
    leaves->push_back(t);
    return true;
  }
  const Eigen::Vector2d mid = 0.5 * (t.v[edge] + t.v[(edge + 1) % 3]);
  const Eigen::Vector2d& opposite = t.v[(edge + 2) % 3];
  return Bisect(Sub{{t.v[edge], mid, opposite}}, s, length, depth - 1, budget,
                leaves) &&
         Bisect(Sub{{mid, t.v[(edge + 1) % 3], opposite}}, s, length, depth - 1,
                budget, leaves);
}

// A triangle that is split, with its pieces.
struct SplitFace {
  Eigen::Index face;
  std::vector<Sub> leaves;
};

// The triangles to split at `per_spacing` samples per knot spacing
// (`spacing`: per knot, `knot_tree`: the knots), in the order of their
// faces, each with its pieces; false when the pieces would exceed
// options.max_pieces (then `split_faces` is to be discarded). The triangles
// are split in parallel; the answer is that of a sequential pass (false iff
// the pieces of all triangles together exceed the budget), for any thread
// count.
bool SplitTriangles(const TriangleMesh& mesh, const Eigen::MatrixX3d& sphere,
                    const Eigen::VectorXd& spacing,
                    const PointKdTree& knot_tree, double per_spacing,
                    const FitSampleOptions& options,
                    std::vector<SplitFace>* split_faces) {
  const int64_t budget = options.max_pieces > 0
                             ? options.max_pieces
                             : std::numeric_limits<int64_t>::max();
  std::atomic<int64_t> pieces{0};
  std::atomic<bool> over{false};
  std::mutex append;
  split_faces->clear();
  // No sample spacing is shorter: a triangle whose edges are all within it
  // is not split, without asking for its nearest knot.
  const double shortest =
      spacing.size() > 0 ? spacing.minCoeff() / per_spacing : 0.0;
  tbb::parallel_for(
      tbb::blocked_range<Eigen::Index>(0, mesh.faces.rows(), 256),
      [&](const tbb::blocked_range<Eigen::Index>& range) {
        std::vector<SplitFace> found;
        // Consecutive triangles and pieces are mostly close: each query
        // starts from the last one's knot (the same answers).
        int hint = -1;
        for (Eigen::Index f = range.begin(); f < range.end(); ++f) {
          if (over.load(std::memory_order_relaxed)) break;
          const Eigen::Vector3d s[3] = {sphere.row(mesh.faces(f, 0)),
                                        sphere.row(mesh.faces(f, 1)),
                                        sphere.row(mesh.faces(f, 2))};
          const double longest =
              std::max({(s[1] - s[0]).norm(), (s[2] - s[1]).norm(),
                        (s[0] - s[2]).norm()});
          // The sample spacing at a point: the spacing of the knot nearest
          // to it over per_spacing.
          const auto length = [&](const Eigen::Vector3d& p) {
            const PointKdTree::Neighbor near = knot_tree.NearestNear(p, hint);
            hint = near.index;
            return near.index >= 0 ? spacing[near.index] / per_spacing
                                   : std::numeric_limits<double>::infinity();
          };
          if (longest <= shortest ||
              longest <= length((s[0] + s[1] + s[2]).normalized())) {
            continue;
          }
          const Sub whole{{Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0),
                           Eigen::Vector2d(0, 1)}};
          // One triangle alone may use the whole budget.
          int64_t own = budget;
          found.push_back({f, {}});
          std::vector<Sub>& leaves = found.back().leaves;
          const bool fits =
              Bisect(whole, s, length, options.max_depth, &own, &leaves);
          const int64_t total =
              pieces.fetch_add(static_cast<int64_t>(leaves.size())) +
              static_cast<int64_t>(leaves.size());
          if (!fits || total > budget) over = true;
        }
        if (found.empty()) return;
        const std::lock_guard<std::mutex> lock(append);
        for (SplitFace& face : found) split_faces->push_back(std::move(face));
      });
  if (over) return false;
  std::sort(
      split_faces->begin(), split_faces->end(),
      [](const SplitFace& a, const SplitFace& b) { return a.face < b.face; });
  return true;
}

// Triangle f's corner vertices, their sphere points and mesh points.
void Corners(const TriangleMesh& mesh, const Eigen::MatrixX3d& sphere,
             Eigen::Index f, int corner[3], Eigen::Vector3d s[3],
             Eigen::Vector3d x[3]) {
  for (int k = 0; k < 3; ++k) {
    corner[k] = mesh.faces(f, k);
    s[k] = sphere.row(corner[k]).transpose();
    x[k] = mesh.vertices.row(corner[k]).transpose();
  }
}

// The mesh point of barycentric b (weights of corners 1 and 2).
Eigen::Vector3d Target(const Eigen::Vector2d& b, const Eigen::Vector3d x[3]) {
  return (1.0 - b[0] - b[1]) * x[0] + b[0] * x[1] + b[1] * x[2];
}

// Barycentric area share of a leaf (affine in the mesh triangle) times the
// triangle's area.
double LeafArea(const Sub& t, double area) {
  const Eigen::Vector2d e0 = t.v[1] - t.v[0], e1 = t.v[2] - t.v[0];
  return area * std::abs(e0[0] * e1[1] - e0[1] * e1[0]);
}

// One of 6 x 4 x 4 bins of a direction: the cube face it points to and a
// 4 x 4 grid on that face (bins about 30 degrees wide).
int64_t NormalBin(const Eigen::Vector3d& n) {
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (std::abs(n[a]) > std::abs(n[axis])) axis = a;
  }
  if (!(std::abs(n[axis]) > 0)) return 0;
  const int face = 2 * axis + (n[axis] < 0 ? 1 : 0);
  const double u = n[(axis + 1) % 3] / std::abs(n[axis]);  // in [-1, 1]
  const double v = n[(axis + 2) % 3] / std::abs(n[axis]);
  const auto cell = [](double t) {
    return std::clamp(static_cast<int>(std::floor((t + 1.0) * 2.0)), 0, 3);
  };
  return 16 * face + 4 * cell(u) + cell(v);
}

// The cell of sphere point p: its nearest knot, the square of side
// spacing / per_spacing holding p in a tangent grid of that knot (a frame
// fixed by the knot alone), and `normal_bin`.
// `hint`: a knot likely nearest to p, or -1 (PointKdTree::NearestNear); set
// to the knot found.
std::array<int64_t, 4> CellKey(const Eigen::Vector3d& p,
                               const Eigen::MatrixX3d& knots,
                               const Eigen::VectorXd& spacing,
                               const PointKdTree& knot_tree, double per_spacing,
                               int64_t normal_bin, int* hint) {
  *hint = knot_tree.NearestNear(p, *hint).index;
  const int k = std::max(*hint, 0);
  const Eigen::Vector3d t = knots.row(k).transpose();
  const Eigen::Vector3d helper = std::abs(t.x()) < 0.6
                                     ? Eigen::Vector3d::UnitX()
                                     : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = t.cross(helper).normalized();
  const Eigen::Vector3d e2 = t.cross(e1);
  const double h = std::max(spacing[k] / per_spacing, 1e-12);
  return {k, static_cast<int64_t>(std::floor(p.dot(e1) / h)),
          static_cast<int64_t>(std::floor(p.dot(e2) / h)), normal_bin};
}

// The pieces exceed the budget: many triangles sample the same part of the
// sphere (a fan's needles, each cut along its whole length, cover the same
// region n times over). Every piece is still integrated at the full density,
// but its quadrature points are pooled in cells of the sample spacing (the
// spacing of the nearest knot over samples_per_spacing, in a tangent grid of
// that knot), each piece by its centroid: one row per cell, at the weighted
// mean of its sphere points and of its targets, with their summed weight. So
// the samples stay as dense as the knots ask everywhere, their count bounded by
// the cells (a few per knot), not by the triangles; the weights still add up to
// the area. Pieces pool only with pieces of a similar normal (NormalBin), so
// a crease's two sides are not averaged into a point inside the solid. A
// cell's row names the triangle that gave it the largest single piece.
void MergedSamples(const TriangleMesh& mesh, const Eigen::MatrixX3d& sphere,
                   const Eigen::MatrixX3d& knots,
                   const Eigen::VectorXd& spacing, const PointKdTree& knot_tree,
                   const FitSampleOptions& options, FitSamples* out) {
  const Eigen::Index nv = mesh.vertices.rows(), nf = mesh.faces.rows();
  struct Cell {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    double weight = 0.0;
    int triangle = -1;
    double triangle_weight = 0.0;
  };
  std::map<std::array<int64_t, 4>, Cell> cells;
  int64_t normal_bin = 0;  // of the triangle being deposited
  const double per_spacing = options.samples_per_spacing;
  Eigen::VectorXd vertex_weight = Eigen::VectorXd::Zero(nv);
  int hint = -1;  // the last deposit's knot
  auto deposit = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& x,
                     double w, int f) {
    const std::array<int64_t, 4> key =
        CellKey(p, knots, spacing, knot_tree, per_spacing, normal_bin, &hint);
    Cell& c = cells[key];
    c.point += w * p;
    c.target += w * x;
    c.weight += w;
    // Weight per triangle within the cell is not kept: the triangle of the
    // heaviest single deposit names the cell.
    if (w > c.triangle_weight) {
      c.triangle_weight = w;
      c.triangle = f;
    }
  };
  out->split_triangles = 0;
  out->merged_pieces = 0;
  std::vector<Sub> leaves;
  for (Eigen::Index f = 0; f < nf; ++f) {
    int corner[3];
    Eigen::Vector3d s[3], x[3];
    Corners(mesh, sphere, f, corner, s, x);
    const Eigen::Vector3d normal = (x[1] - x[0]).cross(x[2] - x[0]);
    const double area = 0.5 * normal.norm() * FaceWeight(options, f);
    normal_bin = NormalBin(normal);
    const auto length = [&](const Eigen::Vector3d& p) {
      const PointKdTree::Neighbor near = knot_tree.NearestNear(p, hint);
      hint = near.index;
      return near.index >= 0 ? spacing[near.index] / per_spacing
                             : std::numeric_limits<double>::infinity();
    };
    const double longest = std::max(
        {(s[1] - s[0]).norm(), (s[2] - s[1]).norm(), (s[0] - s[2]).norm()});
    if (longest <= length((s[0] + s[1] + s[2]).normalized())) {
      for (int k = 0; k < 3; ++k) vertex_weight[corner[k]] += area / 3.0;
      continue;
    }
    ++out->split_triangles;
    // A needle narrower than half the sample spacing: bisection would cut
    // it along its whole length into pieces far thinner than a cell, and
    // its neighbours sample the same cells. Instead, strips across it
    // (parallel to its short edge) at a staggered phase per triangle, as
    // many as its spherical area asks (and at least 2): neighbouring
    // needles' strips interleave and fill the cells between, and the work
    // is bounded by the knots' density, not by the needles' count.
    int apex = 0;
    double edge[3];
    for (int k = 0; k < 3; ++k) {
      edge[k] = (s[(k + 2) % 3] - s[(k + 1) % 3]).norm();
      if (edge[k] < edge[apex]) apex = k;
    }
    const double sphere_area = 0.5 * (s[1] - s[0]).cross(s[2] - s[0]).norm();
    double h = length((s[0] + s[1] + s[2]).normalized());
    for (int k = 0; k < 3; ++k) h = std::min(h, length(s[k]));
    if (2.0 * sphere_area / longest < 0.5 * h) {
      const int64_t strips = std::clamp<int64_t>(
          static_cast<int64_t>(std::ceil(8.0 * sphere_area / (h * h))), 2,
          static_cast<int64_t>(std::ceil(2.0 * longest / h)));
      const double phase =
          std::fmod(0.6180339887498949 * static_cast<double>(f), 1.0);
      out->merged_pieces += strips + 1;
      double from = 0.0;
      for (int64_t j = 0; j <= strips; ++j) {
        const double to =
            j == strips ? 1.0 : (static_cast<double>(j) + phase) / strips;
        const double share = to * to - from * from;  // of the area
        if (share > 0) {
          // The strip's centroid, at distance t from the apex along the
          // median (1 at the short edge).
          const double t =
              (2.0 / 3.0) * (to * to * to - from * from * from) / share;
          double w[3];
          for (int k = 0; k < 3; ++k) w[k] = k == apex ? 1.0 - t : 0.5 * t;
          const Eigen::Vector2d b(w[1], w[2]);
          deposit(OnSphere(b, s), Target(b, x), share * area,
                  static_cast<int>(f));
        }
        from = to;
      }
      continue;
    }
    leaves.clear();
    int64_t unlimited = std::numeric_limits<int64_t>::max();
    const Sub whole{
        {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)}};
    Bisect(whole, s, length, options.max_depth, &unlimited, &leaves);
    out->merged_pieces += static_cast<int64_t>(leaves.size());
    // A piece is far smaller than its cell: its centroid with its whole
    // area (the cell's mean is the quadrature).
    for (const Sub& t : leaves) {
      const Eigen::Vector2d c = (t.v[0] + t.v[1] + t.v[2]) / 3.0;
      deposit(OnSphere(c, s), Target(c, x), LeafArea(t, area),
              static_cast<int>(f));
    }
  }
  // Cells of degenerate (zero-area) pieces only carry no weight: no row.
  Eigen::Index rows = nv;
  for (const auto& entry : cells) rows += entry.second.weight > 0 ? 1 : 0;
  out->points.resize(rows, 3);
  out->targets.resize(rows, 3);
  out->weights.resize(rows);
  out->triangle.assign(rows - nv, -1);
  out->points.topRows(nv) = sphere;
  out->targets.topRows(nv) = mesh.vertices;
  out->weights.head(nv) = vertex_weight;
  Eigen::Index r = nv;
  for (const auto& [key, c] : cells) {
    if (!(c.weight > 0)) continue;
    out->points.row(r) = c.point.normalized().transpose();
    out->targets.row(r) = (c.target / c.weight).transpose();
    out->weights[r] = c.weight;
    out->triangle[r - nv] = c.triangle;
    ++r;
  }
}

// Thins `out` (FitSampleOptions::thin_above_vertices) in place; false, leaving
// it as it was, when thinning would keep more than thin_keep_at_most of its
// rows.
bool Thin(const TriangleMesh& mesh, const Eigen::MatrixX3d* vertex_normals,
          const Eigen::MatrixX3d& knots, const Eigen::VectorXd& spacing,
          const PointKdTree& knot_tree, const FitSampleOptions& options,
          FitSamples* out) {
  const Eigen::Index nv = out->num_vertices, rows = out->points.rows();
  // Mesh normals: of the triangle for a point inside it, area-weighted over
  // the incident triangles for a vertex.
  Eigen::MatrixX3d computed;
  if (vertex_normals == nullptr) computed = VertexNormals(mesh);
  const Eigen::MatrixX3d& vertex_normal =
      vertex_normals != nullptr ? *vertex_normals : computed;
  Eigen::MatrixX3d normal(rows, 3);
  // Each row's cell: (knot, grid row, grid column, normal bin), sorted by
  // cell and then by row (a total order: the same for any sort).
  struct CellRow {
    std::array<int64_t, 4> key;
    Eigen::Index row;
    bool operator<(const CellRow& o) const {
      for (int i = 0; i < 4; ++i) {
        if (key[i] != o.key[i]) return key[i] < o.key[i];
      }
      return row < o.row;
    }
  };
  std::vector<CellRow> cell_rows(rows);
  const double per_spacing = options.thinned_cells_per_spacing;
  tbb::parallel_for(
      tbb::blocked_range<Eigen::Index>(0, rows, 1024),
      [&](const tbb::blocked_range<Eigen::Index>& range) {
        int hint = -1;  // the last row's knot (rows in mesh order are close)
        for (Eigen::Index r = range.begin(); r < range.end(); ++r) {
          Eigen::Vector3d n = Eigen::Vector3d::Zero();
          if (r < nv) {
            n = vertex_normal.row(r).transpose();
          } else {
            const int f = out->triangle[r - nv];
            const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
            const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
            const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
            const Eigen::Vector3d cross = (b - a).cross(c - a);
            const double length = cross.norm();
            if (length > 0) n = cross / length;
          }
          normal.row(r) = n.transpose();
          cell_rows[r] = {
              CellKey(out->points.row(r).transpose(), knots, spacing, knot_tree,
                      per_spacing, NormalBin(n), &hint),
              r};
        }
      });
  tbb::parallel_sort(cell_rows.begin(), cell_rows.end());
  // Per cell (a run of `cell_rows`): the kept row and the cell's weight.
  std::vector<std::pair<Eigen::Index, double>> kept;
  std::vector<Eigen::Index> cell_of(rows);
  for (Eigen::Index begin = 0; begin < rows;) {
    Eigen::Index end = begin + 1;
    while (end < rows && cell_rows[end].key == cell_rows[begin].key) ++end;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    double weight = 0.0;
    for (Eigen::Index i = begin; i < end; ++i) {
      centroid += out->weights[cell_rows[i].row] *
                  out->points.row(cell_rows[i].row).transpose();
      weight += out->weights[cell_rows[i].row];
    }
    // The row nearest the centroid (the lowest on ties: `cell_rows` is
    // sorted by row within a cell).
    Eigen::Index best = cell_rows[begin].row;
    double best_distance = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = begin; i < end; ++i) {
      const double d =
          (out->points.row(cell_rows[i].row).transpose() * weight - centroid)
              .squaredNorm();
      if (d < best_distance) {
        best_distance = d;
        best = cell_rows[i].row;
      }
    }
    for (Eigen::Index i = begin; i < end; ++i) {
      cell_of[cell_rows[i].row] = static_cast<Eigen::Index>(kept.size());
    }
    kept.emplace_back(best, weight);
    begin = end;
  }
  if (static_cast<double>(kept.size()) >
      options.thin_keep_at_most * static_cast<double>(rows)) {
    return false;
  }
  // Kept rows in the order of their original rows.
  std::vector<Eigen::Index> by_row(kept.size());
  for (size_t c = 0; c < kept.size(); ++c)
    by_row[c] = static_cast<Eigen::Index>(c);
  std::sort(by_row.begin(), by_row.end(), [&](Eigen::Index a, Eigen::Index b) {
    return kept[a].first < kept[b].first;
  });
  std::vector<int> row_of_cell(kept.size());
  FitSamples thinned;
  const Eigen::Index n = static_cast<Eigen::Index>(kept.size());
  thinned.points.resize(n, 3);
  thinned.targets.resize(n, 3);
  thinned.weights.resize(n);
  thinned.triangle.assign(n, -1);
  thinned.row_vertex.assign(n, -1);
  thinned.row_normal.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& [row, weight] = kept[by_row[i]];
    row_of_cell[by_row[i]] = static_cast<int>(i);
    thinned.points.row(i) = out->points.row(row);
    thinned.targets.row(i) = out->targets.row(row);
    thinned.weights[i] = weight;
    thinned.row_normal.row(i) = normal.row(row);
    if (row < nv) {
      thinned.row_vertex[i] = static_cast<int>(row);
    } else {
      thinned.triangle[i] = out->triangle[row - nv];
    }
  }
  thinned.vertex_row.resize(nv);
  for (Eigen::Index v = 0; v < nv; ++v) {
    thinned.vertex_row[v] = row_of_cell[cell_of[v]];
  }
  thinned.num_vertices = 0;
  thinned.thinned = true;
  thinned.unthinned_rows = rows;
  thinned.split_triangles = out->split_triangles;
  thinned.samples_per_spacing = out->samples_per_spacing;
  thinned.merged_pieces = out->merged_pieces;
  *out = std::move(thinned);
  return true;
}

}  // namespace

FitSamples BuildFitSamples(const TriangleMesh& mesh,
                           const Eigen::MatrixX3d& sphere,
                           const Eigen::MatrixX3d& knots,
                           const FitSampleOptions& options,
                           const Eigen::MatrixX3d* vertex_normals) {
  const Eigen::Index nv = mesh.vertices.rows(), nf = mesh.faces.rows();
  const Eigen::VectorXd spacing = KnotSpacing(knots);
  const PointKdTree knot_tree(knots, /*direction_index=*/true);

  // The sub-triangles of every triangle whose spherical image has an edge
  // longer than the sample spacing h / samples_per_spacing (h: the spacing
  // of the knot nearest to its centroid); again with half the samples per
  // spacing while they exceed max_pieces.
  FitSamples out;
  out.num_vertices = nv;
  std::vector<SplitFace> split_faces;
  out.samples_per_spacing = options.samples_per_spacing;
  if (!SplitTriangles(mesh, sphere, spacing, knot_tree,
                      options.samples_per_spacing, options, &split_faces)) {
    MergedSamples(mesh, sphere, knots, spacing, knot_tree, options, &out);
    out.unthinned_rows = out.points.rows();
    if (options.thin_above_vertices > 0 && nv > options.thin_above_vertices) {
      Thin(mesh, vertex_normals, knots, spacing, knot_tree, options, &out);
    }
    return out;
  }
  out.split_triangles = static_cast<int>(split_faces.size());

  // Rows: the vertices, then per split triangle its new lattice points and
  // its leaves' centroids.
  Eigen::Index extra = 0;
  for (const SplitFace& l : split_faces) extra += 4 * l.leaves.size();  // bound
  out.points.resize(nv + extra, 3);
  out.targets.resize(nv + extra, 3);
  out.weights = Eigen::VectorXd::Zero(nv + extra);
  out.triangle.assign(extra, -1);
  out.points.topRows(nv) = sphere;
  out.targets.topRows(nv) = mesh.vertices;
  Eigen::Index next = nv;
  std::map<std::pair<double, double>, Eigen::Index> point_row;
  auto split_face = split_faces.begin();
  for (Eigen::Index f = 0; f < nf; ++f) {
    if (split_face == split_faces.end() || split_face->face != f) {
      // Not split: a third of its area to each corner.
      const Eigen::Vector3d x0 = mesh.vertices.row(mesh.faces(f, 0));
      const Eigen::Vector3d x1 = mesh.vertices.row(mesh.faces(f, 1));
      const Eigen::Vector3d x2 = mesh.vertices.row(mesh.faces(f, 2));
      const double area =
          0.5 * (x1 - x0).cross(x2 - x0).norm() * FaceWeight(options, f);
      for (int k = 0; k < 3; ++k) out.weights[mesh.faces(f, k)] += area / 3.0;
      continue;
    }
    const std::vector<Sub>& leaves = (split_face++)->leaves;
    int corner[3];
    Eigen::Vector3d s[3], x[3];
    Corners(mesh, sphere, f, corner, s, x);
    const double area =
        0.5 * (x[1] - x[0]).cross(x[2] - x[0]).norm() * FaceWeight(options, f);
    auto add_point = [&](const Eigen::Vector2d& b) {
      out.points.row(next) = OnSphere(b, s).transpose();
      out.targets.row(next) = Target(b, x).transpose();
      out.triangle[next - nv] = static_cast<int>(f);
      return next++;
    };
    point_row.clear();
    auto row_of = [&](const Eigen::Vector2d& b) -> Eigen::Index {
      if (b[0] == 0 && b[1] == 0) return corner[0];
      if (b[0] == 1 && b[1] == 0) return corner[1];
      if (b[0] == 0 && b[1] == 1) return corner[2];
      const auto [it, inserted] = point_row.emplace(std::pair{b[0], b[1]}, 0);
      if (inserted) it->second = add_point(b);
      return it->second;
    };
    for (const Sub& t : leaves) {
      const double leaf_area = LeafArea(t, area);
      for (int k = 0; k < 3; ++k) {
        out.weights[row_of(t.v[k])] += leaf_area / 12.0;
      }
      out.weights[add_point((t.v[0] + t.v[1] + t.v[2]) / 3.0)] =
          0.75 * leaf_area;
    }
  }
  out.points.conservativeResize(next, 3);
  out.targets.conservativeResize(next, 3);
  out.weights.conservativeResize(next);
  out.triangle.resize(next - nv);
  out.unthinned_rows = out.points.rows();
  if (options.thin_above_vertices > 0 && nv > options.thin_above_vertices) {
    Thin(mesh, vertex_normals, knots, spacing, knot_tree, options, &out);
  }
  return out;
}

void AppendEdgeBandSamples(const TriangleMesh& mesh,
                           const Eigen::MatrixX3d& sphere,
                           const std::vector<std::array<int, 2>>& edges,
                           const std::vector<double>& offsets, int along,
                           double weight, FitSamples* samples) {
  // The triangles at each edge, with the corner opposite it.
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> beside;
  for (const std::array<int, 2>& e : edges) beside[{e[0], e[1]}];
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces(f, k), b = mesh.faces(f, (k + 1) % 3);
      auto it = beside.find({std::min(a, b), std::max(a, b)});
      if (it != beside.end()) {
        it->second.push_back({static_cast<int>(f), mesh.faces(f, (k + 2) % 3)});
      }
    }
  }
  std::vector<Eigen::Vector3d> points, targets;
  std::vector<int> triangles;
  for (const auto& [edge, faces] : beside) {
    const auto [a, b] = edge;
    const Eigen::Vector3d ua = sphere.row(a), ub = sphere.row(b);
    const Eigen::Vector3d pole = ua.cross(ub).normalized();
    for (const auto& [f, c] : faces) {
      const Eigen::Vector3d uc = sphere.row(c);
      const double height = std::asin(std::min(1.0, std::abs(pole.dot(uc))));
      if (!(height > 0.0)) continue;
      for (const double offset : offsets) {
        const double w = std::min(0.5, offset / height);
        for (int i = 0; i < along; ++i) {
          const double t = (i + 0.5) / along;
          const double wa = (1.0 - w) * (1.0 - t), wb = (1.0 - w) * t;
          points.push_back((wa * ua + wb * ub + w * uc).normalized());
          targets.push_back(wa * mesh.vertices.row(a).transpose() +
                            wb * mesh.vertices.row(b).transpose() +
                            w * mesh.vertices.row(c).transpose());
          triangles.push_back(f);
        }
      }
    }
  }
  const Eigen::Index n = samples->points.rows(),
                     m = static_cast<Eigen::Index>(points.size());
  samples->points.conservativeResize(n + m, 3);
  samples->targets.conservativeResize(n + m, 3);
  samples->weights.conservativeResize(n + m);
  for (Eigen::Index i = 0; i < m; ++i) {
    samples->points.row(n + i) = points[i].transpose();
    samples->targets.row(n + i) = targets[i].transpose();
    samples->weights[n + i] = weight;
  }
  if (samples->thinned) {
    samples->row_vertex.resize(n + m, -1);
    samples->row_normal.conservativeResize(n + m, 3);
    for (Eigen::Index i = 0; i < m; ++i) {
      const Eigen::Vector3i t = mesh.faces.row(triangles[i]);
      const Eigen::Vector3d p0 = mesh.vertices.row(t[0]),
                            p1 = mesh.vertices.row(t[1]),
                            p2 = mesh.vertices.row(t[2]);
      samples->row_normal.row(n + i) =
          (p1 - p0).cross(p2 - p0).normalized().transpose();
    }
  }
  samples->triangle.insert(samples->triangle.end(), triangles.begin(),
                           triangles.end());
}

}  // namespace sdcb
