// Tests of converters/cad/cad_network and converters/cad/cad_file on a real
// model (blobby.off, fitted). Oracles, none of them the network fitter's own
// measurement:
// - the STEP / IGES file re-read by OpenCASCADE's readers: one valid solid,
//   closed shells, volume and area against the spline's fine uniform
//   tessellation and OpenCASCADE's own BRepGProp against the report's;
// - distances at >= 100K exact points of the re-read surfaces to the spline
//   (closest-point searches on the spline), and from >= 10K of the spline's
//   points to the re-read surfaces (OpenCASCADE's projection on the face
//   the lattice names);
// - the normal jump across every re-read edge, from the re-read faces'
//   pcurves and surface derivatives (testing/occt_reread.h);
// - every face's side against its edge's curve, evaluated here by the
//   B-spline basis.
#include "sdcb/converters/cad/cad_export.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "converters/blobby_spline.h"
#include "converters/cad_reread_oracle.h"
#include "sdcb/converters/cad/cad_file.h"
#include "sdcb/converters/cad/cad_network.h"
#include "sdcb/core/common/constants.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/kept_cube.h"
#include "testing/occt_reread.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

constexpr double kTolerance = 0.1;
constexpr double kSmoothness = 0.5;

class CadExportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    spline_ = new SphericalSpline(testing::BlobbySpline());
    CadNetworkOptions options;
    options.tolerance_percent = kTolerance;
    options.smoothness_degrees = kSmoothness;
    auto fit = FitCadNetwork(*spline_, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    network_ = new CadNetwork(std::move(*fit));
  }
  static void TearDownTestSuite() {
    delete network_;
    delete spline_;
  }
  static SphericalSpline* spline_;
  static CadNetwork* network_;
};
SphericalSpline* CadExportTest::spline_ = nullptr;
CadNetwork* CadExportTest::network_ = nullptr;

// The curve of `edge` at t, by the basis.
Eigen::Vector3d CurvePoint(const CadEdge& edge, double t) {
  const int s = KnotSpan(edge.breaks, t);
  double n[4];
  CubicBSplineBasis(edge.breaks, s, t, n, nullptr);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int r = 0; r < 4; ++r) p += n[r] * edge.poles[s + r];
  return p;
}

TEST_F(CadExportTest, ReachesTheToleranceAndEverySideIsItsEdgeCurve) {
  const CadNetwork& n = *network_;
  EXPECT_TRUE(n.within_tolerance) << n.stop_reason;
  EXPECT_LE(n.max_distance_percent, kTolerance);
  EXPECT_LE(n.max_normal_jump_degrees, kSmoothness);
  ASSERT_EQ(n.faces.size(), 384u);  // 6 x 8 x 8
  ASSERT_EQ(n.face_edges.size(), n.faces.size());
  EXPECT_EQ(n.edges.size(), 768u);  // a closed quad mesh: 2 edges per face
  EXPECT_EQ(n.num_vertices, 386);   // Euler: V - E + F = 2
  std::vector<int> uses(n.edges.size(), 0);
  for (size_t f = 0; f < n.faces.size(); ++f) {
    const BSplineFace& face = n.faces[f];
    for (int k = 0; k < 4; ++k) {
      const CadEdge& edge = n.edges[n.face_edges[f][k]];
      ++uses[n.face_edges[f][k]];
      for (int q = 0; q <= 32; ++q) {
        const double t = edge.breaks.front() +
                         (edge.breaks.back() - edge.breaks.front()) * q / 32;
        const double u0 = face.u_breaks.front(), u1 = face.u_breaks.back();
        const double v0 = face.v_breaks.front(), v1 = face.v_breaks.back();
        const Eigen::Vector3d x = k == 0   ? face.Evaluate(t, v0)
                                  : k == 1 ? face.Evaluate(u1, t)
                                  : k == 2 ? face.Evaluate(t, v1)
                                           : face.Evaluate(u0, t);
        EXPECT_LT((x - CurvePoint(edge, t)).norm(), 1e-12)
            << "face " << f << " side " << k;
      }
    }
  }
  for (const int u : uses) EXPECT_EQ(u, 2);
}

