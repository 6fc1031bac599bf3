// CGAL's cube fitted with its sharp edges kept (FitOptions::keep_features,
// rmse 0.1 %): the corners' knot clusters alone, 212 control points. The
// model the crease-following converters are tested on.
#ifndef SDCB_TESTS_TESTING_KEPT_CUBE_H_
#define SDCB_TESTS_TESTING_KEPT_CUBE_H_

#include "sdcb/core/fit/spline_fitter.h"
#include "testing/make_mesh.h"

namespace sdcb::testing {

// `inward`: the cube's faces reversed (pointing in, as CGAL's beam and
// tetrahedron are stored).
inline StatusOr<FitResult> FitKeptCube(bool inward = false) {
  FitOptions options;
  options.rmse_percent = 0.1;
  options.keep_features = true;
  TriangleMesh cube = CubeMesh();
  if (inward) cube.faces.col(1).swap(cube.faces.col(2));
  return FitSphericalSpline(cube, options);
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_KEPT_CUBE_H_
