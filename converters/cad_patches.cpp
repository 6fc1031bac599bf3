#include "sdcb/converters/cad_patches.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "sdcb/core/spline/piecewise_surface.h"

namespace sdcb {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Patches are refined until their measured distance is within this share of
// the tolerance: a margin for the distance between lattice points.
constexpr double kTargetShare = 0.95;

// Cubic Bernstein polynomials and their derivatives at t.
void Bernstein(double t, double b[4], double d[4]) {
  const double s = 1.0 - t;
  b[0] = s * s * s;
  b[1] = 3.0 * t * s * s;
  b[2] = 3.0 * t * t * s;
  b[3] = t * t * t;
  if (d != nullptr) {
    d[0] = -3.0 * s * s;
    d[1] = 3.0 * s * s - 6.0 * t * s;
    d[2] = 6.0 * t * s - 3.0 * t * t;
    d[3] = 3.0 * t * t;
  }
}

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

// The pole indices (into BicubicPatch::poles) of local edge k, from corner
// k to corner k + 1.
std::array<int, 4> EdgePoleIndices(int k) {
  switch (k) {
    case 0:
      return {0, 1, 2, 3};
    case 1:
      return {3, 7, 11, 15};
    case 2:
      return {15, 14, 13, 12};
    default:
      return {12, 8, 4, 0};
  }
}

Eigen::Vector3d UnitNormal(const BicubicPatch& patch, double u, double v) {
  Eigen::Vector3d du, dv;
  patch.Evaluate(u, v, &du, &dv);
  const Eigen::Vector3d n = du.cross(dv);
  const double norm = n.norm();
  return norm > 0.0 ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::Zero();
}

class PatchFitter {
 public:
  PatchFitter(const PiecewiseSurface& surface, const CadPatchOptions& options)
      : surface_(surface), options_(options) {}

  // Fits every patch of `layout`.
  StatusOr<std::vector<BicubicPatch>> Fit(const SphereCage& layout,
                                          LayoutEdges* edges_out) {
    SDCB_ASSIGN_OR_RETURN(LayoutEdges edges, BuildEdges(layout));
    const int ne = static_cast<int>(edges.vertices.size());
    const int nf = layout.num_faces();
    const int k = options_.fit_samples_per_side;

    Eigen::MatrixX3d vertex_points;
    surface_.EvaluateMany(layout.sphere_points, &vertex_points, nullptr);

    // Edge curves, from the lower to the higher vertex.
    Eigen::MatrixX3d directions(static_cast<Eigen::Index>(ne) * k, 3);
    for (int e = 0; e < ne; ++e) {
      const Eigen::Vector3d a = layout.sphere_points.row(edges.vertices[e][0]);
      const Eigen::Vector3d b = layout.sphere_points.row(edges.vertices[e][1]);
      for (int m = 0; m < k; ++m) {
        const double t = (m + 1.0) / (k + 1.0);
        directions.row(e * k + m) = ((1.0 - t) * a + t * b).normalized();
      }
    }
    Eigen::MatrixX3d targets;
    surface_.EvaluateMany(directions, &targets, nullptr);
    std::vector<std::array<Eigen::Vector3d, 4>> curves(ne);
    Eigen::Matrix2d normal_matrix = Eigen::Matrix2d::Zero();
    std::vector<std::array<double, 4>> basis(k);
    for (int m = 0; m < k; ++m) {
      Bernstein((m + 1.0) / (k + 1.0), basis[m].data(), nullptr);
      normal_matrix(0, 0) += basis[m][1] * basis[m][1];
      normal_matrix(0, 1) += basis[m][1] * basis[m][2];
      normal_matrix(1, 1) += basis[m][2] * basis[m][2];
    }
    normal_matrix(1, 0) = normal_matrix(0, 1);
    const Eigen::Matrix2d inverse = normal_matrix.inverse();
    for (int e = 0; e < ne; ++e) {
      const Eigen::Vector3d q0 = vertex_points.row(edges.vertices[e][0]);
      const Eigen::Vector3d q3 = vertex_points.row(edges.vertices[e][1]);
      Eigen::Matrix<double, 2, 3> rhs = Eigen::Matrix<double, 2, 3>::Zero();
      for (int m = 0; m < k; ++m) {
        const Eigen::RowVector3d r = targets.row(e * k + m) -
                                     basis[m][0] * q0.transpose() -
                                     basis[m][3] * q3.transpose();
        rhs.row(0) += basis[m][1] * r;
        rhs.row(1) += basis[m][2] * r;
      }
      const Eigen::Matrix<double, 2, 3> inner = inverse * rhs;
      curves[e] = {q0, inner.row(0).transpose(), inner.row(1).transpose(), q3};
    }

    // Inner poles of every face, boundary held fixed.
    std::vector<BicubicPatch> patches(nf);
    Eigen::MatrixX3d face_directions(static_cast<Eigen::Index>(nf) * k * k, 3);
    for (int f = 0; f < nf; ++f) {
      for (int j = 0; j < k; ++j) {
        for (int i = 0; i < k; ++i) {
          face_directions.row((f * k + j) * k + i) =
              layout.SpherePoint(f, (i + 0.5) / k, (j + 0.5) / k);
        }
      }
    }
    surface_.EvaluateMany(face_directions, &targets, nullptr);
    // The design matrix is the same for every face: the inner poles' basis
    // products at the grid.
    constexpr int kInner[4] = {5, 6, 9, 10};
    Eigen::MatrixXd design(k * k, 4);
    Eigen::MatrixXd full(k * k, 16);
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i < k; ++i) {
        double bu[4], bv[4];
        Bernstein((i + 0.5) / k, bu, nullptr);
        Bernstein((j + 0.5) / k, bv, nullptr);
        for (int q = 0; q < 16; ++q) full(j * k + i, q) = bu[q % 4] * bv[q / 4];
      }
    }
    for (int c = 0; c < 4; ++c) design.col(c) = full.col(kInner[c]);
    const Eigen::LDLT<Eigen::Matrix4d> solver(
        (design.transpose() * design).eval());
    for (int f = 0; f < nf; ++f) {
      BicubicPatch& patch = patches[f];
      for (int side = 0; side < 4; ++side) {
        const auto& curve = curves[edges.face_edge[f][side]];
        const std::array<int, 4> slots = EdgePoleIndices(side);
        for (int q = 0; q < 4; ++q) {
          patch.poles[slots[q]] =
              edges.face_forward[f][side] ? curve[q] : curve[3 - q];
        }
      }
      Eigen::MatrixX3d rhs =
          targets.middleRows(static_cast<Eigen::Index>(f) * k * k, k * k);
      for (int q = 0; q < 16; ++q) {
        if (q == 5 || q == 6 || q == 9 || q == 10) continue;
        rhs -= full.col(q) * patch.poles[q].transpose();
      }
      const Eigen::Matrix<double, 4, 3> inner =
          solver.solve(design.transpose() * rhs);
      for (int c = 0; c < 4; ++c) {
        patch.poles[kInner[c]] = inner.row(c).transpose();
      }
    }
    *edges_out = std::move(edges);
    return patches;
  }

 private:
  const PiecewiseSurface& surface_;
  const CadPatchOptions& options_;
};

