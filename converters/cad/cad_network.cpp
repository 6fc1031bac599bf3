#include "sdcb/converters/cad/cad_network.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <utility>

#include "sdcb/converters/cad/gauss_legendre.h"
#include "sdcb/core/common/constants.h"
#include "sdcb/core/common/stopwatch.h"
#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/knots/feature_knots.h"
#include "sdcb/core/spline/piecewise_surface.h"

namespace sdcb {
namespace {

constexpr double kDegrees = 180.0 / kPi;
// The smallest derivative the tangent rows are divided by, in the spline's
// frame per unit of the face parameter (a face spans 2 / grid of it);
// typical derivatives are ~0.5 in a normalized frame.
constexpr double kMinDerivative = 0.05;
// Where the spline's normal on a crease is taken, as a share of the face's
// parameter box inside the face.
constexpr double kCreaseInset = 1e-3;
// Spans are not halved below this parameter length.
constexpr double kMinSpan = 1.0 / 4096;
// A cell over the tolerance halves its span along a direction when the
// residual changes at least this share as much along it as along the other.
constexpr double kAnisotropy = 0.7;

// The Gauss-Legendre rule of the distance and tangent rows.
const GaussLegendre<4>& Gauss() {
  static const GaussLegendre<4> rule;
  return rule;
}

// Side k of a face over [u0, u1] x [v0, v1]: the parameter it runs along (0:
// u, 1: v), the value of the other, and the sign of the derivative that
// points out of the face.
struct SideFrame {
  int along;     // 0: u, 1: v
  double fixed;  // the other parameter's value on the side
  double out;    // +1 or -1 on the fixed parameter
};

SideFrame SideFrameOf(const BSplineFace& face, int k) {
  switch (k) {
    case 0:
      return {0, face.v_breaks.front(), -1.0};
    case 1:
      return {1, face.u_breaks.back(), 1.0};
    case 2:
      return {0, face.v_breaks.back(), 1.0};
    default:
      return {1, face.u_breaks.front(), -1.0};
  }
}

// (u, v) of side `frame` at the along parameter t.
Eigen::Vector2d SidePoint(const SideFrame& frame, double t) {
  return frame.along == 0 ? Eigen::Vector2d(t, frame.fixed)
                          : Eigen::Vector2d(frame.fixed, t);
}

// The accumulated normal equations of a group of rows that share their
// unknowns: local A^T A and A^T b over `vars`.
class LocalBlock {
 public:
  int Index(int var) {
    for (size_t k = 0; k < vars_.size(); ++k) {
      if (vars_[k] == var) return static_cast<int>(k);
    }
    vars_.push_back(var);
    return static_cast<int>(vars_.size()) - 1;
  }
  size_t size() const { return vars_.size(); }
  // Adds the row sum_k coef[k] X[vars[k]] = rhs with weight w (`coef` by
  // local index, as long as vars).
  void AddRow(const std::vector<double>& coef, double w,
              const Eigen::Vector3d& rhs) {
    const Eigen::Index n = static_cast<Eigen::Index>(vars_.size());
    if (ata_.rows() < n) {
      Eigen::MatrixXd grown = Eigen::MatrixXd::Zero(n, n);
      grown.topLeftCorner(ata_.rows(), ata_.cols()) = ata_;
      ata_ = std::move(grown);
      Eigen::MatrixX3d grown_b = Eigen::MatrixX3d::Zero(n, 3);
      grown_b.topRows(atb_.rows()) = atb_;
      atb_ = std::move(grown_b);
    }
    const double w2 = w * w;
    for (Eigen::Index a = 0; a < n; ++a) {
      if (coef[a] == 0.0) continue;
      for (Eigen::Index b = 0; b < n; ++b) {
        ata_(a, b) += w2 * coef[a] * coef[b];
      }
      atb_.row(a) += w2 * coef[a] * rhs.transpose();
    }
  }
  // The lower triangle into `triplets`, A^T b into `rhs`.
  void AppendTo(std::vector<Eigen::Triplet<double>>* triplets,
                Eigen::MatrixX3d* rhs) const {
    for (Eigen::Index a = 0; a < ata_.rows(); ++a) {
      rhs->row(vars_[a]) += atb_.row(a);
      for (Eigen::Index b = 0; b < ata_.cols(); ++b) {
        if (ata_(a, b) != 0.0 && vars_[a] >= vars_[b]) {
          triplets->emplace_back(vars_[a], vars_[b], ata_(a, b));
        }
      }
    }
  }

 private:
  std::vector<int> vars_;
  Eigen::MatrixXd ata_;
  Eigen::MatrixX3d atb_;
};

// A pole as a combination of unknowns.
using PoleTerms = std::vector<std::pair<int, double>>;

// The sorted knots two break lists have in common (both dyadic, so equal
// knots are equal numbers).
KnotBreaks CommonKnots(const KnotBreaks& a, const KnotBreaks& b) {
  KnotBreaks c;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(),
                        std::back_inserter(c));
  return c;
}

KnotBreaks UnionKnots(const KnotBreaks& a, const KnotBreaks& b) {
  KnotBreaks c;
  std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(c));
  return c;
}

