#include "sdcb/core/param/spherical_parameterization.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/mesh_hierarchy.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/param/parameterization_distortion.h"
#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {

Eigen::Vector3d Row(const Eigen::MatrixX3d& m, int i) {
  return m.row(i).transpose();
}

// Points on S^2, one per vertex, stored contiguously (a row of a
// column-major Eigen matrix is spread over three arrays: three cache misses
// per neighbor instead of one in the optimizer's inner loop).
using Points = std::vector<Eigen::Vector3d>;

Points ToPoints(const Eigen::MatrixX3d& m) {
  Points p(m.rows());
  for (Eigen::Index i = 0; i < m.rows(); ++i) p[i] = Row(m, i);
  return p;
}

Eigen::MatrixX3d ToMatrix(const Points& p) {
  Eigen::MatrixX3d m(p.size(), 3);
  for (size_t i = 0; i < p.size(); ++i) m.row(i) = p[i].transpose();
  return m;
}

// One triangle as seen from one of its corners v: the other two corners in
// counter-clockwise order and the mesh shape rotated so that v is corner 0.
struct Incidence {
  int a = -1;
  int b = -1;
  MeshTriangleShape shape;
};

// One greedy step of a vertex at *p along the great circle of steepest
// descent of `energy`, with backtracking from *step (radians); only
// positions where the energy drops (Armijo) are taken. `trial(q, limit)` is
// the energy at q if q is a valid position and that energy is at most
// `limit`, else anything above `limit` (it may stop summing early).
// Adapts *step and returns the energy decrease (0 if no move).
template <typename EnergyFn, typename TrialFn>
double GreatCircleStep(Eigen::Vector3d* p, double* step, const EnergyFn& energy,
                       const TrialFn& trial) {
  constexpr int kMaxHalvings = 12;
  constexpr double kArmijo = 1e-4;
  constexpr double kMaxStep = 0.5;
  Eigen::Vector3d gradient;
  const double e0 = energy(*p, &gradient);
  if (!std::isfinite(e0)) return 0.0;
  const Eigen::Vector3d tangent = gradient - gradient.dot(*p) * *p;
  const double slope = tangent.norm();
  if (!(slope > 0.0)) return 0.0;
  const Eigen::Vector3d direction = -tangent / slope;
  double t = *step;
  for (int k = 0; k < kMaxHalvings; ++k, t *= 0.5) {
    const Eigen::Vector3d q =
        (std::cos(t) * *p + std::sin(t) * direction).normalized();
    const double limit = e0 - kArmijo * t * slope;
    const double e1 = trial(q, limit);
    if (e1 <= limit) {
      *p = q;
      *step = std::min(2.0 * t, kMaxStep);
      return e0 - e1;
    }
  }
  *step = std::max(t, 1e-12);
  return 0.0;
}

// The current level of the hierarchy: which faces and vertices are alive.
struct LevelState {
  Eigen::MatrixX3i faces;
  std::vector<bool> face_alive;
  std::vector<bool> vertex_alive;
};

// Greedy per-vertex minimization of eq. (12) on one level (Sec. 4.3).
class LevelOptimizer {
 public:
  LevelOptimizer(const Eigen::MatrixX3d& mesh_positions, double lambda)
      : mesh_positions_(mesh_positions), lambda_(lambda) {}

  void set_lambda(double lambda) { lambda_ = lambda; }
  double lambda() const { return lambda_; }