TEST_F(CadExportTest, BudgetTooSmallReportsWhatItReached) {
  CadNetworkOptions options;
  options.tolerance_percent = 1e-5;
  options.max_control_points = 8000;  // the first round has 6146
  auto fit = FitCadNetwork(*spline_, options);
  ASSERT_TRUE(fit.ok());
  EXPECT_FALSE(fit->within_tolerance);
  EXPECT_EQ(fit->stop_reason, "control point budget");
  EXPECT_GT(fit->max_distance_percent, 1e-5);
  EXPECT_LE(fit->control_points, 8000);
  options.max_faces = 383;  // the network has 384
  EXPECT_EQ(FitCadNetwork(*spline_, options).status().code(),
            StatusCode::kInvalidArgument);
}

// The coordinates of every CARTESIAN_POINT of a STEP file's text, white
// space removed ("1.5,-2.,0.25").
std::vector<std::string> CartesianPointTexts(const std::string& step) {
  std::vector<std::string> points;
  const std::string head = "CARTESIAN_POINT('',(";
  for (size_t at = step.find(head); at != std::string::npos;
       at = step.find(head, at + 1)) {
    const size_t begin = at + head.size();
    const size_t end = step.find(')', begin);
    std::string point;
    for (size_t i = begin; i < end && end != std::string::npos; ++i) {
      if (!std::isspace(static_cast<unsigned char>(step[i]))) {
        point += step[i];
      }
    }
    points.push_back(point);
  }
  return points;
}

// The STEP and IGES files re-read by OpenCASCADE against the spline.
void CheckReread(const SphericalSpline& spline, const CadNetwork& network,
                 const CadSolidReport& report, const std::string& path,
                 bool iges, bool distances) {
  const testing::RereadShape r = testing::Reread(path, iges);
  ASSERT_TRUE(r.read) << path;
  EXPECT_EQ(r.solids, 1);
  EXPECT_EQ(r.shells, 1);
  EXPECT_EQ(r.free_edges, 0);
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.faces, static_cast<int>(network.faces.size()));
  // The curves, surfaces and corners meet as written: the reader keeps its
  // confusion distance (1e-7).
  EXPECT_LE(r.max_tolerance, 1e-7) << path;

  const testing::RereadComparison c = testing::CompareRereadWithSpline(
      r, spline, distances ? 100000 : 1000, distances ? 10000 : 100);
  ASSERT_TRUE(c.ok);
  EXPECT_NEAR(r.volume / c.spline_volume, 1.0, 1e-3)
      << r.volume << " vs " << c.spline_volume;
  EXPECT_NEAR(r.area / c.spline_area, 1.0, 1e-3)
      << r.area << " vs " << c.spline_area;
  // The report's volume and area (from the faces' Bezier spans) are
  // OpenCASCADE's, up to the poles' decimal digits in the file (1.4e-9 on
  // the bunny's model).
  EXPECT_NEAR(report.volume / r.volume, 1.0, 1e-8);
  EXPECT_NEAR(report.area / r.area, 1.0, 1e-7);
  // The normal jump across every re-read edge, at 24 points each.
  const testing::NormalJumps jumps = testing::MeasureNormalJumps(r, 24);
  EXPECT_EQ(jumps.edges, 768);
  EXPECT_LE(jumps.max_degrees, kSmoothness);
  EXPECT_GT(jumps.max_degrees, 0.0);
  std::printf(
      "%s: %d faces, volume %.6f (spline %.6f), area %.6f (%.6f), jump "
      "%.4f deg (reported %.4f)\n",
      iges ? "IGES" : "STEP", r.faces, r.volume, c.spline_volume, r.area,
      c.spline_area, jumps.max_degrees, network.max_normal_jump_degrees);
  if (!distances) return;  // the same surfaces as the STEP file's
  EXPECT_GE(c.surface_points, 100000);
  EXPECT_GE(c.spline_points, 10000);
  EXPECT_LE(c.to_spline_percent, kTolerance);
  EXPECT_LE(c.from_spline_percent, kTolerance);
  // The fitter's parametric figure bounds both (it is the distance to the
  // spline point of the same sphere point), up to the spacing of its
  // lattice.
  EXPECT_LE(c.to_spline_percent, network.max_distance_percent * 1.05);
  EXPECT_LE(c.from_spline_percent, network.max_distance_percent * 1.05);
  std::printf("to spline %.5f%%, from spline %.5f%% (reported %.5f%%)\n",
              c.to_spline_percent, c.from_spline_percent,
              network.max_distance_percent);
}

