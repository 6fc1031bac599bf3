// Are the folds MeasureSurfaceDeviation reports real orientation reversals of
// the spline, or samples whose closest mesh point lies on another part of the
// mesh (the far side of a thin leg, ear or horn)?
//   fold_diagnosis_bench MESH [--rmse PCT] [--max-rounds R] [--threads T]
// Fits MESH (parameters stored), measures the result as the fit's final
// measurement does, and for every sample u the closest-point test calls
// folded, finds the mesh triangle whose spherical image (the fit's
// parameterization, gnomonic barycentrics) contains u: x(u) and that
// triangle's normal n. Prints, area-weighted in percent of the spline's area:
//   (a) the spline's normal at u opposes n as well: a real reversal (split by
//       whether that triangle's spherical image is itself inverted);
//   (b) the spline agrees with n: the closest point's triangle is not the
//       corresponding one; (b1) its normal opposes n (the far side of a
//       part), (b2) it does not;
//   (u) no spherical triangle contains u (numerically);
// for (b1) |F(u) - x(u)|, the closest distance and the thickness at x(u)
// (first hit of the ray from x(u) along -n), in percent of the largest
// bounding-box side (for (a) the thickness too, against that of every 8th
// sample); and, over ALL samples, the area where the spline's
// normal opposes the corresponding triangle's (a correspondence-based fold
// measure, for comparison with the closest-point one).
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/mesh/mesh_reader.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle3 = Kernel::Triangle_3;
using Iterator = std::vector<Triangle3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 ToPoint(const Eigen::Vector3d& v) {
  return Kernel::Point_3(v.x(), v.y(), v.z());
}

// An AABB tree over the triangles of (vertices, faces) whose primitives
// report their face index.
class FaceTree {
 public:
  FaceTree(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
    triangles_.reserve(faces.rows());
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      triangles_.emplace_back(ToPoint(vertices.row(faces(f, 0))),
                              ToPoint(vertices.row(faces(f, 1))),
                              ToPoint(vertices.row(faces(f, 2))));
    }
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.accelerate_distance_queries();
  }
  // Faces crossed by the segment (a, b).
  std::vector<int> Crossed(const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b) const {
    std::vector<Iterator> ids;
    tree_.all_intersected_primitives(Kernel::Segment_3(ToPoint(a), ToPoint(b)),
                                     std::back_inserter(ids));
    std::vector<int> out;
    for (Iterator it : ids) {
      out.push_back(static_cast<int>(it - triangles_.begin()));
    }
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  std::vector<Triangle3> triangles_;
  AabbTree tree_;
};

// Parameter t of the intersection of the line o + t d with the plane of
// (a, b, c), or NaN when parallel.
double LinePlane(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                 const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                 const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double den = n.dot(d);
  if (den == 0) return std::numeric_limits<double>::quiet_NaN();
  return n.dot(a - o) / den;
}

struct Located {
  int face = -1;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();  // gnomonic, sums to 1
  int containing = 0;  // spherical triangles containing u
};

// The triangle of the sphere mesh (corners u_a, u_b, u_c) whose spherical
// image contains u: det(u, u_b, u_c), det(u_a, u, u_c), det(u_a, u_b, u) all
// of the sign of det(u_a, u_b, u_c) (zero allowed). Candidates: the faces the
// segment from the origin to 2u crosses; all faces if none of them holds u.
Located Locate(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces,
               const FaceTree& tree, const Eigen::Vector3d& u) {
  Located out;
  auto test = [&](int f) {
    const Eigen::Vector3d a = sphere.row(faces(f, 0)),
                          b = sphere.row(faces(f, 1)),
                          c = sphere.row(faces(f, 2));
    const double o = sdcb::Det3(a, b, c);
    const Eigen::Vector3d s(sdcb::Det3(u, b, c), sdcb::Det3(a, u, c),
                            sdcb::Det3(a, b, u));
    const double sign = o >= 0 ? 1.0 : -1.0;
    if ((sign * s).minCoeff() < 0 || s.sum() == 0) return;
    if (++out.containing == 1) {
      out.face = f;
      out.bary = s / s.sum();
    }
  };
  for (int f : tree.Crossed(Eigen::Vector3d::Zero(), 2.0 * u)) test(f);
  if (out.containing == 0) {
    for (int f = 0; f < faces.rows(); ++f) test(f);
  }
  return out;
}