  // Rebuilds the one-rings, shapes, colors and step sizes for `level`.
  void Prepare(const LevelState& level, const Points& sphere) {
    const int nv = static_cast<int>(mesh_positions_.rows());
    std::vector<int> alive_faces;
    for (int f = 0; f < level.faces.rows(); ++f) {
      if (level.face_alive[f]) alive_faces.push_back(f);
    }
    std::vector<MeshTriangleShape> shapes(alive_faces.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, alive_faces.size(), 1024),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) {
                          const int f = alive_faces[i];
                          shapes[i] = ComputeMeshTriangleShape(
                              Corner(level, f, 0), Corner(level, f, 1),
                              Corner(level, f, 2), 1.0);
                        }
                      });
    double total_area = 0.0;
    for (const MeshTriangleShape& shape : shapes) total_area += shape.area;
    const double scale = 4.0 * kPi / total_area;
    // Incidences in CSR order: vertex v owns [offset_[v], offset_[v + 1]).
    offset_.assign(nv + 1, 0);
    for (int f : alive_faces) {
      for (int i = 0; i < 3; ++i) ++offset_[level.faces(f, i) + 1];
    }
    for (int v = 0; v < nv; ++v) offset_[v + 1] += offset_[v];
    incidences_.assign(offset_[nv], Incidence());
    std::vector<int> fill(offset_.begin(), offset_.end() - 1);
    for (size_t j = 0; j < alive_faces.size(); ++j) {
      const int f = alive_faces[j];
      MeshTriangleShape shape = shapes[j];
      shape.area *= scale;
      for (int i = 0; i < 3; ++i) {
        Incidence& inc = incidences_[fill[level.faces(f, i)]++];
        inc.a = level.faces(f, (i + 1) % 3);
        inc.b = level.faces(f, (i + 2) % 3);
        inc.shape = RotateShape(shape, i);
      }
    }
    // Greedy coloring in vertex order: same colors on every run.
    std::vector<int> color(nv, -1);
    color_classes_.clear();
    alive_.clear();
    std::vector<char> used;
    for (int v = 0; v < nv; ++v) {
      if (!level.vertex_alive[v]) continue;
      alive_.push_back(v);
      used.assign(offset_[v + 1] - offset_[v] + 1, 0);
      for (int k = offset_[v]; k < offset_[v + 1]; ++k) {
        for (int w : {incidences_[k].a, incidences_[k].b}) {
          if (color[w] >= 0 && color[w] < static_cast<int>(used.size())) {
            used[color[w]] = 1;
          }
        }
      }
      int c = 0;
      while (used[c]) ++c;
      color[v] = c;
      if (c >= static_cast<int>(color_classes_.size()))
        color_classes_.resize(c + 1);
      color_classes_[c].push_back(v);
    }
    // Initial step: a quarter of the mean one-ring edge length on S^2.
    step_.assign(nv, 0.0);
    tbb::parallel_for(tbb::blocked_range<int>(0, nv, 1024),
                      [&](const tbb::blocked_range<int>& r) {
                        for (int v = r.begin(); v != r.end(); ++v) {
                          double sum = 0.0;
                          for (int k = offset_[v]; k < offset_[v + 1]; ++k) {
                            sum +=
                                (sphere[incidences_[k].a] - sphere[v]).norm();
                          }
                          const int n = offset_[v + 1] - offset_[v];
                          if (n > 0) step_[v] = 0.25 * sum / n;
                        }
                      });
    decrease_.assign(nv, 0.0);
  }

  // Eq. (12) over the level's faces (each face once, summed in order).
  double Energy(const Points& sphere) const {
    std::vector<double> local(alive_.size(), 0.0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, alive_.size(), 256),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) {
                          const int v = alive_[i];
                          local[i] = LocalEnergy(v, sphere[v], sphere, nullptr);
                        }
                      });
    double e = 0.0;
    for (double l : local) e += l;  // vertex order: same for any threads
    return e / 3.0;
  }

  // Sweeps until the relative decrease of E per sweep is below `tolerance`
  // or `max_sweeps` were run. Returns the final energy.
  double Optimize(Points* sphere, int max_sweeps, double tolerance,
                  double active_fraction) {
    double energy = Energy(*sphere);
    // Active set: a vertex is visited again only if it or a neighbor
    // lowered E by more than `active_fraction` times its share of the
    // stopping threshold (tolerance * E / vertices) in the previous sweep.
    // Else its one-ring energy is unchanged (active_fraction = 0, the
    // default: the line search already failed there), or changed so little
    // that all such vertices together could lower E by at most
    // active_fraction times the threshold per sweep (on the bunny, 99 % of
    // a fine level's decrease comes from 3-20 % of its vertices).
    // Per-sweep bookkeeping runs over the level's vertices only (a coarse
    // level of a large input has a few hundred of its millions); the other
    // entries of `decrease_` stay 0 and do not change the sums.
    std::vector<char> active(decrease_.size(), 1);
    for (int sweep = 0; sweep < max_sweeps; ++sweep) {
      for (int v : alive_) decrease_[v] = 0.0;
      for (const std::vector<int>& cls : color_classes_) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, cls.size(), 64),
                          [&](const tbb::blocked_range<size_t>& r) {
                            for (size_t i = r.begin(); i != r.end(); ++i) {
                              if (active[cls[i]]) MoveVertex(cls[i], sphere);
                            }
                          });
      }
      double decrease = 0.0;
      for (int v : alive_) decrease += decrease_[v];  // fixed order
      energy -= decrease;
      if (decrease < tolerance * energy || sweep + 1 == max_sweeps) break;
      const double threshold = active_fraction * tolerance * energy /
                               static_cast<double>(alive_.size());
      tbb::parallel_for(tbb::blocked_range<size_t>(0, alive_.size(), 1024),
                        [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t i = r.begin(); i != r.end(); ++i) {
                            const int v = alive_[i];
                            bool moved = decrease_[v] > threshold;
                            for (int k = offset_[v];
                                 k < offset_[v + 1] && !moved; ++k) {
                              moved = decrease_[incidences_[k].a] > threshold;
                            }
                            active[v] = moved;
                          }
                        });
    }
    return energy;
  }

  // Global limited-memory BFGS on all of the level's vertices at once
  // (`memory` pairs), for the low-frequency part of eq. (12) that per-vertex
  // moves reach only slowly (area has to flow across the whole sphere). The
  // iterate is a point of (S^2)^n: a step moves every vertex along its
  // tangent direction and renormalizes; the curvature pairs are the
  // differences of positions and of tangent gradients in R^3n. A step is
  // taken only if every triangle stays positively oriented (exact) and the
  // energy drops (Armijo). Stops after `iterations` or when an iteration
  // lowers E by less than `tolerance` times E. Returns the final energy.
  double OptimizeGlobal(Eigen::MatrixX3d* sphere, int iterations,
                        double tolerance, int memory = 8) {
    const int nv = static_cast<int>(decrease_.size());
    Eigen::MatrixX3d gradient(nv, 3);
    double energy = EnergyAndGradient(ToPoints(*sphere), &gradient);
    std::vector<Eigen::MatrixX3d> s_hist, y_hist;
    std::vector<double> rho_hist;
    double first_step = 0.0;  // radians of the largest move, first iteration
    for (const double st : step_) first_step = std::max(first_step, st);
    for (int it = 0; it < iterations; ++it) {
      // Two-loop recursion: direction = -H gradient.
      Eigen::MatrixX3d q = gradient;
      const int m = static_cast<int>(s_hist.size());
      std::vector<double> alpha(m);
      for (int i = m - 1; i >= 0; --i) {
        alpha[i] = rho_hist[i] * Dot(s_hist[i], q);
        q -= alpha[i] * y_hist[i];
      }
      if (m > 0) {
        q *= Dot(s_hist[m - 1], y_hist[m - 1]) /
             Dot(y_hist[m - 1], y_hist[m - 1]);
      } else {
        // First iteration: scale so that the largest vertex move is
        // first_step radians.
        double largest = 0.0;
        for (int v = 0; v < nv; ++v)
          largest = std::max(largest, q.row(v).norm());
        if (!(largest > 0.0)) break;
        q *= first_step / largest;
      }
      for (int i = 0; i < m; ++i) {
        const double beta = rho_hist[i] * Dot(y_hist[i], q);
        q += (alpha[i] - beta) * s_hist[i];
      }
      Eigen::MatrixX3d direction = -q;
      ProjectToTangent(*sphere, &direction);
      double slope = Dot(direction, gradient);
      if (!(slope < 0.0)) {  // not a descent direction: restart
        s_hist.clear();
        y_hist.clear();
        rho_hist.clear();
        continue;
      }
      constexpr int kMaxHalvings = 30;
      constexpr double kArmijo = 1e-4;
      Eigen::MatrixX3d trial(nv, 3);
      double t = 1.0, trial_energy = 0.0;
      bool accepted = false;
      for (int k = 0; k < kMaxHalvings && !accepted; ++k, t *= 0.5) {
        for (int v = 0; v < nv; ++v) {
          trial.row(v) = (sphere->row(v) + t * direction.row(v)).normalized();
        }
        const Points trial_points = ToPoints(trial);
        if (!AllValid(trial_points)) continue;
        trial_energy = Energy(trial_points);
        accepted = trial_energy <= energy + kArmijo * t * slope;
        if (accepted) break;
      }
      if (!accepted) break;
      Eigen::MatrixX3d new_gradient(nv, 3);
      trial_energy = EnergyAndGradient(ToPoints(trial), &new_gradient);
      const double decrease = energy - trial_energy;
      Eigen::MatrixX3d s = trial - *sphere;
      Eigen::MatrixX3d y = new_gradient - gradient;
      *sphere = trial;
      gradient = new_gradient;
      energy = trial_energy;
      const double sy = Dot(s, y);
      if (sy > 1e-12 * std::sqrt(Dot(s, s) * Dot(y, y))) {
        if (static_cast<int>(s_hist.size()) == memory) {
          s_hist.erase(s_hist.begin());
          y_hist.erase(y_hist.begin());
          rho_hist.erase(rho_hist.begin());
        }
        s_hist.push_back(std::move(s));
        y_hist.push_back(std::move(y));
        rho_hist.push_back(1.0 / sy);
      }
      if (decrease < tolerance * energy) break;
    }
    return energy;
  }

 private:
  // Sum of the entry-wise products, in row order (deterministic).
  static double Dot(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b) {
    double sum = 0.0;
    for (int v = 0; v < a.rows(); ++v) sum += a.row(v).dot(b.row(v));
    return sum;
  }

  static void ProjectToTangent(const Eigen::MatrixX3d& sphere,
                               Eigen::MatrixX3d* vectors) {
    for (int v = 0; v < sphere.rows(); ++v) {
      const Eigen::RowVector3d p = sphere.row(v);
      vectors->row(v) -= vectors->row(v).dot(p) * p;
    }
  }

  // E (eq. 12) and its gradient, projected onto each vertex's tangent plane
  // (zero rows for vertices not on the level).
  double EnergyAndGradient(const Points& sphere,
                           Eigen::MatrixX3d* gradient) const {
    const int nv = static_cast<int>(sphere.size());
    std::vector<double> local(nv, 0.0);
    tbb::parallel_for(tbb::blocked_range<int>(0, nv, 256),
                      [&](const tbb::blocked_range<int>& r) {
                        for (int v = r.begin(); v != r.end(); ++v) {
                          Eigen::Vector3d g = Eigen::Vector3d::Zero();
                          const Eigen::Vector3d& p = sphere[v];
                          local[v] = LocalEnergy(v, p, sphere, &g);
                          gradient->row(v) = (g - g.dot(p) * p).transpose();
                        }
                      });
    double e = 0.0;
    for (double l : local) e += l;  // fixed order
    return e / 3.0;
  }

  // True if every triangle of the level is positively oriented (exact).
  bool AllValid(const Points& sphere) const {
    const int nv = static_cast<int>(sphere.size());
    return tbb::parallel_reduce(
        tbb::blocked_range<int>(0, nv, 256), true,
        [&](const tbb::blocked_range<int>& r, bool ok) {
          for (int v = r.begin(); v != r.end() && ok; ++v) {
            ok = OneRingValid(v, sphere[v], sphere);
          }
          return ok;
        },
        [](bool a, bool b) { return a && b; });
  }

  Eigen::Vector3d Corner(const LevelState& level, int f, int i) const {
    return Row(mesh_positions_, level.faces(f, i));
  }

  // Energy of v's one-ring with v at p (p on S^2), and its gradient in R^3.
  double LocalEnergy(int v, const Eigen::Vector3d& p, const Points& sphere,
                     Eigen::Vector3d* gradient) const {
    double e = 0.0;
    if (gradient != nullptr) gradient->setZero();
    Eigen::Vector3d g;
    for (int k = offset_[v]; k < offset_[v + 1]; ++k) {
      const Incidence& inc = incidences_[k];
      e += TriangleEnergy(inc.shape, p, sphere[inc.a], sphere[inc.b], lambda_,
                          gradient != nullptr ? &g : nullptr);
      if (gradient != nullptr) *gradient += g;
    }
    return e;
  }

  // LocalEnergy without gradient if every triangle of v's one-ring is
  // positively oriented with v at p (exact sign) and the energy is at most
  // `limit`; else infinity (summing stops once the terms, all positive,
  // exceed `limit`).
  double TrialEnergy(int v, const Eigen::Vector3d& p, const Points& sphere,
                     double limit) const {
    double e = 0.0;
    for (int k = offset_[v]; k < offset_[v + 1]; ++k) {
      const Incidence& inc = incidences_[k];
      const Eigen::Vector3d& a = sphere[inc.a];
      const Eigen::Vector3d& b = sphere[inc.b];
      double det;
      if (SmallTriangleDet3Sign(p, a, b, &det) <= 0) {
        return std::numeric_limits<double>::infinity();
      }
      e += TriangleEnergyWithDet(inc.shape, p, a, b, det, lambda_);
      if (!(e <= limit)) return std::numeric_limits<double>::infinity();
    }
    return e;
  }

  // True if every triangle of v's one-ring is positively oriented with v at p.
  bool OneRingValid(int v, const Eigen::Vector3d& p,
                    const Points& sphere) const {
    for (int k = offset_[v]; k < offset_[v + 1]; ++k) {
      double det;
      if (SmallTriangleDet3Sign(p, sphere[incidences_[k].a],
                                sphere[incidences_[k].b], &det) <= 0) {
        return false;
      }
    }
    return true;
  }

  // One greedy step of v (Sec. 4.3's line search on great circles).
  void MoveVertex(int v, Points* sphere) {
    Eigen::Vector3d p = (*sphere)[v];
    decrease_[v] = GreatCircleStep(
        &p, &step_[v],
        [&](const Eigen::Vector3d& q, Eigen::Vector3d* g) {
          return LocalEnergy(v, q, *sphere, g);
        },
        [&](const Eigen::Vector3d& q, double limit) {
          return TrialEnergy(v, q, *sphere, limit);
        });
    (*sphere)[v] = p;
  }

  const Eigen::MatrixX3d& mesh_positions_;
  double lambda_;
  std::vector<int> offset_;
  std::vector<Incidence> incidences_;
  std::vector<std::vector<int>> color_classes_;
  std::vector<int> alive_;  // the level's vertices, ascending
  std::vector<double> step_;
  std::vector<double> decrease_;
};