// Parametric distance of every patch to the spline on an (n + 1)^2 lattice
// per face: the per-face maxima, the overall maximum and the area-weighted
// rms (percent); and the angle between the patch's normal and the spline's
// (where the spline has one) at the same points.
void Measure(const PiecewiseSurface& surface, const SphereCage& layout,
             const std::vector<BicubicPatch>& patches, int n,
             double percent_per_unit, CadPatchSet* out) {
  const int nf = layout.num_faces();
  const int per_face = (n + 1) * (n + 1);
  Eigen::MatrixX3d directions(static_cast<Eigen::Index>(nf) * per_face, 3);
  for (int f = 0; f < nf; ++f) {
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        directions.row(static_cast<Eigen::Index>(f) * per_face + j * (n + 1) +
                       i) = layout.SpherePoint(f, double(i) / n, double(j) / n);
      }
    }
  }
  Eigen::MatrixX3d points, normals;
  surface.EvaluateMany(directions, &points, &normals);
  out->patch_max_percent.assign(nf, 0.0);
  out->patch_max_normal_degrees.assign(nf, 0.0);
  double max_angle = 0.0;
  double sum_squares = 0.0, sum_area = 0.0, max_distance = 0.0;
  for (int f = 0; f < nf; ++f) {
    double face_max = 0.0;
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        Eigen::Vector3d du, dv;
        const Eigen::Vector3d b =
            patches[f].Evaluate(double(i) / n, double(j) / n, &du, &dv);
        const Eigen::Index row =
            static_cast<Eigen::Index>(f) * per_face + j * (n + 1) + i;
        const double d = (b - points.row(row).transpose()).norm();
        const Eigen::Vector3d patch_normal = du.cross(dv);
        const Eigen::Vector3d spline_normal = normals.row(row);
        if (patch_normal.norm() > 0.0 && spline_normal.norm() > 0.0) {
          const double c = std::clamp(
              patch_normal.normalized().dot(spline_normal), -1.0, 1.0);
          out->patch_max_normal_degrees[f] = std::max(
              out->patch_max_normal_degrees[f], std::acos(c) * 180.0 / kPi);
        }
        // Trapezoid weights of the lattice.
        const double w = ((i == 0 || i == n) ? 0.5 : 1.0) *
                         ((j == 0 || j == n) ? 0.5 : 1.0) * du.cross(dv).norm();
        sum_squares += w * d * d;
        sum_area += w;
        face_max = std::max(face_max, d);
      }
    }
    out->patch_max_percent[f] = face_max * percent_per_unit;
    max_distance = std::max(max_distance, face_max);
    max_angle = std::max(max_angle, out->patch_max_normal_degrees[f]);
  }
  out->max_normal_deviation_degrees = max_angle;
  out->max_deviation_percent = max_distance * percent_per_unit;
  out->rms_deviation_percent =
      sum_area > 0.0 ? std::sqrt(sum_squares / sum_area) * percent_per_unit
                     : 0.0;
  out->measured_points = static_cast<int64_t>(nf) * per_face;
}

