#include "sdcb/core/measure/surface_sampler.h"

#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

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

bool PiecewiseSplineSampler::SampleShape(
    const Eigen::MatrixX3d& directions,
    std::vector<SurfaceShape>* shapes) const {
  pieces_.EvaluateShapeMany(directions, shapes);
  return true;
}

}  // namespace sdcb