// Per vertex, its faces as (a, b): the other two corners counter-clockwise.
using FaceRings = std::vector<std::vector<std::pair<int, int>>>;

// The Tutte embedding of the base mesh minus `pole`, centrally projected
// onto the northern hemisphere, plus `pole` at the south pole. Fails when a
// triangle comes out folded: exact in theory, but the embedding shrinks
// geometrically with the graph distance from the pole's link, and along a
// long thin part the innermost triangles fall below double precision.
Status EmbedBaseMeshFrom(const LevelState& level, const FaceRings& ring,
                         int pole, Points* sphere) {
  const int nv = static_cast<int>(level.vertex_alive.size());
  // The pole's link counter-clockwise; in the plane it must run clockwise
  // for the disk's faces to be counter-clockwise.
  std::map<int, int> next(ring[pole].begin(), ring[pole].end());
  std::vector<int> link = {ring[pole][0].first};
  while (link.size() < next.size()) link.push_back(next.at(link.back()));
  constexpr double kBoundaryRadius = 2.0;  // in the plane z = 1
  std::vector<int> index(nv, -1);          // unknown index, -2 for fixed
  std::vector<Eigen::Vector2d> plane(nv, Eigen::Vector2d::Zero());
  for (size_t i = 0; i < link.size(); ++i) {
    const double angle = -2.0 * kPi * static_cast<double>(i) / link.size();
    plane[link[i]] =
        kBoundaryRadius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    index[link[i]] = -2;
  }
  index[pole] = -2;
  int unknowns = 0;
  for (int v = 0; v < nv; ++v) {
    if (level.vertex_alive[v] && index[v] == -1) index[v] = unknowns++;
  }
  // Uniform Laplacian: deg(v) x_v - sum_{interior w} x_w = sum_{boundary w}
  // x_w.
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(unknowns, 2);
  for (int v = 0; v < nv; ++v) {
    if (index[v] < 0) continue;
    triplets.emplace_back(index[v], index[v],
                          static_cast<double>(ring[v].size()));
    for (const auto& [w, unused] : ring[v]) {
      if (index[w] >= 0) {
        triplets.emplace_back(index[v], index[w], -1.0);
      } else {
        rhs.row(index[v]) += plane[w].transpose();
      }
    }
  }
  if (unknowns > 0) {
    Eigen::SparseMatrix<double> laplacian(unknowns, unknowns);
    laplacian.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
    if (solver.info() != Eigen::Success) {
      return InternalError(
          "the base mesh's Tutte system could not be factored");
    }
    const Eigen::MatrixX2d x = solver.solve(rhs);
    for (int v = 0; v < nv; ++v) {
      if (index[v] >= 0) plane[v] = x.row(index[v]).transpose();
    }
  }
  sphere->assign(nv, Eigen::Vector3d::Zero());
  for (int v = 0; v < nv; ++v) {
    if (!level.vertex_alive[v]) continue;
    (*sphere)[v] =
        Eigen::Vector3d(plane[v].x(), plane[v].y(), 1.0).normalized();
  }
  (*sphere)[pole] = Eigen::Vector3d(0.0, 0.0, -1.0);
  for (int f = 0; f < level.faces.rows(); ++f) {
    if (!level.face_alive[f]) continue;
    if (Det3Sign((*sphere)[level.faces(f, 0)], (*sphere)[level.faces(f, 1)],
                 (*sphere)[level.faces(f, 2)]) <= 0) {
      return InternalError(
          "the base mesh's Tutte embedding has a folded triangle");
    }
  }
  return Status::Ok();
}

