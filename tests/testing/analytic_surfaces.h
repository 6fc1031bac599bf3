// Surfaces over S^2 with closed-form geometry, as SurfaceSamplers: oracles
// for the tessellator and the optimal-count quadrature.
#ifndef SDCB_TESTS_TESTING_ANALYTIC_SURFACES_H_
#define SDCB_TESTS_TESTING_ANALYTIC_SURFACES_H_

#include <Eigen/Core>
#include <cmath>
#include <utility>
#include <vector>

#include "sdcb/core/measure/surface_sampler.h"

namespace sdcb::testing {

// The ellipsoid S(u) = diag(a) u (a sphere of radius r for a = (r, r, r)).
class EllipsoidSampler : public SurfaceSampler {
 public:
  explicit EllipsoidSampler(const Eigen::Vector3d& axes) : axes_(axes) {}
  void Sample(const Eigen::MatrixX3d& d, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override {
    positions->resize(d.rows(), 3);
    if (normals) normals->resize(d.rows(), 3);
    for (Eigen::Index i = 0; i < d.rows(); ++i) {
      const Eigen::Vector3d u = d.row(i).transpose();
      positions->row(i) = axes_.cwiseProduct(u).transpose();
      // Gradient of sum x_i^2 / a_i^2 at x = a u: u / a.
      if (normals) normals->row(i) = u.cwiseQuotient(axes_).normalized();
    }
  }
  bool SampleCurvature(const Eigen::MatrixX3d& d, Eigen::VectorXd* gaussian,
                       Eigen::VectorXd* mean) const override {
    gaussian->resize(d.rows());
    mean->resize(d.rows());
    const double abc = axes_.prod();
    for (Eigen::Index i = 0; i < d.rows(); ++i) {
      const Eigen::Vector3d x = axes_.cwiseProduct(d.row(i).transpose());
      double s = 0;
      for (int k = 0; k < 3; ++k) s += x[k] * x[k] / std::pow(axes_[k], 4);
      (*gaussian)[i] = 1.0 / (abc * abc * s * s);
      (*mean)[i] = std::nan("");  // not needed by the tests
    }
    return true;
  }
  // Distance from x to the ellipsoid (Eberly's root of
  // sum (a_k x_k / (t + a_k^2))^2 = 1), by bisection on t.
  double Distance(const Eigen::Vector3d& x) const {
    auto f = [&](double t) {
      double s = 0;
      for (int k = 0; k < 3; ++k) {
        const double r = axes_[k] * x[k] / (t + axes_[k] * axes_[k]);
        s += r * r;
      }
      return s - 1.0;
    };
    const double amin = axes_.minCoeff();
    double lo = -amin * amin, hi = x.norm() * axes_.maxCoeff() + 1.0;
    // f decreases from +inf (or a finite value) on (lo, inf).
    lo += 1e-15 * amin * amin;
    if (f(lo) < 0) {
      // x deep inside along the shortest axis: the root is at lo.
      hi = lo;
    }
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (f(mid) > 0)
        lo = mid;
      else
        hi = mid;
    }
    const double t = 0.5 * (lo + hi);
    Eigen::Vector3d y;
    for (int k = 0; k < 3; ++k) {
      y[k] = axes_[k] * axes_[k] * x[k] / (t + axes_[k] * axes_[k]);
    }
    return (x - y).norm();
  }

 private:
  Eigen::Vector3d axes_;
};

// The same ellipsoid over a twisted domain: S(u) = diag(a) R_z(twist u_z) u,
// each latitude rotated about z by an angle proportional to its height. The
// surface (and every distance to it) is the ellipsoid's; the map from the
// sphere is sheared sideways, as a spherical parameterization of a scan is
// where it squeezes: the image of a domain triangle's edge bends within
// the surface.
class TwistedEllipsoidSampler : public EllipsoidSampler {
 public:
  TwistedEllipsoidSampler(const Eigen::Vector3d& axes, double twist)
      : EllipsoidSampler(axes), twist_(twist) {}
  void Sample(const Eigen::MatrixX3d& d, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override {
    EllipsoidSampler::Sample(Twisted(d), positions, normals);
  }
  bool SampleCurvature(const Eigen::MatrixX3d& d, Eigen::VectorXd* gaussian,
                       Eigen::VectorXd* mean) const override {
    return EllipsoidSampler::SampleCurvature(Twisted(d), gaussian, mean);
  }

 private:
  Eigen::MatrixX3d Twisted(const Eigen::MatrixX3d& d) const {
    Eigen::MatrixX3d out(d.rows(), 3);
    for (Eigen::Index i = 0; i < d.rows(); ++i) {
      const double angle = twist_ * d(i, 2);
      const double c = std::cos(angle), s = std::sin(angle);
      out(i, 0) = c * d(i, 0) - s * d(i, 1);
      out(i, 1) = s * d(i, 0) + c * d(i, 1);
      out(i, 2) = d(i, 2);
    }
    return out;
  }
  double twist_;
};

// A unit sphere with narrow Gaussian bumps: S(u) = r(u) u with
// r(u) = 1 + sum_k height * exp((u . c_k - 1) / width), the bumps' centres
// c_k unit vectors. Its curvature changes sign on each bump's flank within
// a few faces, where a face's largest distance from the surface can sit
// between the points of a sample lattice. Normals in closed form: for a
// radial graph, n ~ r u - grad_T r (grad_T the tangential gradient).
class BumpySphereSampler : public SurfaceSampler {
 public:
  BumpySphereSampler(std::vector<Eigen::Vector3d> centres, double height,
                     double width)
      : centres_(std::move(centres)), height_(height), width_(width) {}
  void Sample(const Eigen::MatrixX3d& d, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override {
    positions->resize(d.rows(), 3);
    if (normals) normals->resize(d.rows(), 3);
    for (Eigen::Index i = 0; i < d.rows(); ++i) {
      const Eigen::Vector3d u = d.row(i).transpose();
      double r = 1.0;
      Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& c : centres_) {
        const double e = height_ * std::exp((u.dot(c) - 1.0) / width_);
        r += e;
        gradient += (e / width_) * c;
      }
      positions->row(i) = (r * u).transpose();
      if (normals) {
        const Eigen::Vector3d tangential = gradient - gradient.dot(u) * u;
        normals->row(i) = (r * u - tangential).normalized().transpose();
      }
    }
  }

 private:
  std::vector<Eigen::Vector3d> centres_;
  double height_, width_;
};

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_ANALYTIC_SURFACES_H_
