#include "sdcb/core/measure/surface_sampler.h"

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {
namespace {

// The first-order part of a shape as a SurfacePoint (the chart of the
// tangent frame at `direction`).
SurfacePoint JetOfShape(const Eigen::Vector3d& direction,
                        const SurfaceShape& shape) {
  SurfacePoint out;
  out.position = shape.position;
  TangentFrame(direction.normalized(), &out.frame_u, &out.frame_v);
  out.du = shape.du;
  out.dv = shape.dv;
  out.normal = shape.normal;
  return out;
}

// A PiecewiseSplineSampler that owns its PiecewiseSurface.
class OwningPiecewiseSampler : public PiecewiseSplineSampler {
 public:
  OwningPiecewiseSampler(const SphericalSpline& spline,
                         std::unique_ptr<PiecewiseSurface> pieces)
      : PiecewiseSplineSampler(spline, *pieces), pieces_(std::move(pieces)) {}

 private:
  std::unique_ptr<PiecewiseSurface> pieces_;
};

}  // namespace

Eigen::Vector3d SurfaceSampler::Evaluate(
    const Eigen::Vector3d& direction) const {
  const Eigen::MatrixX3d row = direction.transpose();
  Eigen::MatrixX3d positions;
  Sample(row, &positions, nullptr);
  return positions.row(0).transpose();
}

Eigen::Vector3d SurfaceSampler::EvaluateNormal(
    const Eigen::Vector3d& direction) const {
  const Eigen::MatrixX3d row = direction.transpose();
  Eigen::MatrixX3d positions, normals;
  Sample(row, &positions, &normals);
  return normals.row(0).transpose();
}

SurfacePoint SurfaceSampler::EvaluateJet(
    const Eigen::Vector3d& direction) const {
  const Eigen::MatrixX3d row = direction.transpose();
  std::vector<SurfaceShape> shapes;
  if (SampleShape(row, &shapes)) {
    return JetOfShape(direction, shapes[0]);
  }
  SurfacePoint out;
  out.position = Evaluate(direction);
  TangentFrame(direction.normalized(), &out.frame_u, &out.frame_v);
  return out;
}

std::unique_ptr<SurfaceSampler> MakeSplineSampler(const SphericalSpline& spline,
                                                  bool polynomials) {
  if (!polynomials) return std::make_unique<SplineSampler>(spline);
  return std::make_unique<OwningPiecewiseSampler>(
      spline, std::make_unique<PiecewiseSurface>(spline));
}

void SplineSampler::Sample(const Eigen::MatrixX3d& directions,
                           Eigen::MatrixX3d* positions,
                           Eigen::MatrixX3d* normals) const {
  if (normals == nullptr) {
    *positions = spline_.EvaluateMany(directions);
    return;
  }
  const std::vector<SurfacePoint> jets =
      spline_.EvaluateDifferentialMany(directions, JetOrder::kGradient);
  positions->resize(directions.rows(), 3);
  normals->resize(directions.rows(), 3);
  for (size_t i = 0; i < jets.size(); ++i) {
    positions->row(i) = jets[i].position.transpose();
    normals->row(i) = jets[i].normal.transpose();
  }
}

bool SplineSampler::SampleCurvature(const Eigen::MatrixX3d& directions,
                                    Eigen::VectorXd* gaussian,
                                    Eigen::VectorXd* mean) const {
  const std::vector<SurfacePoint> jets =
      spline_.EvaluateDifferentialMany(directions, JetOrder::kHessian);
  gaussian->resize(directions.rows());
  mean->resize(directions.rows());
  for (size_t i = 0; i < jets.size(); ++i) {
    (*gaussian)[i] = jets[i].gaussian_curvature;
    (*mean)[i] = jets[i].mean_curvature;
  }
  return true;
}

bool SplineSampler::SampleShape(const Eigen::MatrixX3d& directions,
                                std::vector<SurfaceShape>* shapes) const {
  shapes->resize(directions.rows());
  spline_.basis().ParallelForEachPoint(directions, [&](Eigen::Index r) {
    (*shapes)[r] = spline_.EvaluateShape(directions.row(r).transpose());
  });
  return true;
}

void PiecewiseSplineSampler::Sample(const Eigen::MatrixX3d& directions,
                                    Eigen::MatrixX3d* positions,
                                    Eigen::MatrixX3d* normals) const {
  pieces_.EvaluateMany(directions, positions, normals);
}

bool PiecewiseSplineSampler::SampleCurvature(const Eigen::MatrixX3d& directions,
                                             Eigen::VectorXd* gaussian,
                                             Eigen::VectorXd* mean) const {
  pieces_.EvaluateCurvatureMany(directions, gaussian, mean);
  return true;
}

Eigen::Vector3d SplineSampler::Evaluate(
    const Eigen::Vector3d& direction) const {
  return spline_.Evaluate(direction);
}

Eigen::Vector3d SplineSampler::EvaluateNormal(
    const Eigen::Vector3d& direction) const {
  return EvaluateJet(direction).normal;
}

SurfacePoint SplineSampler::EvaluateJet(
    const Eigen::Vector3d& direction) const {
  return spline_.EvaluateDifferential(direction, JetOrder::kGradient);
}

Eigen::Vector3d PiecewiseSplineSampler::Evaluate(
    const Eigen::Vector3d& direction) const {
  return pieces_.Evaluate(direction);
}

Eigen::Vector3d PiecewiseSplineSampler::EvaluateNormal(
    const Eigen::Vector3d& direction) const {
  Eigen::Vector3d position, normal;
  pieces_.EvaluateWithNormal(direction, &position, &normal);
  return normal;
}

SurfacePoint PiecewiseSplineSampler::EvaluateJet(
    const Eigen::Vector3d& direction) const {
  return JetOfShape(direction, pieces_.EvaluateShape(direction));
}

bool PiecewiseSplineSampler::SampleShape(
    const Eigen::MatrixX3d& directions,
    std::vector<SurfaceShape>* shapes) const {
  pieces_.EvaluateShapeMany(directions, shapes);
  return true;
}

}  // namespace sdcb