// The vertex whose largest graph distance to another is smallest (the
// lowest index among equals): as the pole, it leaves the shallowest disk.
int GraphCenter(const LevelState& level, const FaceRings& ring) {
  const int nv = static_cast<int>(level.vertex_alive.size());
  int best = -1, best_depth = nv;
  std::vector<int> distance(nv, -1);
  std::vector<int> queue;
  for (int s = 0; s < nv; ++s) {
    if (!level.vertex_alive[s]) continue;
    for (int v : queue) distance[v] = -1;  // the last search's vertices
    queue.assign(1, s);
    distance[s] = 0;
    int depth = 0;
    for (size_t head = 0; head < queue.size(); ++head) {
      const int v = queue[head];
      depth = distance[v];
      for (const auto& [w, unused] : ring[v]) {
        if (distance[w] < 0) {
          distance[w] = depth + 1;
          queue.push_back(w);
        }
      }
    }
    if (depth < best_depth) {
      best_depth = depth;
      best = s;
    }
  }
  return best;
}

// Step 2 of the method: EmbedBaseMeshFrom the vertex of highest degree, or,
// when that folds, from the graph center.
Status EmbedBaseMesh(const LevelState& level, Points* sphere) {
  const int nv = static_cast<int>(level.vertex_alive.size());
  FaceRings ring(nv);
  for (int f = 0; f < level.faces.rows(); ++f) {
    if (!level.face_alive[f]) continue;
    for (int i = 0; i < 3; ++i) {
      ring[level.faces(f, i)].emplace_back(level.faces(f, (i + 1) % 3),
                                           level.faces(f, (i + 2) % 3));
    }
  }
  int pole = -1;
  for (int v = 0; v < nv; ++v) {
    if (level.vertex_alive[v] &&
        (pole < 0 || ring[v].size() > ring[pole].size())) {
      pole = v;
    }
  }
  const Status status = EmbedBaseMeshFrom(level, ring, pole, sphere);
  if (status.ok()) return status;
  const int center = GraphCenter(level, ring);
  if (center == pole) return status;
  return EmbedBaseMeshFrom(level, ring, center, sphere);
}