const KnotBreaks& AlongBreaks(const BSplineFace& face, int k) {
  return k % 2 == 0 ? face.u_breaks : face.v_breaks;
}

// The network's state between rounds: the faces' knots, the topology and
// the unknowns of every pole.
class NetworkFitter {
 public:
  NetworkFitter(const PiecewiseSurface& surface, const CadQuadLayout& layout,
                int spans)
      : surface_(surface), layout_(layout) {
    const int grid = layout.grid;
    for (int c = 0; c < layout.num_quads(); ++c) {
      for (int j = 0; j < grid; ++j) {
        for (int i = 0; i < grid; ++i) {
          BSplineFace face;
          for (int k = 0; k <= spans; ++k) {
            face.u_breaks.push_back(-1.0 +
                                    2.0 * (i + double(k) / spans) / grid);
            face.v_breaks.push_back(-1.0 +
                                    2.0 * (j + double(k) / spans) / grid);
          }
          faces_.push_back(std::move(face));
          quad_.push_back(c);
        }
      }
    }
    BuildTopology();
  }

  int num_faces() const { return static_cast<int>(faces_.size()); }
  const std::vector<BSplineFace>& faces() const { return faces_; }
  const std::vector<int>& quad() const { return quad_; }
  const CadQuadLayout& layout() const { return layout_; }
  int num_vars() const { return num_vars_; }
  int num_vertices() const { return num_vertices_; }
  const std::vector<std::array<int, 4>>& face_edges() const {
    return face_edges_;
  }

  // The sphere point of face f at (u, v), with derivatives.
  Eigen::Vector3d Sphere(int f, double u, double v,
                         Eigen::Vector3d* du = nullptr,
                         Eigen::Vector3d* dv = nullptr) const {
    return layout_.Point(quad_[f], u, v, du, dv);
  }

  // Whether side k of face f lies on a crease of the layout.
  bool OnCrease(int f, int k) const {
    const BSplineFace& face = faces_[f];
    const bool at_quad_side = (k == 0 && face.v_breaks.front() == -1.0) ||
                              (k == 1 && face.u_breaks.back() == 1.0) ||
                              (k == 2 && face.v_breaks.back() == 1.0) ||
                              (k == 3 && face.u_breaks.front() == -1.0);
    return at_quad_side && layout_.crease[quad_[f]][k];
  }

  // Every side: its two (face, side), its vertices at the start and end of
  // its parameter, and whether it lies on a crease.
  struct Edge {
    int face[2], side[2];
    int start = -1, end = -1;
    bool crease = false;
    KnotBreaks breaks;  // the knots both faces have along it
    std::vector<int> vars;
  };
  const std::vector<Edge>& edges() const { return edges_; }

  // Numbers the unknowns for the faces' present knots: one per vertex, per
  // inner pole of every edge (on the knots its faces share) and per inner
  // pole of every face; a boundary pole of a face is its edge's poles
  // through the knot insertion matrix.
  void NumberPoles() {
    num_vars_ = num_vertices_;
    for (Edge& e : edges_) {
      e.breaks = CommonKnots(AlongBreaks(faces_[e.face[0]], e.side[0]),
                             AlongBreaks(faces_[e.face[1]], e.side[1]));
      const int n = static_cast<int>(e.breaks.size()) + 2;
      e.vars.assign(n, -1);
      e.vars.front() = e.start;
      e.vars.back() = e.end;
      for (int q = 1; q + 1 < n; ++q) e.vars[q] = num_vars_++;
    }
    terms_.assign(faces_.size(), {});
    for (size_t f = 0; f < faces_.size(); ++f) {
      const BSplineFace& face = faces_[f];
      const int nu = face.num_u(), nv = face.num_v();
      std::vector<PoleTerms>& terms = terms_[f];
      terms.assign(static_cast<size_t>(nu) * nv, {});
      for (int j = 1; j + 1 < nv; ++j) {
        for (int i = 1; i + 1 < nu; ++i) {
          terms[j * nu + i] = {{num_vars_++, 1.0}};
        }
      }
      for (int k = 0; k < 4; ++k) {
        const Edge& e = edges_[face_edges_[f][k]];
        const Eigen::MatrixXd m =
            KnotInsertionMatrix(e.breaks, AlongBreaks(face, k));
        for (Eigen::Index q = 0; q < m.rows(); ++q) {
          const int i =
              k == 0 || k == 2 ? static_cast<int>(q) : (k == 1 ? nu - 1 : 0);
          const int j =
              k == 1 || k == 3 ? static_cast<int>(q) : (k == 0 ? 0 : nv - 1);
          PoleTerms& t = terms[j * nu + i];
          if (!t.empty()) continue;  // a corner, from the previous side
          for (Eigen::Index c = 0; c < m.cols(); ++c) {
            if (m(q, c) != 0.0) t.push_back({e.vars[c], m(q, c)});
          }
        }
      }
    }
  }

