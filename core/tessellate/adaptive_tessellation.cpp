#include "sdcb/core/tessellate/adaptive_tessellation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/tessellate/face_verification.h"
#include "sdcb/core/tessellate/sampled_certificate.h"
#include "sdcb/core/tessellate/sampled_simplification.h"
#include "sdcb/core/tessellate/surface_samples.h"
#include "sdcb/core/tessellate/trim_pattern.h"

namespace sdcb {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}
// The simplification certifies its faces at this share of the tolerance:
// what is left covers the surface between the samples, which the
// verification's lattice then measures.
constexpr double kSimplificationShare = 0.96;
// Samples per face: the pattern's faces are predicted within this fraction
// of the tolerance.
constexpr double kSampleErrorFraction = 1.0 / 8.0;
// The simplification starts from the samples' coarse pattern, whose faces
// pass criteria this many times looser (a third of the tolerance
// predicted), with the other samples inside them: the same certificates,
// without the collapses of the first passes.
constexpr double kCoarseScale = 3.0;

// The surface with zero normals on the feature arcs of a pattern (its
// creases, SphereTriangulation::SetFeatures): the surface has no normal
// there, and every test that compares normals (samples, certificates,
// lattices) treats such points as singular.
class CreaseSampler : public SurfaceSampler {
 public:
  CreaseSampler(const SurfaceSampler& surface,
                const SphereTriangulation& pattern)
      : surface_(surface) {
    for (const auto& [a, b] : pattern.arc_ends()) {
      const Eigen::Vector3d x = pattern.vertex(a), y = pattern.vertex(b);
      arcs_.push_back({x, y, x.cross(y).normalized()});
    }
  }
  void Sample(const Eigen::MatrixX3d& directions, Eigen::MatrixX3d* positions,
              Eigen::MatrixX3d* normals) const override {
    surface_.Sample(directions, positions, normals);
    if (normals == nullptr) return;
    for (Eigen::Index r = 0; r < directions.rows(); ++r) {
      const Eigen::Vector3d d = directions.row(r).transpose();
      for (const Arc& arc : arcs_) {
        if (std::abs(arc.pole.dot(d)) <= kOnArc &&
            arc.a.cross(d).dot(arc.pole) >= 0.0 &&
            d.cross(arc.b).dot(arc.pole) >= 0.0) {
          normals->row(r).setZero();
          break;
        }
      }
    }
  }
  bool SampleCurvature(const Eigen::MatrixX3d& directions,
                       Eigen::VectorXd* gaussian,
                       Eigen::VectorXd* mean) const override {
    return surface_.SampleCurvature(directions, gaussian, mean);
  }
  bool SampleShape(const Eigen::MatrixX3d& directions,
                   std::vector<SurfaceShape>* shapes) const override {
    return surface_.SampleShape(directions, shapes);
  }

 private:
  // Points of an arc's edges are normalized sums of points on its circle:
  // off it by rounding only.
  static constexpr double kOnArc = 1e-12;
  struct Arc {
    Eigen::Vector3d a, b, pole;
  };
  const SurfaceSampler& surface_;
  std::vector<Arc> arcs_;
};