// Step 4: puts the vertex a collapse removed back inside the kernel of its
// one-ring on S^2 (all one-ring triangles positively oriented, checked
// exactly), at the candidate whose worst one-ring triangle is fattest.
Status PlaceSplitVertex(const HalfEdgeCollapse& collapse,
                        const Eigen::MatrixX3d& mesh_positions,
                        double area_scale, double lambda, Points* sphere) {
  const std::vector<int>& link = collapse.link;
  const size_t k = link.size();
  // Smallest det(q,a,b) / (|q-a| |q-b| |a-b|) over the one-ring (a sine
  // over a length: scale-aware fatness), or -1 if a triangle is not
  // positively oriented. Validity is the exact sign; the fatness is a
  // floating-point value that only ranks valid candidates, clamped at 0
  // (on tiny triangles its rounding error exceeds it).
  const Points& s = *sphere;
  auto score = [&](const Eigen::Vector3d& q) {
    double worst = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < k; ++i) {
      const Eigen::Vector3d& a = s[link[i]];
      const Eigen::Vector3d& b = s[link[(i + 1) % k]];
      double det;
      if (SmallTriangleDet3Sign(q, a, b, &det) <= 0) return -1.0;
      worst = std::min(
          worst, det / ((q - a).norm() * (q - b).norm() * (a - b).norm()));
    }
    return std::max(worst, 0.0);
  };
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int w : link) centroid += s[w];
  centroid.normalize();
  const Eigen::Vector3d u = s[collapse.kept];
  std::vector<Eigen::Vector3d> candidates = {centroid};
  for (double t : {0.25, 0.5, 0.75}) {
    candidates.push_back((u + t * (centroid - u)).normalized());
  }
  Eigen::Vector3d best = centroid;
  double best_score = -1.0;
  auto consider = [&](const Eigen::Vector3d& q) {
    const double s = score(q);
    if (s > best_score) {
      best_score = s;
      best = q;
    }
  };
  for (const Eigen::Vector3d& q : candidates) consider(q);
  if (best_score < 0.0) {
    // Near the kept vertex u, inside the wedge between its edges to the
    // first and last link vertices: valid for a small enough offset,
    // because the fan around u was valid.
    auto tangent = [&](int w) {
      const Eigen::Vector3d d = s[w] - u;
      return Eigen::Vector3d(d - d.dot(u) * u);
    };
    const Eigen::Vector3d t1 = tangent(link[1]), t2 = tangent(link[k - 1]);
    const Eigen::Vector3d bisector = t1.normalized() + t2.normalized();
    const Eigen::Vector3d side = u.cross(t1.normalized());
    const double reach = 0.5 * std::min(t1.norm(), t2.norm());
    int extra_halvings = 3;
    for (double eps = reach; eps > 1e-14 * reach && extra_halvings > 0;
         eps *= 0.5) {
      for (const Eigen::Vector3d& d : {bisector, Eigen::Vector3d(-bisector),
                                       side, Eigen::Vector3d(-side)}) {
        if (d.norm() > 1e-9) consider((u + eps * d.normalized()).normalized());
      }
      if (best_score >= 0.0) --extra_halvings;
    }
  }
  if (best_score < 0.0) {
    return InternalError(
        "a vertex split found no valid position on the sphere");
  }
  // A few descent steps of the new vertex alone, so that vertices split
  // next to it later in the same level find a fat one-ring.
  constexpr int kRelaxSteps = 3;
  std::vector<MeshTriangleShape> shapes(k);
  for (size_t i = 0; i < k; ++i) {
    shapes[i] = ComputeMeshTriangleShape(
        Row(mesh_positions, collapse.removed), Row(mesh_positions, link[i]),
        Row(mesh_positions, link[(i + 1) % k]), area_scale);
  }
  auto energy = [&](const Eigen::Vector3d& q, Eigen::Vector3d* gradient) {
    double e = 0.0;
    Eigen::Vector3d g;
    if (gradient != nullptr) gradient->setZero();
    for (size_t i = 0; i < k; ++i) {
      e += TriangleEnergy(shapes[i], q, s[link[i]], s[link[(i + 1) % k]],
                          lambda, gradient != nullptr ? &g : nullptr);
      if (gradient != nullptr) *gradient += g;
    }
    return e;
  };
  double step = 0.0;
  for (size_t i = 0; i < k; ++i) step += (s[link[i]] - best).norm();
  step *= 0.25 / k;
  for (int i = 0; i < kRelaxSteps; ++i) {
    GreatCircleStep(
        &best, &step, energy, [&](const Eigen::Vector3d& q, double) {
          return score(q) >= 0.0 ? energy(q, nullptr)
                                 : std::numeric_limits<double>::infinity();
        });
  }
  (*sphere)[collapse.removed] = best;
  return Status::Ok();
}