  // Fits every unknown (NumberPoles must have numbered them for the present
  // knots); the faces' poles and the edges' curves are set from the
  // solution.
  Status Fit(double tangent_weight) {
    struct Cell {
      int face, su, sv;
    };
    std::vector<Cell> cells;
    for (int f = 0; f < num_faces(); ++f) {
      const int mu = static_cast<int>(faces_[f].u_breaks.size()) - 1;
      const int mv = static_cast<int>(faces_[f].v_breaks.size()) - 1;
      for (int sv = 0; sv < mv; ++sv) {
        for (int su = 0; su < mu; ++su) cells.push_back({f, su, sv});
      }
    }
    Eigen::MatrixX3d directions(static_cast<Eigen::Index>(cells.size()) * 16,
                                3);
    tbb::parallel_for(size_t{0}, cells.size(), [&](size_t c) {
      const Cell& cell = cells[c];
      const KnotBreaks &bu = faces_[cell.face].u_breaks,
                       &bv = faces_[cell.face].v_breaks;
      for (int b = 0; b < 4; ++b) {
        for (int a = 0; a < 4; ++a) {
          const double u =
              bu[cell.su] + Gauss().x[a] * (bu[cell.su + 1] - bu[cell.su]);
          const double v =
              bv[cell.sv] + Gauss().x[b] * (bv[cell.sv + 1] - bv[cell.sv]);
          directions.row(c * 16 + 4 * b + a) = Sphere(cell.face, u, v);
        }
      }
    });
    Eigen::MatrixX3d targets;
    surface_.EvaluateMany(directions, &targets, nullptr);
    std::vector<LocalBlock> blocks(cells.size());
    tbb::parallel_for(size_t{0}, cells.size(), [&](size_t c) {
      const Cell& cell = cells[c];
      const BSplineFace& face = faces_[cell.face];
      const KnotBreaks &bu = face.u_breaks, &bv = face.v_breaks;
      const double hu = bu[cell.su + 1] - bu[cell.su];
      const double hv = bv[cell.sv + 1] - bv[cell.sv];
      LocalBlock& block = blocks[c];
      for (int b = 0; b < 4; ++b) {
        for (int a = 0; a < 4; ++a) {
          const double u = bu[cell.su] + Gauss().x[a] * hu;
          const double v = bv[cell.sv] + Gauss().x[b] * hv;
          double nu[4], nv[4];
          CubicBSplineBasis(bu, cell.su, u, nu, nullptr);
          CubicBSplineBasis(bv, cell.sv, v, nv, nullptr);
          std::vector<double> coef(block.size(), 0.0);
          for (int q = 0; q < 4; ++q) {
            for (int p = 0; p < 4; ++p) {
              AddPole(cell.face, cell.su + p, cell.sv + q, nu[p] * nv[q],
                      &block, &coef);
            }
          }
          block.AddRow(coef, std::sqrt(Gauss().w[a] * Gauss().w[b] * hu * hv),
                       targets.row(c * 16 + 4 * b + a));
        }
      }
    });
    std::vector<LocalBlock> tangent(tangent_weight > 0.0 ? edges_.size() : 0);
    tbb::parallel_for(size_t{0}, tangent.size(), [&](size_t e) {
      if (edges_[e].crease) return;
      AddTangentRows(edges_[e], tangent_weight, &tangent[e]);
    });

    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(num_vars_, 3);
    for (const LocalBlock& block : blocks) block.AppendTo(&triplets, &rhs);
    for (const LocalBlock& block : tangent) block.AppendTo(&triplets, &rhs);
    Eigen::SparseMatrix<double> normal(num_vars_, num_vars_);
    normal.setFromTriplets(triplets.begin(), triplets.end());
    double trace = 0.0;
    for (int k = 0; k < num_vars_; ++k) trace += normal.coeff(k, k);
    for (int k = 0; k < num_vars_; ++k) {
      normal.coeffRef(k, k) += 1e-12 * trace / num_vars_;
    }
    SDCB_ASSIGN_OR_RETURN(const Eigen::MatrixX3d x,
                          SolveNormalEquations(normal, rhs));
    for (size_t f = 0; f < faces_.size(); ++f) {
      BSplineFace& face = faces_[f];
      face.poles.assign(terms_[f].size(), Eigen::Vector3d::Zero());
      for (size_t q = 0; q < face.poles.size(); ++q) {
        for (const auto& [var, w] : terms_[f][q]) {
          face.poles[q] += w * x.row(var).transpose();
        }
      }
    }
    curves_.assign(edges_.size(), {});
    for (size_t e = 0; e < edges_.size(); ++e) {
      CadEdge& curve = curves_[e];
      curve.breaks = edges_[e].breaks;
      curve.start = edges_[e].start;
      curve.end = edges_[e].end;
      for (const int var : edges_[e].vars) {
        curve.poles.push_back(x.row(var).transpose());
      }
    }
    return Status::Ok();
  }
  const std::vector<CadEdge>& curves() const { return curves_; }