// Every vertex of `out` on a crease (a feature arc of `pattern`; `vertices`:
// the pattern vertex of each row) once per side of it: the faces around it
// between two of the arc's edges get their own copy, whose normal is the
// mean of their normals weighted by their angles at the vertex (a flat
// side's normal however it is split into triangles).
void SplitAlongCreases(const SphereTriangulation& pattern,
                       const std::vector<int>& vertices, Tessellation* out) {
  const Eigen::Index nf = out->faces.rows();
  std::vector<Eigen::Vector3d> weighted(3 * nf, Eigen::Vector3d::Zero());
  for (Eigen::Index f = 0; f < nf; ++f) {
    Eigen::Vector3d x[3];
    for (int k = 0; k < 3; ++k) x[k] = out->positions.row(out->faces(f, k));
    const Eigen::Vector3d n = (x[1] - x[0]).cross(x[2] - x[0]).normalized();
    if (!n.allFinite()) continue;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = x[(k + 1) % 3] - x[k];
      const Eigen::Vector3d w = x[(k + 2) % 3] - x[k];
      weighted[3 * f + k] = std::atan2(u.cross(w).norm(), u.dot(w)) * n;
    }
  }
  std::vector<int> row_of_slot(pattern.num_face_slots(), -1);
  for (int f = 0, r = 0; f < pattern.num_face_slots(); ++f) {
    if (pattern.alive(f)) row_of_slot[f] = r++;
  }
  const Eigen::Index nv = out->positions.rows();
  std::vector<Eigen::Index> copy_of;  // per new row, the row it copies
  std::vector<Eigen::Vector3d> normal_of;
  std::vector<int> star, ring;
  for (Eigen::Index i = 0; i < nv; ++i) {
    const int v = vertices[i];
    if (!pattern.IsFeatureVertex(v)) continue;
    pattern.Star(v, &star, &ring);
    const int n = static_cast<int>(star.size());
    int first = 0;
    while (first < n && !pattern.IsFeatureEdge(v, ring[first])) ++first;
    if (first == n) continue;
    // star[j] = (v, ring[j], ring[j + 1]): a side begins at each arc edge.
    Eigen::Index target = -1;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const auto finish = [&] {
      if (target < 0 || !(sum.norm() > 0.0)) return;
      if (target < nv) {
        out->normals.row(target) = sum.normalized().transpose();
      } else {
        normal_of[target - nv] = sum.normalized();
      }
    };
    for (int s = 0; s < n; ++s) {
      const int j = (first + s) % n;
      if (pattern.IsFeatureEdge(v, ring[j])) {
        finish();
        sum.setZero();
        if (target < 0) {
          target = i;
        } else {
          target = nv + static_cast<Eigen::Index>(copy_of.size());
          copy_of.push_back(i);
          normal_of.push_back(out->normals.row(i).transpose());
        }
      }
      const int row = row_of_slot[star[j]];
      for (int k = 0; k < 3; ++k) {
        if (out->faces(row, k) != i) continue;
        sum += weighted[3 * row + k];
        out->faces(row, k) = static_cast<int>(target);
      }
    }
    finish();
  }
  const Eigen::Index added = static_cast<Eigen::Index>(copy_of.size());
  out->directions.conservativeResize(nv + added, 3);
  out->positions.conservativeResize(nv + added, 3);
  out->normals.conservativeResize(nv + added, 3);
  for (Eigen::Index c = 0; c < added; ++c) {
    out->directions.row(nv + c) = out->directions.row(copy_of[c]);
    out->positions.row(nv + c) = out->positions.row(copy_of[c]);
    out->normals.row(nv + c) = normal_of[c].transpose();
  }
}

// The faces of a trimmed pattern's kept region (KeptFaceSlots) and their
// vertices, in the order of the pattern's slots and vertices.
Status KeepTrimmedFaces(const SphereTriangulation& pattern,
                        const SurfaceSamples& samples, Tessellation* out) {
  SDCB_ASSIGN_OR_RETURN(const std::vector<char> kept, KeptFaceSlots(pattern));
  std::vector<int> row(pattern.num_vertices(), -1);
  int nf = 0;
  for (int f = 0; f < pattern.num_face_slots(); ++f) {
    if (!kept[f]) continue;
    ++nf;
    for (int v : pattern.face(f)) row[v] = 1;  // used
  }
  int nv = 0;
  for (int& r : row) r = r > 0 ? nv++ : -1;
  out->directions.resize(nv, 3);
  out->positions.resize(nv, 3);
  out->normals.resize(nv, 3);
  for (int v = 0; v < pattern.num_vertices(); ++v) {
    if (row[v] < 0) continue;
    out->directions.row(row[v]) = pattern.vertex(v).transpose();
    out->positions.row(row[v]) = samples.positions[v].transpose();
    out->normals.row(row[v]) = samples.normals[v].transpose();
  }
  out->faces.resize(nf, 3);
  for (int f = 0, r = 0; f < pattern.num_face_slots(); ++f) {
    if (!kept[f]) continue;
    const SphereTriangulation::Face& t = pattern.face(f);
    out->faces.row(r++) << row[t[0]], row[t[1]], row[t[2]];
  }
  return Status::Ok();
}

}  // namespace