// Step 4 for the collapses [first, last) of the hierarchy, undone from the
// back: the same positions as PlaceSplitVertex on each, from last - 1 down to
// first, computed in parallel. A split reads only the positions of its link
// and writes that of its removed vertex, and its link vertices were removed
// (if at all) by later collapses; so the splits are grouped in waves, a
// split's wave one after the latest wave that placed one of its link
// vertices, and the splits of one wave are independent.
Status PlaceSplitVertices(const std::vector<HalfEdgeCollapse>& collapses,
                          size_t first, size_t last,
                          const Eigen::MatrixX3d& mesh_positions,
                          double area_scale, double lambda, Points* sphere) {
  std::vector<int> wave_of_vertex(sphere->size(), -1);
  std::vector<std::vector<size_t>> waves;
  for (size_t j = last; j-- > first;) {
    int wave = 0;
    for (int w : collapses[j].link) {
      wave = std::max(wave, wave_of_vertex[w] + 1);
    }
    wave_of_vertex[collapses[j].removed] = wave;
    if (wave >= static_cast<int>(waves.size())) waves.resize(wave + 1);
    waves[wave].push_back(j);
  }
  std::vector<char> failed(last - first, 0);
  for (const std::vector<size_t>& wave : waves) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, wave.size(), 16),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) {
                          const size_t j = wave[i];
                          failed[j - first] =
                              !PlaceSplitVertex(collapses[j], mesh_positions,
                                                area_scale, lambda, sphere)
                                   .ok();
                        }
                      });
  }
  for (char f : failed) {
    if (f) {
      return InternalError(
          "a vertex split found no valid position on the sphere");
    }
  }
  return Status::Ok();
}

}  // namespace