  // Halves the spans marked per face (u spans, v spans).
  void Split(const std::vector<std::array<std::vector<bool>, 2>>& marked) {
    for (size_t f = 0; f < faces_.size(); ++f) {
      for (int d = 0; d < 2; ++d) {
        KnotBreaks& b = d == 0 ? faces_[f].u_breaks : faces_[f].v_breaks;
        KnotBreaks next;
        for (size_t s = 0; s + 1 < b.size(); ++s) {
          next.push_back(b[s]);
          if (marked[f][d][s] && b[s + 1] - b[s] > kMinSpan) {
            next.push_back(0.5 * (b[s] + b[s + 1]));
          }
        }
        next.push_back(b.back());
        b = std::move(next);
      }
    }
  }

 private:
  // Vertices by their sphere points; sides paired into edges by their two
  // vertices.
  void BuildTopology() {
    std::map<std::array<long long, 3>, int> vertex;
    const auto vertex_of = [&](const Eigen::Vector3d& p) {
      const std::array<long long, 3> key = {std::llround(p.x() * 1e9),
                                            std::llround(p.y() * 1e9),
                                            std::llround(p.z() * 1e9)};
      return vertex.try_emplace(key, static_cast<int>(vertex.size()))
          .first->second;
    };
    std::map<std::pair<int, int>, int> edge_of;
    face_edges_.assign(faces_.size(), {});
    for (size_t f = 0; f < faces_.size(); ++f) {
      for (int k = 0; k < 4; ++k) {
        const SideFrame s = SideFrameOf(faces_[f], k);
        const KnotBreaks& along = AlongBreaks(faces_[f], k);
        const Eigen::Vector2d a = SidePoint(s, along.front());
        const Eigen::Vector2d b = SidePoint(s, along.back());
        const int start = vertex_of(Sphere(static_cast<int>(f), a.x(), a.y()));
        const int end = vertex_of(Sphere(static_cast<int>(f), b.x(), b.y()));
        auto [it, inserted] =
            edge_of.try_emplace({std::min(start, end), std::max(start, end)},
                                static_cast<int>(edges_.size()));
        if (inserted) {
          Edge e;
          e.face[0] = static_cast<int>(f);
          e.side[0] = k;
          e.face[1] = e.side[1] = -1;
          e.start = start;
          e.end = end;
          e.crease = OnCrease(static_cast<int>(f), k);
          edges_.push_back(e);
        } else {
          edges_[it->second].face[1] = static_cast<int>(f);
          edges_[it->second].side[1] = k;
        }
        face_edges_[f][k] = it->second;
      }
    }
    num_vertices_ = static_cast<int>(vertex.size());
  }

  // Adds `c` times pole (i, j) of face f into `coef` (by the block's local
  // indices).
  void AddPole(int f, int i, int j, double c, LocalBlock* block,
               std::vector<double>* coef) const {
    if (c == 0.0) return;
    for (const auto& [var, w] : terms_[f][j * faces_[f].num_u() + i]) {
      const int k = block->Index(var);
      if (static_cast<int>(coef->size()) <= k) coef->resize(k + 1, 0.0);
      (*coef)[k] += c * w;
    }
  }

  // The coefficients of face f's derivative along `direction` (0: u, 1: v)
  // at (u, v), times `scale`.
  void AddDerivative(int f, double u, double v, int direction, double scale,
                     LocalBlock* block, std::vector<double>* coef) const {
    const BSplineFace& face = faces_[f];
    const int su = KnotSpan(face.u_breaks, u), sv = KnotSpan(face.v_breaks, v);
    double n_u[4], d_u[4], n_v[4], d_v[4];
    CubicBSplineBasis(face.u_breaks, su, u, n_u, d_u);
    CubicBSplineBasis(face.v_breaks, sv, v, n_v, d_v);
    for (int b = 0; b < 4; ++b) {
      for (int a = 0; a < 4; ++a) {
        const double c = direction == 0 ? d_u[a] * n_v[b] : n_u[a] * d_v[b];
        AddPole(f, su + a, sv + b, scale * c, block, coef);
      }
    }
  }