TEST_F(CadExportTest, StepRereadIsOneValidSmoothSolidWithinTheTolerance) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/blobby.step";
  auto report = WriteCadSolid(*network_, CadFormat::kStep, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(report->valid);
  EXPECT_EQ(report->free_edges, 0);
  const std::string text = testing::ReadBytes(path);
  EXPECT_NE(text.find("AUTOMOTIVE_DESIGN"), std::string::npos);  // AP214
  EXPECT_NE(text.find("B_SPLINE_SURFACE_WITH_KNOTS"), std::string::npos);
  EXPECT_NE(text.find("MANIFOLD_SOLID_BREP"), std::string::npos);
  // Every point is written once, each coordinate with at most 8 decimals
  // (the corners, the sides' poles shared by a face and its edge's curve):
  // fewer points than the faces' and edges' poles together.
  const std::vector<std::string> points = CartesianPointTexts(text);
  const std::set<std::string> distinct(points.begin(), points.end());
  EXPECT_EQ(distinct.size(), points.size());
  size_t poles = 0;
  for (const BSplineFace& face : network_->faces) poles += face.poles.size();
  for (const CadEdge& edge : network_->edges) poles += edge.poles.size();
  EXPECT_LT(points.size(), poles * 9 / 10) << poles;
  for (const std::string& point : points) {
    for (size_t at = point.find('.'); at != std::string::npos;
         at = point.find('.', at + 1)) {
      const size_t end = point.find_first_not_of("0123456789", at + 1);
      EXPECT_LE((end == std::string::npos ? point.size() : end) - at - 1, 8u)
          << point;
    }
  }
  CheckReread(*spline_, *network_, *report, path, false, true);
}

TEST_F(CadExportTest, IgesRereadIsOneValidSmoothSolid) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/blobby.igs";
  auto report = WriteCadSolid(*network_, CadFormat::kIges, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  CheckReread(*spline_, *network_, *report, path, true, false);
  const std::string again = dir + "/again.igs";
  ASSERT_TRUE(WriteCadSolid(*network_, CadFormat::kIges, again).ok());
  // The same network gives the same bytes (the global section's dates are
  // fixed). STEP's are compared across processes by the CLI test: within
  // one, OpenCASCADE numbers its product names.
  EXPECT_TRUE(testing::ReadBytes(again) == testing::ReadBytes(path));
}

TEST_F(CadExportTest, FacesThatDoNotCloseWriteNothing) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/open.step";
  CadNetwork open = *network_;
  open.faces.pop_back();
  open.face_edges.pop_back();
  auto report = WriteCadSolid(open, CadFormat::kStep, path);
  EXPECT_FALSE(report.ok());
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

// The cube fitted with its edges kept (its knots hold 12 feature arcs): the
// STEP solid has the cube's six faces, flat, on the cube's planes, meeting
// at right angles along its edges. Oracles: the cube's closed form and
// OpenCASCADE's reader.
// The same from the cube stored with its faces pointing inward: its sphere
// map is mirrored, and the solid is still oriented outward.
class CadExportCreaseTest : public ::testing::TestWithParam<bool> {};
INSTANTIATE_TEST_SUITE_P(Outward, CadExportCreaseTest,
                         ::testing::Values(false));
INSTANTIATE_TEST_SUITE_P(Inward, CadExportCreaseTest, ::testing::Values(true));