Status CheckSphericalBijection(const TriangleMesh& mesh,
                               const Eigen::MatrixX3d& sphere) {
  if (sphere.rows() != mesh.num_vertices()) {
    return InvalidArgumentError(
        "parameterization size does not match the mesh");
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!(std::abs(sphere.row(v).norm() - 1.0) <= 1e-12)) {
      return InternalError("vertex " + std::to_string(v) +
                           " is off the unit sphere");
    }
  }
  // Per face in parallel (the sign exact, by the filtered predicate), the
  // first bad face and the area sum in face order: the same answer for any
  // number of threads.
  const int nf = mesh.num_faces();
  std::vector<double> area(nf);
  const int first_bad = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, nf, 1024), nf,
      [&](const tbb::blocked_range<int>& r, int bad) {
        for (int f = r.begin(); f != r.end(); ++f) {
          const Eigen::Vector3d a = Row(sphere, mesh.faces(f, 0));
          const Eigen::Vector3d b = Row(sphere, mesh.faces(f, 1));
          const Eigen::Vector3d c = Row(sphere, mesh.faces(f, 2));
          double det;
          if (SmallTriangleDet3Sign(a, b, c, &det) <= 0) {
            bad = std::min(bad, f);
            area[f] = 0.0;
          } else {
            area[f] = SphericalTriangleArea(a, b, c);
          }
        }
        return bad;
      },
      [](int x, int y) { return std::min(x, y); });
  if (first_bad < nf) {
    return InternalError("sphere triangle " + std::to_string(first_bad) +
                         " is folded or degenerate");
  }
  double total = 0.0;
  for (double x : area) total += x;
  if (std::abs(total - 4.0 * kPi) > 1e-6) {
    return InternalError("sphere triangles cover S^2 " +
                         std::to_string(total / (4.0 * kPi)) +
                         " times, not once");
  }
  return Status::Ok();
}