double MaxNormalJump(const std::vector<BicubicPatch>& patches,
                     const LayoutEdges& edges, int samples) {
  double worst = 0.0;
  for (size_t e = 0; e < edges.vertices.size(); ++e) {
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
      worst = std::max(worst, std::acos(c) * 180.0 / kPi);
    }
  }
  return worst;
}

}  // namespace

Eigen::Vector3d BicubicPatch::Evaluate(double u, double v, Eigen::Vector3d* du,
                                       Eigen::Vector3d* dv) const {
  double bu[4], bv[4], du_basis[4], dv_basis[4];
  Bernstein(u, bu, du_basis);
  Bernstein(v, bv, dv_basis);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d pu = Eigen::Vector3d::Zero(), pv = Eigen::Vector3d::Zero();
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d& pole = poles[4 * j + i];
      p += bu[i] * bv[j] * pole;
      pu += du_basis[i] * bv[j] * pole;
      pv += bu[i] * dv_basis[j] * pole;
    }
  }
  if (du != nullptr) *du = pu;
  if (dv != nullptr) *dv = pv;
  return p;
}

Eigen::Vector2d QuadEdgeParameter(int k, double t) {
  switch (k) {
    case 0:
      return {t, 0.0};
    case 1:
      return {1.0, t};
    case 2:
      return {1.0 - t, 1.0};
    default:
      return {0.0, 1.0 - t};
  }
}

StatusOr<CadPatchSet> FitCadPatches(const SphericalSpline& spline,
                                    const CadPatchOptions& options) {
  if (!(options.tolerance_percent > 0.0) || !(options.length_unit > 0.0) ||
      !(options.max_normal_degrees > 0.0) || options.max_patches < 96 ||
      options.initial_levels < 0 || options.initial_levels > 8 ||
      options.fit_samples_per_side < 3 || options.check_samples_per_side < 1 ||
      options.max_rounds < 1) {
    return InvalidArgumentError(
        "CAD patches need a positive tolerance and length unit, at least 96 "
        "patches, 0..8 initial levels and at least 3 fit samples per side");
  }
  const PiecewiseSurface surface(spline);
  const double percent_per_unit = 100.0 / options.length_unit;
  SphereCageTopology topology =
      SphereCageTopology::Create(CageCellShape::kQuad, options.initial_levels);
  PatchFitter fitter(surface, options);
  CadPatchSet result;
  for (int round = 1;; ++round) {
    const SphereCage& layout = topology.cage();
    LayoutEdges edges;
    SDCB_ASSIGN_OR_RETURN(std::vector<BicubicPatch> patches,
                          fitter.Fit(layout, &edges));
    const int nf = layout.num_faces();
    const int n = std::max(
        options.check_samples_per_side,
        static_cast<int>(std::ceil(
            std::sqrt(static_cast<double>(options.measure_samples) / nf))));
    CadPatchSet measured;
    Measure(surface, layout, patches, n, percent_per_unit, &measured);
    if (options.on_round) {
      options.on_round(round, nf, measured.max_deviation_percent);
    }
    const auto failing = [&](const CadPatchSet& m) {
      std::vector<int> cells;
      for (int f = 0; f < nf; ++f) {
        if (m.patch_max_percent[f] > kTargetShare * options.tolerance_percent ||
            m.patch_max_normal_degrees[f] > options.max_normal_degrees) {
          cells.push_back(layout.face_cell[f]);
        }
      }
      return cells;
    };
    std::vector<int> cells = failing(measured);
    if (cells.empty()) {
      // Every lattice point is within: the returned figures come from a
      // lattice three times as fine (the distance between lattice points
      // can exceed that at them), which may still send faces back.
      Measure(surface, layout, patches, 3 * n, percent_per_unit, &measured);
      cells = failing(measured);
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
               options.max_patches) {
      stop = "patch budget";
    }
    if (!stop.empty()) {
      result = std::move(measured);
      result.patches = std::move(patches);
      result.layout = layout;
      result.max_normal_jump_degrees = MaxNormalJump(result.patches, edges, 32);
      result.rounds = round;
      result.within_tolerance =
          result.max_deviation_percent <= options.tolerance_percent &&
          result.max_normal_deviation_degrees <= options.max_normal_degrees;
      result.stop_reason = stop;
      return result;
    }
    topology.Refine(cells);
  }
}

}  // namespace sdcb