// Area-weighted median of `values`.
double WeightedMedian(std::vector<std::pair<double, double>> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  double total = 0;
  for (const auto& v : values) total += v.second;
  double run = 0;
  for (const auto& v : values) {
    run += v.second;
    if (run >= 0.5 * total) return v.first;
  }
  return values.back().first;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = std::string(SDCB_MESH_DIR) + "/cow.off";
  sdcb::FitOptions options;
  options.rmse_percent = 0.1;
  options.max_rounds = 4;
  options.store_parameters = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? argv[++i] : "0"; };
    if (a == "--rmse") {
      options.rmse_percent = std::atof(next());
    } else if (a == "--max-rounds") {
      options.max_rounds = std::atoi(next());
    } else if (a == "--threads") {
      options.threads = std::atoi(next());
    } else {
      path = a;
    }
  }
  auto input = sdcb::ReadMesh(path);
  if (!input.ok()) {
    std::fprintf(stderr, "%s\n", input.status().message().c_str());
    return 1;
  }
  auto fit = sdcb::FitSphericalSpline(*input, options);
  if (!fit.ok()) {
    std::fprintf(stderr, "%s\n", fit.status().message().c_str());
    return 1;
  }
  const sdcb::SplineModel& model = fit->model;
  auto surface = sdcb::SurfaceFromModel(model);
  if (!surface.ok()) {
    std::fprintf(stderr, "%s\n", surface.status().message().c_str());
    return 1;
  }
  // The fit's frame: the mesh normalized (largest side 1, so percent =
  // 100 x distance), measured as the fit's final measurement.
  sdcb::TriangleMesh mesh;
  mesh.faces = input->faces;
  mesh.vertices = model.transform.ToNormalized(input->vertices);
  const Eigen::MatrixX3d& sphere = model.parameters;
  const Eigen::MatrixX3i& faces = mesh.faces;
  const Eigen::Index nf = faces.rows();
  sdcb::DeviationOptions measure;
  measure.min_surface_samples =
      std::max(options.final_surface_samples,
               options.round_samples_per_knot *
                   static_cast<int>(surface->knots().rows()));
  measure.search_all_vertices = false;
  const Eigen::MatrixX3d vertex_points = surface->EvaluateMany(sphere);
  auto deviation =
      sdcb::MeasureSurfaceDeviation(*surface, mesh, measure, &vertex_points);
  if (!deviation.ok()) {
    std::fprintf(stderr, "measurement failed\n");
    return 1;
  }
  const sdcb::SurfaceDeviation& d = *deviation;

  // The parameterization: inverted spherical triangles.
  double mesh_area = 0, inverted_area = 0;
  int inverted = 0;
  Eigen::MatrixX3d face_normal(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(faces(f, 0)),
                          b = mesh.vertices.row(faces(f, 1)),
                          c = mesh.vertices.row(faces(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    face_normal.row(f) = n.normalized().transpose();
    mesh_area += 0.5 * n.norm();
    if (sdcb::Det3(sphere.row(faces(f, 0)), sphere.row(faces(f, 1)),
                   sphere.row(faces(f, 2))) < 0) {
      ++inverted;
      inverted_area += 0.5 * n.norm();
    }
  }
  // Area-weighted vertex normals: a smooth reference that a noisy triangle
  // cannot flip.
  Eigen::MatrixX3d vertex_normal =
      Eigen::MatrixX3d::Zero(mesh.vertices.rows(), 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(faces(f, 0)),
                          b = mesh.vertices.row(faces(f, 1)),
                          c = mesh.vertices.row(faces(f, 2));
    for (int k = 0; k < 3; ++k) {
      vertex_normal.row(faces(f, k)) += (b - a).cross(c - a).transpose();
    }
  }
  const FaceTree sphere_tree(sphere, faces);
  const FaceTree mesh_tree(mesh.vertices, faces);

  const Eigen::Index ns = d.surface_sample_points.rows();
  const double area = d.surface_area;
  auto pct = [&](double a) { return 100.0 * a / area; };
  double folded = 0, real = 0, real_inverted = 0, other = 0, far_side = 0,
         unlocated = 0, multiple = 0;
  double real_same_side = 0, real_smooth = 0;
  std::vector<std::pair<double, double>> real_dist, real_angle;
  double corr_all = 0;  // correspondence-based fold area over all samples
  double corr_inverted = 0, corr_only = 0;
  double deeper_than_half = 0, closer_than_corr = 0, thick_known = 0;
  // Area-weighted (value, weight) lists for the medians.
  std::vector<std::pair<double, double>> corr_dist, closest_dist, thickness,
      ratio, real_thickness, all_thickness;
  // Thickness at x on face `face` of normal n, percent: the nearest face hit
  // by the ray x - t n, t > 0, other than `face` (a segment of length 2
  // spans the unit frame); NaN if none.
  auto thickness_at = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& n,
                          int face) {
    double t_min = std::numeric_limits<double>::infinity();
    for (int f : mesh_tree.Crossed(x, x - 2.0 * n)) {
      if (f == face) continue;
      const double t = LinePlane(x, -n, mesh.vertices.row(faces(f, 0)),
                                 mesh.vertices.row(faces(f, 1)),
                                 mesh.vertices.row(faces(f, 2)));
      if (t > 1e-7) t_min = std::min(t_min, t);
    }
    return std::isfinite(t_min) ? 100.0 * t_min
                                : std::numeric_limits<double>::quiet_NaN();
  };
  for (Eigen::Index i = 0; i < ns; ++i) {
    const Eigen::Vector3d u = d.surface_sample_points.row(i);
    const double w = d.surface_sample_weight[i];
    const bool is_folded = d.surface_sample_folded[i];
    const Located at = Locate(sphere, faces, sphere_tree, u);
    if (at.containing > 1) multiple += w;
    if (at.face < 0) {
      if (is_folded) {
        folded += w;
        unlocated += w;
      }
      continue;
    }
    const sdcb::SurfacePoint s =
        surface->EvaluateDifferential(u, sdcb::JetOrder::kGradient);
    const Eigen::Vector3d n = face_normal.row(at.face);
    const bool opposes = s.normal.dot(n) < 0;
    const bool inverted_here =
        sdcb::Det3(sphere.row(faces(at.face, 0)), sphere.row(faces(at.face, 1)),
                   sphere.row(faces(at.face, 2))) < 0;
    if (opposes) {
      corr_all += w;
      if (inverted_here) corr_inverted += w;
      if (!is_folded) corr_only += w;
    }
    Eigen::Vector3d x = Eigen::Vector3d::Zero(),
                    smooth = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      x += at.bary[k] * mesh.vertices.row(faces(at.face, k)).transpose();
      smooth += at.bary[k] *
                vertex_normal.row(faces(at.face, k)).normalized().transpose();
    }
    // The thickness over all samples: every 8th (8 times its weight).
    if (i % 8 == 0) {
      const double th = thickness_at(x, n, at.face);
      if (!std::isnan(th)) all_thickness.emplace_back(th, w);
    }
    if (!is_folded) continue;
    folded += w;
    const int closest_face = d.surface_sample_mesh_face[i];
    const double to_x = 100.0 * (s.position - x).norm();
    const double th = thickness_at(x, n, at.face);
    if (opposes) {
      real += w;
      if (inverted_here) real_inverted += w;
      if (face_normal.row(closest_face).dot(n) >= 0) real_same_side += w;
      if (s.normal.dot(smooth) < 0) real_smooth += w;
      real_dist.emplace_back(to_x, w);
      real_angle.emplace_back(
          std::acos(std::clamp(s.normal.dot(n), -1.0, 1.0)) * 180 / sdcb::kPi,
          w);
      if (!std::isnan(th)) real_thickness.emplace_back(th, w);
      continue;
    }
    other += w;
    if (!(face_normal.row(closest_face).dot(n) < 0)) continue;
    // (b1): the hypothesis's class.
    far_side += w;
    const double closest = d.surface_sample_distance_percent[i];
    corr_dist.emplace_back(to_x, w);
    closest_dist.emplace_back(closest, w);
    if (closest < to_x) closer_than_corr += w;
    if (!std::isnan(th)) {
      thick_known += w;
      thickness.emplace_back(th, w);
      ratio.emplace_back(to_x / th, w);
      if (to_x > 0.5 * th) deeper_than_half += w;
    }
  }

  const auto& f = model.statistics.final_result;
  std::printf(
      "returned round %d (its statistics from the round's own, "
      "coarser measurement unless it met the target)\n",
      f.round);
  std::printf(
      "%s: %d vertices, %d faces; %d rounds, %d knots, %d control "
      "points; model rms %.4f%% folded %.4f%%\n",
      path.c_str(), input->num_vertices(), input->num_faces(),
      static_cast<int>(model.statistics.rounds.size()),
      static_cast<int>(surface->knots().rows()), f.control_points,
      f.rmse_percent, f.folded_area_percent);
  std::printf(
      "parameterization: %d of %d spherical triangles inverted "
      "(%.4f%% of the mesh area)\n",
      inverted, static_cast<int>(nf), 100.0 * inverted_area / mesh_area);
  std::printf(
      "measured: %ld samples (level %d), rms %.4f%%, folded %.4f%% of "
      "the spline's area; samples in >1 spherical triangle %.4f%%\n",
      static_cast<long>(ns), d.lattice_level, d.rms_percent,
      d.folded_area_percent, pct(multiple));
  std::printf("closest-point folds, %% of the spline's area (%% of folded):\n");
  auto row = [&](const char* name, double a) {
    std::printf("  %-52s %8.4f%% (%5.1f%%)\n", name, pct(a),
                folded > 0 ? 100.0 * a / folded : 0.0);
  };
  row("all folded", folded);
  row("(a) opposes the corresponding triangle too", real);
  row("    ... in an inverted spherical triangle", real_inverted);
  row("    ... closest triangle on the corresponding's side", real_same_side);
  row("    ... opposes the smooth (vertex) normal at x(u) too", real_smooth);
  row("(b) agrees with the corresponding triangle", other);
  row("    (b1) closest triangle opposes the corresponding", far_side);
  row("    (b2) closest triangle does not", other - far_side);
  row("(u) not located on the sphere", unlocated);
  if (real > 0) {
    std::printf(
        "(a), median (area-weighted): |F(u)-x(u)| %.4f%%, angle between "
        "the normals %.1f deg, thickness at x(u) %.4f%% (all samples: "
        "%.4f%%)\n",
        WeightedMedian(real_dist), WeightedMedian(real_angle),
        WeightedMedian(real_thickness), WeightedMedian(all_thickness));
  }
  if (far_side > 0) {
    std::printf(
        "(b1), median (area-weighted): |F(u)-x(u)| %.4f%%, closest distance "
        "%.4f%%, thickness at x(u) %.4f%% (known for %.1f%% of (b1)), "
        "|F-x|/thickness %.3f\n",
        WeightedMedian(corr_dist), WeightedMedian(closest_dist),
        WeightedMedian(thickness), 100.0 * thick_known / far_side,
        WeightedMedian(ratio));
    std::printf(
        "(b1): closest distance < |F(u)-x(u)| on %.1f%%, |F(u)-x(u)| > half "
        "the thickness on %.1f%% (of (b1)'s area)\n",
        100.0 * closer_than_corr / far_side,
        100.0 * deeper_than_half / far_side);
  }
  std::printf(
      "correspondence folds over all samples (spline normal opposes "
      "the triangle containing u): %.4f%% of the spline's area, "
      "%.4f%% in inverted spherical triangles, %.4f%% not folded by the "
      "closest-point test\n",
      pct(corr_all), pct(corr_inverted), pct(corr_only));
  return 0;
}
