#include "sdcb/core/measure/closest_surface_points.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {
namespace {

// Steps longer than this (radians on the sphere) are shortened to it.
constexpr double kMaxStep = 0.5;
// Halvings of a step that does not bring the point nearer.
constexpr int kHalvings = 4;
// A point whose step was shorter than this (radians) has converged: the
// next step would change its distance by about the square of it.
constexpr double kConverged = 1e-7;

// The longest step of ClosestSurfacePoint, radians.
constexpr double kMaxJetStep = 0.2;

ChartPoint ToChartPoint(const SurfacePoint& s) {
  ChartPoint out;
  out.position = s.position;
  out.du = s.du;
  out.dv = s.dv;
  return out;
}

}  // namespace

double GaussNewtonClosest(
    const Eigen::Vector3d& x, ChartPoint current, int iterations,
    double max_step,
    const std::function<void(const Eigen::Vector2d&, ChartPoint*)>& try_step,
    const std::function<void()>& accept) {
  double best = (current.position - x).norm();
  for (int it = 0; it < iterations && best > 0; ++it) {
    const Eigen::Vector3d r = current.position - x;
    const Eigen::Vector3d& du = current.du;
    const Eigen::Vector3d& dv = current.dv;
    Eigen::Matrix2d jtj;
    jtj << du.dot(du), du.dot(dv), du.dot(dv), dv.dot(dv);
    const Eigen::Vector2d jtr(du.dot(r), dv.dot(r));
    const double det = jtj.determinant();
    if (!(std::abs(det) > 1e-300)) break;
    Eigen::Vector2d step = -jtj.inverse() * jtr;
    if (max_step > 0) {
      const double length = step.norm();
      if (length > max_step) step *= max_step / length;
    }
    bool improved = false;
    for (int halving = 0; halving < 4; ++halving, step *= 0.5) {
      ChartPoint candidate;
      try_step(step, &candidate);
      const double d = (candidate.position - x).norm();
      if (d < best) {
        best = d;
        current = candidate;
        accept();
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  return best;
}

double ClosestSurfacePoint(const SurfaceSampler& surface,
                           const Eigen::Vector3d& x,
                           const Eigen::Vector3d& start, int iterations,
                           Eigen::Vector3d* found) {
  Eigen::Vector3d p = start, q;
  SurfacePoint s = surface.EvaluateJet(p), t;
  const double best = GaussNewtonClosest(
      x, ToChartPoint(s), iterations, kMaxJetStep,
      [&](const Eigen::Vector2d& step, ChartPoint* point) {
        q = (p + step[0] * s.frame_u + step[1] * s.frame_v).normalized();
        t = surface.EvaluateJet(q);
        *point = ToChartPoint(t);
      },
      [&] {
        p = q;
        s = t;
      });
  if (found) *found = p;
  return best;
}

Eigen::VectorXd ClosestSurfacePoints(const SurfaceSampler& surface,
                                     const Eigen::MatrixX3d& points,
                                     int iterations,
                                     Eigen::MatrixX3d* directions,
                                     int64_t* evaluations, double good_enough) {
  const Eigen::MatrixX3d& x = points;
  Eigen::MatrixX3d& u = *directions;
  const Eigen::Index n = x.rows();
  const double h = 1e-6;
  int64_t sampled = n;
  Eigen::VectorXd best(n);
  {
    Eigen::MatrixX3d s;
    surface.Sample(u, &s, nullptr);
    best = (x - s).rowwise().norm();
  }
  std::vector<Eigen::Index> active;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (best[i] > good_enough) active.push_back(i);
  }
  for (int iteration = 0; iteration < iterations && !active.empty();
       ++iteration) {
    // The Jacobian at u by forward differences along a tangent frame.
    const Eigen::Index m = static_cast<Eigen::Index>(active.size());
    Eigen::MatrixX3d probe(3 * m, 3), eu(m, 3), ev(m, 3);
    for (Eigen::Index j = 0; j < m; ++j) {
      const Eigen::Vector3d p = u.row(active[j]).transpose();
      Eigen::Vector3d a, b;
      TangentFrame(p, &a, &b);
      eu.row(j) = a;
      ev.row(j) = b;
      probe.row(3 * j) = p;
      probe.row(3 * j + 1) = (p + h * a).normalized();
      probe.row(3 * j + 2) = (p + h * b).normalized();
    }
    Eigen::MatrixX3d s;
    surface.Sample(probe, &s, nullptr);
    sampled += probe.rows();
    Eigen::MatrixX2d step(m, 2);
    for (Eigen::Index j = 0; j < m; ++j) {
      const Eigen::Vector3d s0 = s.row(3 * j).transpose();
      Eigen::Matrix<double, 3, 2> jacobian;
      jacobian.col(0) = (s.row(3 * j + 1).transpose() - s0) / h;
      jacobian.col(1) = (s.row(3 * j + 2).transpose() - s0) / h;
      Eigen::Vector2d d = (jacobian.transpose() * jacobian)
                              .ldlt()
                              .solve(jacobian.transpose() *
                                     (x.row(active[j]).transpose() - s0));
      if (!d.allFinite()) d.setZero();
      if (d.norm() > kMaxStep) d *= kMaxStep / d.norm();
      step.row(j) = d.transpose();
    }
    // Take each step, halved while it does not bring the point nearer.
    std::vector<Eigen::Index> trying(m), moved;
    for (Eigen::Index j = 0; j < m; ++j) trying[j] = j;
    for (int halving = 0; halving <= kHalvings && !trying.empty(); ++halving) {
      const Eigen::Index t = static_cast<Eigen::Index>(trying.size());
      Eigen::MatrixX3d candidate(t, 3);
      for (Eigen::Index k = 0; k < t; ++k) {
        const Eigen::Index j = trying[k];
        candidate.row(k) =
            (u.row(active[j]) + step(j, 0) * eu.row(j) + step(j, 1) * ev.row(j))
                .normalized();
      }
      Eigen::MatrixX3d c;
      surface.Sample(candidate, &c, nullptr);
      sampled += t;
      std::vector<Eigen::Index> rejected;
      for (Eigen::Index k = 0; k < t; ++k) {
        const Eigen::Index j = trying[k], i = active[j];
        const double d = (x.row(i) - c.row(k)).norm();
        if (d < best[i]) {
          best[i] = d;
          u.row(i) = candidate.row(k);
          if (step.row(j).norm() > kConverged && d > good_enough) {
            moved.push_back(j);
          }
        } else {
          step.row(j) *= 0.5;
          rejected.push_back(j);
        }
      }
      trying = std::move(rejected);
    }
    // Points that did not move, or barely, are where the search ends.
    std::sort(moved.begin(), moved.end());
    std::vector<Eigen::Index> next;
    for (Eigen::Index j : moved) next.push_back(active[j]);
    active = std::move(next);
  }
  if (evaluations) *evaluations += sampled;
  return best;
}

}  // namespace sdcb