TEST_P(CadExportCreaseTest, KeptCubeIsSixFlatFacesMeetingAtRightAngles) {
  auto fit = testing::FitKeptCube(/*inward=*/GetParam());
  ASSERT_TRUE(fit.ok() && fit->features_kept);
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/cube.step";
  CadExportOptions options;  // 0.05 %, 0.5 degrees
  auto report = WriteCadExport(fit->model, options, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(report->layout, "feature faces");
  EXPECT_EQ(report->crease_edges, 12);

  const testing::RereadShape r = testing::Reread(path, false);
  ASSERT_TRUE(r.read);
  EXPECT_EQ(r.solids, 1);
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.free_edges, 0);
  ASSERT_EQ(r.faces, 6);
  // The input is the cube [-1, 1]^3: within the tolerance (0.05 % of its
  // side 2) its volume is 8 to the area times that.
  const double tolerance = 0.0005 * 2.0;
  EXPECT_NEAR(r.volume, 8.0, 24.0 * tolerance);
  EXPECT_NEAR(r.area, 24.0, 0.01 * 24.0);
  // Every face on one of the cube's planes, its normal the plane's.
  std::set<int> planes;
  for (int f = 0; f < r.faces; ++f) {
    const auto& b = r.bounds[f];
    int plane = -1;
    for (int j = 0; j <= 8; ++j) {
      for (int i = 0; i <= 8; ++i) {
        gp_Pnt p;
        gp_Vec du, dv;
        r.surfaces[f]->D1(b[0] + (b[1] - b[0]) * i / 8,
                          b[2] + (b[3] - b[2]) * j / 8, p, du, dv);
        const Eigen::Vector3d x(p.X(), p.Y(), p.Z());
        gp_Vec n = du.Crossed(dv);
        Eigen::Vector3d normal(n.X(), n.Y(), n.Z());
        normal.normalize();
        int axis = 0;
        normal.cwiseAbs().maxCoeff(&axis);
        const int side = 2 * axis + (x[axis] > 0.0 ? 0 : 1);
        if (plane < 0) plane = side;
        EXPECT_EQ(side, plane) << f;
        // The plane x[axis] = +-1, the normal along the axis (either way: a
        // read face may be reversed; the volume says the solid points out).
        EXPECT_NEAR(std::abs(x[axis]), 1.0, tolerance) << f;
        EXPECT_GT(std::abs(normal[axis]), std::cos(1.0 * kPi / 180.0)) << f;
      }
    }
    planes.insert(plane);
  }
  EXPECT_EQ(planes.size(), 6u);
  // Right angles along every edge, all along it.
  const testing::NormalJumps jumps = testing::MeasureNormalJumps(r, 24);
  EXPECT_EQ(jumps.edges, 12);
  EXPECT_GT(jumps.min_degrees, 89.0);
  EXPECT_LT(jumps.max_degrees, 91.0);
}

// The library call behind `sdcb export OUT.step`: the file and its report,
// or, when the budget cannot reach the tolerance or the model folds, a
// status saying so and no file.
TEST(CadExportCallTest, WritesTheFileItReportsOrNothing) {
  const std::string dir = testing::FreshTestDir();
  auto model = ReadSdcbFile(testing::TestDataPath("cow_round0_v1.sdcb"));
  ASSERT_TRUE(model.ok());
  CadExportOptions options;
  options.network.tolerance_percent = 0.5;
  options.network.smoothness_degrees = 1.0;
  double last = -1.0;
  options.progress = [&](const std::string& stage, double fraction) {
    EXPECT_GE(fraction, last) << stage;
    last = fraction;
  };
  const std::string path = dir + "/cow.step";
  auto report = WriteCadExport(*model, options, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(last, 1.0);
  EXPECT_EQ(report->bytes,
            static_cast<int64_t>(std::filesystem::file_size(path)));
  EXPECT_TRUE(report->valid);
  EXPECT_EQ(report->faces, 384);
  EXPECT_LE(report->max_distance_percent, 0.5);
  EXPECT_LE(report->max_normal_jump_degrees, 1.0);
  EXPECT_EQ(static_cast<int>(report->face_max_distance_percent.size()),
            report->faces);
  const auto j = CadExportReportToJson(*report);
  EXPECT_EQ(j["faces"], report->faces);
  EXPECT_EQ(j["format"], "step");
  EXPECT_EQ(j["control_points"], report->control_points);

  options.network.tolerance_percent = 1e-5;
  options.network.max_control_points = 3000;
  options.progress = nullptr;
  const std::string refused = dir + "/refused.step";
  report = WriteCadExport(*model, options, refused);
  EXPECT_EQ(report.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(report.status().message().find("max distance of"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(refused));

  // A model whose fit measured folds refuses, unless the smoothness is 180.
  model->statistics.final_result.folded_area_percent = 0.14;
  options.network.tolerance_percent = 0.5;
  options.network.max_control_points = 200000;
  report = WriteCadExport(*model, options, refused);
  EXPECT_EQ(report.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(report.status().message().find("folds over 0.14 %"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(refused));
  options.network.smoothness_degrees = 180.0;
  EXPECT_TRUE(WriteCadExport(*model, options, refused).ok());
}

}  // namespace
}  // namespace sdcb