  // The tangent-plane rows of one edge: at a point of it, the sphere map's
  // derivatives out of face 0 (A), out of face 1 (B) and along the edge (E)
  // satisfy A = alpha B + beta E; the spline's surface satisfies the same
  // relation between its derivatives, and the rows ask the faces to:
  // X_0,out - alpha X_1,out - beta X_e = 0, divided by |dS(A)|.
  void AddTangentRows(const Edge& e, double weight, LocalBlock* block) const {
    const BSplineFace &f0 = faces_[e.face[0]], &f1 = faces_[e.face[1]];
    const SideFrame s0 = SideFrameOf(f0, e.side[0]);
    const SideFrame s1 = SideFrameOf(f1, e.side[1]);
    const KnotBreaks b =
        UnionKnots(AlongBreaks(f0, e.side[0]), AlongBreaks(f1, e.side[1]));
    const int m = static_cast<int>(b.size()) - 1;
    for (int s = 0; s < m; ++s) {
      const double h = b[s + 1] - b[s];
      std::vector<std::pair<double, double>> points;  // t, row weight
      for (int k = 0; k < 4; ++k) {
        points.push_back(
            {b[s] + Gauss().x[k] * h, std::sqrt(Gauss().w[k] * h)});
      }
      if (s == 0) points.push_back({b.front(), std::sqrt(0.25 * h)});
      if (s == m - 1) points.push_back({b.back(), std::sqrt(0.25 * h)});
      for (const auto& [t, w] : points) {
        const Eigen::Vector2d p0 = SidePoint(s0, t), p1 = SidePoint(s1, t);
        Eigen::Vector3d d0[2], d1[2];
        const Eigen::Vector3d p =
            Sphere(e.face[0], p0.x(), p0.y(), &d0[0], &d0[1]);
        Sphere(e.face[1], p1.x(), p1.y(), &d1[0], &d1[1]);
        const int out0 = 1 - s0.along, out1 = 1 - s1.along;
        const Eigen::Vector3d a = s0.out * d0[out0];
        const Eigen::Vector3d bb = s1.out * d1[out1];
        const Eigen::Vector3d along = d0[s0.along];
        Eigen::Matrix<double, 3, 2> basis;
        basis << bb, along;
        const Eigen::Vector2d ab =
            (basis.transpose() * basis).ldlt().solve(basis.transpose() * a);
        // |dS(A)| by central differences on the sphere.
        const Eigen::Vector3d step = 1e-5 * a.normalized();
        // Not below kMinDerivative: where the spline is nearly singular
        // the rows would outweigh everything else.
        const double scale = std::max(
            kMinDerivative,
            (surface_.Evaluate(p + step) - surface_.Evaluate(p - step)).norm() /
                (2e-5 / a.norm()));
        std::vector<double> coef(block->size(), 0.0);
        AddDerivative(e.face[0], p0.x(), p0.y(), out0, s0.out, block, &coef);
        AddDerivative(e.face[1], p1.x(), p1.y(), out1, -ab[0] * s1.out, block,
                      &coef);
        AddDerivative(e.face[0], p0.x(), p0.y(), s0.along, -ab[1], block,
                      &coef);
        coef.resize(block->size(), 0.0);
        block->AddRow(coef, weight * w / scale, Eigen::Vector3d::Zero());
      }
    }
  }

  const PiecewiseSurface& surface_;
  const CadQuadLayout& layout_;
  std::vector<BSplineFace> faces_;
  std::vector<int> quad_;
  std::vector<std::array<int, 4>> face_edges_;
  std::vector<Edge> edges_;
  std::vector<CadEdge> curves_;
  std::vector<std::vector<PoleTerms>> terms_;
  int num_vertices_ = 0;
  int num_vars_ = 0;
};

double AngleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kDegrees;
}

// Per knot cell of the faces: the largest distance and normal angle on its
// lattice, its sum of squared distances times area and its area, and the
// points above 90 degrees.
struct CellFigures {
  int face = 0, su = 0, sv = 0;
  double max_distance = 0.0, max_angle = 0.0;
  double squared = 0.0, area = 0.0;
  int64_t folded = 0;
  // How much the residual X - S changes between lattice neighbours along u
  // and along v (summed): which of the cell's spans a split should halve.
  double change_u = 0.0, change_v = 0.0;
};