StatusOr<Tessellation> TessellateAdaptively(
    const SurfaceSampler& surface_in, const TessellationOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    return InvalidArgumentError("tessellation tolerance must be > 0");
  }
  if (!(options.angle_degrees > 0.0 && options.angle_degrees <= 180.0)) {
    return InvalidArgumentError("tessellation angle must be in (0, 180]");
  }
  if (options.max_samples < 1 || options.max_faces < 1) {
    return InvalidArgumentError("tessellation budgets must be >= 1");
  }
  if (options.lattice < 2 || options.lattice > 16) {
    return InvalidArgumentError("tessellation lattice order must be in 2..16");
  }
  // Each stage's own fraction into its share of the whole, never back.
  double reported = 0.0;
  const auto progress = [&](const char* stage, double fraction) {
    static constexpr struct {
      const char* name;
      double from, to;
    } kShares[] = {
        {"samples", 0.0, 0.2}, {"simplify", 0.2, 0.9}, {"verify", 0.9, 1.0}};
    if (!options.progress) return;
    for (const auto& share : kShares) {
      if (std::string(stage) != share.name) continue;
      const double f = std::clamp(fraction, 0.0, 1.0);
      reported = std::max(reported, share.from + f * (share.to - share.from));
    }
    options.progress(stage, reported);
  };

  std::optional<SphereTriangulation> trimmed;
  if (!options.trims.empty()) {
    if (options.initial_pattern != nullptr) {
      return InvalidArgumentError(
          "a tessellation with both creases and trims is not supported yet");
    }
    SDCB_ASSIGN_OR_RETURN(trimmed, TrimmedPattern(options.trims));
  }
  const SphereTriangulation* initial_pattern =
      trimmed ? &*trimmed : options.initial_pattern;
  std::optional<CreaseSampler> creases;
  if (!trimmed && options.initial_pattern != nullptr &&
      options.initial_pattern->has_features()) {
    creases.emplace(surface_in, *options.initial_pattern);
  }
  const SurfaceSampler& surface =
      creases ? static_cast<const SurfaceSampler&>(*creases) : surface_in;
  SurfaceSampleOptions sampling;
  sampling.tolerance = options.tolerance;
  sampling.angle_degrees = options.angle_degrees;
  sampling.error_fraction = kSampleErrorFraction;
  sampling.min_edge_radians = options.min_edge_radians;
  sampling.coarse_scale = kCoarseScale;
  sampling.initial_pattern = initial_pattern;
  sampling.kept_region_only = trimmed.has_value();
  sampling.max_vertices = options.max_samples;
  sampling.progress = [&](int64_t vertices) {
    progress("samples", 1.0 - 1.0 / std::log2(4.0 + vertices / 1000.0));
  };
  Tessellation out;
  Clock::time_point start = Clock::now();
  SDCB_ASSIGN_OR_RETURN(SurfaceSamples samples,
                        SampleSurface(surface, sampling));
  out.seconds.samples = Since(start);
  start = Clock::now();
  const int64_t sample_count = samples.evaluations;

  CertificateOptions certificate;
  certificate.tolerance = options.tolerance;
  certificate.angle_degrees = options.angle_degrees;
  SampledFaces faces(&samples, certificate);
  if (!samples.coarse_faces.empty()) faces.StartFromCoarse();
  SimplificationOptions simplification;
  simplification.threshold = kSimplificationShare * options.tolerance;
  simplification.lattice_surface = &surface;
  simplification.lattice = options.lattice;
  simplification.progress = [&](int pass, int passes, int) {
    progress("simplify", double(pass) / passes);
  };
  SimplifySampledFaces(simplification, &faces);
  out.seconds.simplify = Since(start);
  start = Clock::now();

  VerificationOptions verification;
  verification.threshold = options.tolerance;
  verification.lattice = options.lattice;
  verification.min_edge_radians = options.min_edge_radians;
  verification.max_faces = options.max_faces;
  verification.kept_region_only = trimmed.has_value();
  int64_t measured = 0;
  const int64_t to_measure = samples.pattern.num_faces();
  verification.progress = [&](int64_t n, int64_t) {
    measured += n;
    progress("verify", double(measured) / std::max<int64_t>(1, to_measure));
  };
  VerificationResult verified;
  SDCB_RETURN_IF_ERROR(VerifyFaces(surface, verification, &faces, &verified));
  out.seconds.verify = Since(start);

  const SphereTriangulation& pattern = samples.pattern;
  if (trimmed) {
    SDCB_RETURN_IF_ERROR(KeepTrimmedFaces(pattern, samples, &out));
  } else {
    const std::vector<int> vertices = pattern.AliveVertices();
    out.faces = pattern.Faces();
    const int nv = static_cast<int>(vertices.size());
    out.directions.resize(nv, 3);
    out.positions.resize(nv, 3);
    out.normals.resize(nv, 3);
    for (int i = 0; i < nv; ++i) {
      const int v = vertices[i];
      out.directions.row(i) = pattern.vertex(v).transpose();
      out.positions.row(i) = samples.positions[v].transpose();
      out.normals.row(i) = samples.normals[v].transpose();
    }
    if (pattern.has_features()) SplitAlongCreases(pattern, vertices, &out);
  }
  out.certified_distance = verified.max_distance;
  out.max_normal_angle_degrees = verified.max_angle * 180.0 / kPi;
  out.uncertified_faces = verified.uncertified_faces;
  out.evaluations = samples.evaluations + verified.evaluations;
  out.samples = sample_count;
  return out;
}

Tessellation TessellateUniformly(const SurfaceSampler& surface,
                                 int subdivisions) {
  const TriangleMesh sphere = MakeIcosphere(std::clamp(subdivisions, 0, 9));
  Tessellation out;
  out.directions = sphere.vertices;
  out.faces = sphere.faces;
  surface.Sample(out.directions, &out.positions, &out.normals);
  out.evaluations = out.directions.rows();
  return out;
}

int UniformLevelForVertices(int64_t vertices) {
  int best = 0;
  double best_gap = 1e300;
  for (int s = 0; s <= 9; ++s) {
    const double count = 10.0 * std::pow(4.0, s) + 2.0;
    const double gap =
        std::abs(std::log(count) - std::log(std::max<double>(1, vertices)));
    if (gap < best_gap) {
      best_gap = gap;
      best = s;
    }
  }
  return best;
}

}  // namespace sdcb
