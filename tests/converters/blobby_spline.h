// The model the CAD tests export: blobby.off fitted to rms 0.2 % (a few
// seconds), a smooth spline without folds.
#ifndef SDCB_TESTS_CONVERTERS_BLOBBY_SPLINE_H_
#define SDCB_TESTS_CONVERTERS_BLOBBY_SPLINE_H_

#include <gtest/gtest.h>

#include <utility>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "testing/temp_dir.h"

namespace sdcb::testing {

inline SphericalSpline BlobbySpline() {
  auto mesh = ReadMesh(MeshPath("blobby.off"));
  EXPECT_TRUE(mesh.ok());
  FitOptions options;
  options.rmse_percent = 0.2;
  auto fit = FitSphericalSpline(*mesh, options);
  EXPECT_TRUE(fit.ok());
  auto spline = SurfaceFromModel(fit->model);
  EXPECT_TRUE(spline.ok());
  return std::move(*spline);
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_CONVERTERS_BLOBBY_SPLINE_H_