std::vector<CellFigures> MeasureCells(const NetworkFitter& fitter,
                                      const PiecewiseSurface& surface, int n) {
  const std::vector<BSplineFace>& faces = fitter.faces();
  std::vector<CellFigures> cells;
  for (int f = 0; f < fitter.num_faces(); ++f) {
    const int mu = static_cast<int>(faces[f].u_breaks.size()) - 1;
    const int mv = static_cast<int>(faces[f].v_breaks.size()) - 1;
    for (int sv = 0; sv < mv; ++sv) {
      for (int su = 0; su < mu; ++su) {
        CellFigures c;
        c.face = f;
        c.su = su;
        c.sv = sv;
        cells.push_back(c);
      }
    }
  }
  const int per_cell = (n + 1) * (n + 1);
  const auto parameter = [&](const CellFigures& c, int k, double* u,
                             double* v) {
    const KnotBreaks &bu = faces[c.face].u_breaks, &bv = faces[c.face].v_breaks;
    const int i = k % (n + 1), j = k / (n + 1);
    *u = bu[c.su] + (bu[c.su + 1] - bu[c.su]) * i / n;
    *v = bv[c.sv] + (bv[c.sv + 1] - bv[c.sv]) * j / n;
  };
  Eigen::MatrixX3d directions(
      static_cast<Eigen::Index>(cells.size()) * per_cell, 3);
  tbb::parallel_for(size_t{0}, cells.size(), [&](size_t c) {
    for (int k = 0; k < per_cell; ++k) {
      double u, v;
      parameter(cells[c], k, &u, &v);
      directions.row(c * per_cell + k) = fitter.Sphere(cells[c].face, u, v);
    }
  });
  Eigen::MatrixX3d positions, normals;
  if (!fitter.layout().has_creases()) {
    surface.EvaluateMany(directions, &positions, &normals);
  } else {
    // The spline's normal at a point on a crease is either side's: it is
    // taken kCreaseInset of the face's parameter box inside the face.
    Eigen::MatrixX3d inside = directions;
    tbb::parallel_for(size_t{0}, cells.size(), [&](size_t c) {
      const CellFigures& cell = cells[c];
      const BSplineFace& face = faces[cell.face];
      const double inset_u =
          kCreaseInset * (face.u_breaks.back() - face.u_breaks.front());
      const double inset_v =
          kCreaseInset * (face.v_breaks.back() - face.v_breaks.front());
      for (int k = 0; k < per_cell; ++k) {
        double u, v;
        parameter(cell, k, &u, &v);
        const double u0 = u, v0 = v;
        if (v == face.v_breaks.front() && fitter.OnCrease(cell.face, 0)) {
          v += inset_v;
        }
        if (u == face.u_breaks.back() && fitter.OnCrease(cell.face, 1)) {
          u -= inset_u;
        }
        if (v == face.v_breaks.back() && fitter.OnCrease(cell.face, 2)) {
          v -= inset_v;
        }
        if (u == face.u_breaks.front() && fitter.OnCrease(cell.face, 3)) {
          u += inset_u;
        }
        if (u != u0 || v != v0) {
          inside.row(c * per_cell + k) = fitter.Sphere(cell.face, u, v);
        }
      }
    });
    surface.EvaluateMany(directions, &positions, nullptr);
    Eigen::MatrixX3d inside_positions;
    surface.EvaluateMany(inside, &inside_positions, &normals);
  }
  tbb::parallel_for(size_t{0}, cells.size(), [&](size_t c) {
    CellFigures& cell = cells[c];
    const BSplineFace& face = faces[cell.face];
    const KnotBreaks &bu = face.u_breaks, &bv = face.v_breaks;
    const double cell_area = (bu[cell.su + 1] - bu[cell.su]) *
                             (bv[cell.sv + 1] - bv[cell.sv]) / (n * n);
    std::vector<Eigen::Vector3d> residual(per_cell);
    for (int k = 0; k < per_cell; ++k) {
      double u, v;
      parameter(cell, k, &u, &v);
      Eigen::Vector3d du, dv;
      const Eigen::Vector3d x = face.Evaluate(u, v, &du, &dv);
      const Eigen::Index r = static_cast<Eigen::Index>(c) * per_cell + k;
      residual[k] = x - positions.row(r).transpose();
      const double d = residual[k].norm();
      cell.max_distance = std::max(cell.max_distance, d);
      const double a = du.cross(dv).norm() * cell_area;
      cell.squared += d * d * a;
      cell.area += a;
      const Eigen::Vector3d s = normals.row(r);
      if (s.squaredNorm() > 0.0) {
        const double angle = AngleDegrees(du.cross(dv), s);
        cell.max_angle = std::max(cell.max_angle, angle);
        if (angle > 90.0) ++cell.folded;
      }
    }
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const int k = j * (n + 1) + i;
        if (i < n) cell.change_u += (residual[k + 1] - residual[k]).norm();
        if (j < n) cell.change_v += (residual[k + n + 1] - residual[k]).norm();
      }
    }
  });
  return cells;
}

// The largest angle between the two faces' normals along every edge but
// the creases, at 8 points of every span of both faces' knots and the ends;
// the points.
double MaxNormalJump(const NetworkFitter& fitter, int* points) {
  const std::vector<BSplineFace>& faces = fitter.faces();
  double jump = 0.0;
  *points = 0;
  for (const NetworkFitter::Edge& e : fitter.edges()) {
    if (e.crease) continue;  // the spline turns there too
    const BSplineFace &f0 = faces[e.face[0]], &f1 = faces[e.face[1]];
    const SideFrame s0 = SideFrameOf(f0, e.side[0]);
    const SideFrame s1 = SideFrameOf(f1, e.side[1]);
    const KnotBreaks b =
        UnionKnots(AlongBreaks(f0, e.side[0]), AlongBreaks(f1, e.side[1]));
    for (size_t s = 0; s + 1 < b.size(); ++s) {
      for (int k = 0; k < 8 + (s + 2 == b.size() ? 1 : 0); ++k) {
        const double t = b[s] + (b[s + 1] - b[s]) * k / 8.0;
        const Eigen::Vector2d p0 = SidePoint(s0, t), p1 = SidePoint(s1, t);
        Eigen::Vector3d du0, dv0, du1, dv1;
        f0.Evaluate(p0.x(), p0.y(), &du0, &dv0);
        f1.Evaluate(p1.x(), p1.y(), &du1, &dv1);
        jump = std::max(jump, AngleDegrees(du0.cross(dv0), du1.cross(dv1)));
        ++*points;
      }
    }
  }
  return jump;
}