StatusOr<SphericalParameterization> ParameterizeOnSphere(
    const TriangleMesh& mesh, const SphericalParameterizationOptions& options) {
  if (!(options.lambda > 0.0) || !std::isfinite(options.lambda)) {
    return InvalidArgumentError("lambda must be a finite number > 0");
  }
  if (options.level_growth <= 1.0 || options.threads < 0) {
    return InvalidArgumentError("level_growth must be > 1 and threads >= 0");
  }
  SDCB_RETURN_IF_ERROR(RequireClosedGenusZero(mesh));
  auto report = [&](const std::string& stage, double fraction) {
    if (options.progress) options.progress(stage, fraction);
  };

  tbb::task_arena arena(options.threads > 0 ? options.threads
                                            : tbb::task_arena::automatic);
  MeshHierarchyOptions hierarchy_options;
  hierarchy_options.base_vertices = std::max(4, options.base_vertices);
  report("hierarchy", 0.0);
  SDCB_ASSIGN_OR_RETURN(MeshHierarchy hierarchy, arena.execute([&] {
    return BuildMeshHierarchy(mesh, hierarchy_options);
  }));
  LevelState level{std::move(hierarchy.faces), std::move(hierarchy.face_alive),
                   std::move(hierarchy.vertex_alive)};
  SDCB_ASSIGN_OR_RETURN(const double area_scale, AreaScaleToUnitSphere(mesh));
  SphericalParameterization result;
  result.base_vertices =
      mesh.num_vertices() - static_cast<int>(hierarchy.collapses.size());

  Status status = Status::Ok();
  arena.execute([&] {
    Points sphere;
    report("base", 0.0);
    status = EmbedBaseMesh(level, &sphere);
    if (!status.ok()) return;
    LevelOptimizer optimizer(mesh.vertices, options.lambda);
    optimizer.Prepare(level, sphere);
    // Continuation in lambda: a large lambda makes eq. (12) so stiff that
    // descent from the Tutte embedding stalls. Rounds of `sweeps` with lambda
    // growing by `lambda_growth` from `from` up to `to`.
    auto optimize_rising = [&](double from, double to, int sweeps,
                               double tolerance) {
      for (double lambda = from;;
           lambda = std::min(options.lambda_growth * lambda, to)) {
        optimizer.set_lambda(lambda);
        result.energy = optimizer.Optimize(&sphere, sweeps, tolerance,
                                           options.active_fraction);
        if (lambda >= to) break;
      }
    };
    const double start_lambda = std::min(1.0, options.lambda);
    const double coarse_lambda =
        std::min(options.lambda, options.coarse_lambda);
    optimize_rising(start_lambda, coarse_lambda, options.base_sweeps,
                    options.level_tolerance);
    result.levels = 1;
    int alive = result.base_vertices;
    size_t next = hierarchy.collapses.size();
    while (next > 0) {
      report("optimize", static_cast<double>(alive) / mesh.num_vertices());
      int target =
          std::max(alive + 1, static_cast<int>(alive * options.level_growth));
      // A large level within sqrt(level_growth) of the input is the input:
      // a level of nearly the input's size costs as much as the finest.
      if (target > options.large_level_vertices &&
          target * std::sqrt(options.level_growth) > mesh.num_vertices()) {
        target = mesh.num_vertices();
      }
      const size_t last = next;
      while (next > 0 && alive < target) {
        UndoCollapse(hierarchy.collapses[--next], &level.faces,
                     &level.face_alive, &level.vertex_alive);
        ++alive;
      }
      status =
          PlaceSplitVertices(hierarchy.collapses, next, last, mesh.vertices,
                             area_scale, optimizer.lambda(), &sphere);
      if (!status.ok()) return;
      optimizer.Prepare(level, sphere);
      // Levels within `rising_levels` of the finest raise lambda to its
      // final value.
      const bool rising =
          static_cast<double>(mesh.num_vertices()) <=
          alive * std::pow(options.level_growth, options.rising_levels - 1);
      const double from = optimizer.lambda();
      const double to = rising ? options.lambda : coarse_lambda;
      // Small levels converge tightly; large ones stop early (the options).
      const bool finest = next == 0;
      const bool large = alive > options.large_level_vertices;
      const bool small =
          !finest &&
          alive <= std::min(options.small_level_fraction * mesh.num_vertices(),
                            static_cast<double>(options.small_level_vertices));
      const int sweeps = large    ? options.large_level_sweeps
                         : finest ? options.finest_sweeps
                                  : options.level_sweeps;
      const double tolerance = small   ? options.level_tolerance
                               : large ? options.large_level_tolerance
                                       : options.finest_tolerance;
      optimize_rising(from, to, sweeps, tolerance);
      if (finest && options.global_iterations > 0) {
        Eigen::MatrixX3d matrix = ToMatrix(sphere);
        result.energy = optimizer.OptimizeGlobal(
            &matrix, options.global_iterations, options.global_tolerance);
        sphere = ToPoints(matrix);
      }
      ++result.levels;
    }
    result.sphere = ToMatrix(sphere);
  });
  SDCB_RETURN_IF_ERROR(status);
  report("optimize", 1.0);
  arena.execute([&] { status = CheckSphericalBijection(mesh, result.sphere); });
  SDCB_RETURN_IF_ERROR(status);
  return result;
}

}  // namespace sdcb