// A face's boundary is its edge's curve, which has only the knots both
// faces share: a cell at a side that is split along the side gets the
// neighbour's span through the split split too, so that the side can follow
// (one level; the neighbour's own cells carry it further if they need).
void PropagateAcrossSides(
    const NetworkFitter& fitter, const std::vector<CellFigures>& cells,
    std::vector<std::array<std::vector<bool>, 2>>* marked) {
  const std::vector<BSplineFace>& faces = fitter.faces();
  std::vector<std::array<std::vector<bool>, 2>> added = *marked;
  for (const CellFigures& c : cells) {
    const BSplineFace& face = faces[c.face];
    const int mu = static_cast<int>(face.u_breaks.size()) - 1;
    const int mv = static_cast<int>(face.v_breaks.size()) - 1;
    for (int k = 0; k < 4; ++k) {
      const bool at_side = (k == 0 && c.sv == 0) ||
                           (k == 1 && c.su == mu - 1) ||
                           (k == 2 && c.sv == mv - 1) || (k == 3 && c.su == 0);
      const int along = k % 2;  // 0: u, 1: v
      const int span = along == 0 ? c.su : c.sv;
      if (!at_side || !(*marked)[c.face][along][span]) continue;
      const KnotBreaks& b = AlongBreaks(face, k);
      const double x = 0.5 * (b[span] + b[span + 1]);
      const NetworkFitter::Edge& e =
          fitter.edges()[fitter.face_edges()[c.face][k]];
      const int other = e.face[0] == c.face && e.side[0] == k ? 1 : 0;
      const int g = e.face[other], side = e.side[other];
      const KnotBreaks& gb = AlongBreaks(faces[g], side);
      if (std::binary_search(gb.begin(), gb.end(), x)) continue;
      added[g][side % 2][KnotSpan(gb, x)] = true;
    }
  }
  *marked = std::move(added);
}

}  // namespace

StatusOr<CadNetwork> FitCadNetwork(const SphericalSpline& spline,
                                   const CadNetworkOptions& o) {
  if (!(o.tolerance_percent > 0.0) || !(o.length_unit > 0.0) ||

      !(o.smoothness_degrees > 0.0) || !(o.tangent_weight > 0.0) ||
      o.initial_spans < 1 || o.max_rounds < 1 || o.measure_per_cell < 1 ||
      o.max_control_points < 1 || o.face_grid < 1 || o.face_grid > 64 ||
      (o.face_grid & (o.face_grid - 1)) != 0 ||
      (o.initial_spans & (o.initial_spans - 1)) != 0) {
    return InvalidArgumentError(
        "the CAD network needs a positive tolerance, smoothness, tangent "
        "weight, length unit, rounds, lattice and control point budget, and "
        "a face grid and initial spans that are powers of 2 (grid <= 64)");
  }
  std::optional<CadQuadLayout> layout;
  if (o.follow_creases) {
    layout = FeatureQuadLayout(FeatureArcsOfKnots(spline.knots()));
  }
  if (!layout) layout = CubeSphereLayout(o.face_grid);
  const int num_faces = layout->num_quads() * layout->grid * layout->grid;
  if (o.max_faces < num_faces) {
    return InvalidArgumentError(
        "the CAD network has " + std::to_string(num_faces) +
        " faces, more than the face budget " + std::to_string(o.max_faces));
  }
  const PiecewiseSurface surface(spline);
  const double tolerance = o.tolerance_percent / 100.0 * o.length_unit;
  NetworkFitter fitter(surface, *layout, o.initial_spans);
  CadNetwork net;
  net.layout = *layout;
  for (const NetworkFitter::Edge& e : fitter.edges())
    net.crease_edges += e.crease;
  // Without a smoothness limit the faces are fitted to the distance alone.
  double tangent_weight =
      o.smoothness_degrees >= 180.0 ? 0.0 : o.tangent_weight;
  // The distance of the last rounds that refined, to see it grow.
  std::vector<double> refined_distance;
  for (int round = 1; round <= o.max_rounds; ++round) {
    const Stopwatch round_watch;
    Stopwatch watch;
    fitter.NumberPoles();
    if (round > 1 && fitter.num_vars() > o.max_control_points) {
      net.stop_reason = "control point budget";
      return net;
    }
    SDCB_RETURN_IF_ERROR(fitter.Fit(tangent_weight));
    net.fit_seconds += watch.Seconds();
    watch.Restart();
    net.rounds = round;
    net.faces = fitter.faces();
    net.face_quad = fitter.quad();
    net.face_edges = fitter.face_edges();
    net.edges = fitter.curves();
    net.num_vertices = fitter.num_vertices();
    net.control_points = fitter.num_vars();
    const std::vector<CellFigures> cells =
        MeasureCells(fitter, surface, o.measure_per_cell);
    net.face_max_distance_percent.assign(net.faces.size(), 0.0);
    double squared = 0.0, area = 0.0, max_distance = 0.0;
    net.max_normal_angle_degrees = 0.0;
    net.folded_points = 0;
    std::vector<std::array<std::vector<bool>, 2>> marked(net.faces.size());
    for (size_t f = 0; f < net.faces.size(); ++f) {
      marked[f][0].assign(net.faces[f].u_breaks.size() - 1, false);
      marked[f][1].assign(net.faces[f].v_breaks.size() - 1, false);
    }
    for (const CellFigures& c : cells) {
      squared += c.squared;
      area += c.area;
      max_distance = std::max(max_distance, c.max_distance);
      net.face_max_distance_percent[c.face] =
          std::max(net.face_max_distance_percent[c.face],
                   100.0 * c.max_distance / o.length_unit);
      net.max_normal_angle_degrees =
          std::max(net.max_normal_angle_degrees, c.max_angle);
      net.folded_points += c.folded;
      if (c.max_distance > 0.95 * tolerance) {
        // Halve the spans along which the residual changes (both unless one
        // direction changes less than kAnisotropy as much).
        // A cell at a side halves its span along the side too: the side's
        // curve must be able to follow what the cell does.
        const double most = std::max(c.change_u, c.change_v);
        const int mu = static_cast<int>(net.faces[c.face].u_breaks.size()) - 1;
        const int mv = static_cast<int>(net.faces[c.face].v_breaks.size()) - 1;
        const bool at_u_side = c.sv == 0 || c.sv == mv - 1;  // sides 0, 2
        const bool at_v_side = c.su == 0 || c.su == mu - 1;  // sides 1, 3
        if (c.change_u >= kAnisotropy * most || at_u_side) {
          marked[c.face][0][c.su] = true;
        }
        if (c.change_v >= kAnisotropy * most || at_v_side) {
          marked[c.face][1][c.sv] = true;
        }
      }
    }
    const int per_cell = (o.measure_per_cell + 1) * (o.measure_per_cell + 1);
    net.measured_points = static_cast<int64_t>(cells.size()) * per_cell;
    net.max_distance_percent = 100.0 * max_distance / o.length_unit;
    net.rms_distance_percent =
        area > 0.0 ? 100.0 * std::sqrt(squared / area) / o.length_unit : 0.0;
    net.max_normal_jump_degrees = MaxNormalJump(fitter, &net.jump_points);
    net.measure_seconds += watch.Seconds();

    const bool distance_ok = max_distance <= tolerance;
    const bool smooth_ok = net.max_normal_jump_degrees <= o.smoothness_degrees;
    CadNetwork::Round figures;
    figures.knot_cells = static_cast<int>(cells.size());
    figures.control_points = net.control_points;
    figures.tangent_weight = tangent_weight;
    figures.max_distance_percent = net.max_distance_percent;
    figures.rms_distance_percent = net.rms_distance_percent;
    figures.max_normal_jump_degrees = net.max_normal_jump_degrees;
    figures.max_normal_angle_degrees = net.max_normal_angle_degrees;
    figures.folded_points = net.folded_points;
    figures.seconds = round_watch.Seconds();
    net.history.push_back(figures);
    if (o.progress) {
      char stage[160];
      std::snprintf(stage, sizeof(stage),
                    "round %d, %d control points, %.3g%%, jump %.2g deg", round,
                    net.control_points, net.max_distance_percent,
                    net.max_normal_jump_degrees);
      o.progress(stage, std::min(1.0, round / 10.0));
    }
    if (distance_ok && smooth_ok) {
      net.within_tolerance = true;
      net.stop_reason.clear();
      return net;
    }
    if (round == o.max_rounds) {
      net.stop_reason = "round budget";
      return net;
    }
    if (!distance_ok) {
      // Refining should bring the distance down; where the spline folds or
      // is singular the tangent rows cannot hold and it grows instead.
      refined_distance.push_back(max_distance);
      const size_t n = refined_distance.size();
      if (n >= 3 && refined_distance[n - 1] > refined_distance[n - 2] &&
          refined_distance[n - 2] > refined_distance[n - 3]) {
        net.stop_reason =
            "the distance grew for two refinements: the spline may fold or "
            "be singular there";
        return net;
      }
      PropagateAcrossSides(fitter, cells, &marked);
      fitter.Split(marked);
    }
    if (!smooth_ok && distance_ok) tangent_weight *= 10.0;
  }
  return net;
}

}  // namespace sdcb
