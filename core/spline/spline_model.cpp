#include "sdcb/core/spline/spline_model.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {

std::string Str(int64_t x) { return std::to_string(x); }

constexpr uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ULL;
constexpr uint64_t kFnvPrime = 0x100000001b3ULL;

// Incremental FNV-1a 64 over little-endian encodings of integers.
class Fnv1aHasher {
 public:
  void Byte(uint8_t b) {
    hash_ ^= b;
    hash_ *= kFnvPrime;
  }
  void U64(uint64_t v) {
    for (int i = 0; i < 8; ++i) Byte(static_cast<uint8_t>(v >> (8 * i)));
  }
  void U32(uint32_t v) {
    for (int i = 0; i < 4; ++i) Byte(static_cast<uint8_t>(v >> (8 * i)));
  }
  void Double(double d) {
    uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    U64(bits);
  }
  uint64_t hash() const { return hash_; }

 private:
  uint64_t hash_ = kFnvOffsetBasis;
};

bool AllFinite(const Eigen::MatrixX3d& m) { return m.allFinite(); }

int64_t Binomial3(int64_t n) { return n * (n - 1) * (n - 2) / 6; }

Status ValidateRound(const RoundStatistics& r, const std::string& what) {
  if (r.round < 0 || r.knots < 0 || r.control_points < 0) {
    return InvalidArgumentError(what + " has a negative count");
  }
  for (double v : {r.rmse_percent, r.max_error_percent, r.vertex_rmse_percent,
                   r.vertex_max_error_percent, r.folded_area_percent}) {
    if (!std::isfinite(v)) {
      return InvalidArgumentError(what + " has a non-finite value");
    }
  }
  return Status::Ok();
}

Status ValidateStatistics(const FitStatistics& s) {
  for (size_t i = 0; i < s.rounds.size(); ++i) {
    SDCB_RETURN_IF_ERROR(
        ValidateRound(s.rounds[i], "fit statistics round " + Str(i)));
  }
  SDCB_RETURN_IF_ERROR(ValidateRound(s.final_result, "final fit statistics"));
  const RecordedFitOptions& o = s.options;
  for (double v : {o.rmse_percent, o.lambda, o.alpha, o.regularization,
                   o.fairness, o.samples_per_spacing,
                   o.thinned_cells_per_spacing, o.feature_angle_degrees}) {
    if (!std::isfinite(v)) {
      return InvalidArgumentError("a recorded fit option is not finite");
    }
  }
  if (s.error_measure != ErrorMeasure::kVertices &&
      s.error_measure != ErrorMeasure::kDenseTwoSided) {
    return InvalidArgumentError("unknown error measure");
  }
  return Status::Ok();
}

Status ValidateSet(const ConfigurationSet& set, int degree, int64_t num_knots,
                   const std::string& what) {
  const size_t size = static_cast<size_t>(degree) + 3;
  if (set.knots.size() != size) {
    return InvalidArgumentError(what + " has " + Str(set.knots.size()) +
                                " knots; degree " + Str(degree) + " needs " +
                                Str(size));
  }
  for (size_t j = 0; j < size; ++j) {
    if (set.knots[j] < 0 || set.knots[j] >= num_knots) {
      return InvalidArgumentError(what + " refers to knot " +
                                  Str(set.knots[j]) + ", out of range 0.." +
                                  Str(num_knots - 1));
    }
    if (j > 0 && set.knots[j] <= set.knots[j - 1]) {
      return InvalidArgumentError(
          what + ": knot indices are not strictly ascending (repeated knot?)");
    }
  }
  const int64_t max_boundaries = Binomial3(static_cast<int64_t>(size));
  if (set.boundaries.empty() ||
      static_cast<int64_t>(set.boundaries.size()) > max_boundaries) {
    return InvalidArgumentError(what + " has " + Str(set.boundaries.size()) +
                                " boundary triples; expected 1.." +
                                Str(max_boundaries));
  }
  for (size_t b = 0; b < set.boundaries.size(); ++b) {
    const std::array<int, 3>& t = set.boundaries[b];
    if (!(t[0] < t[1] && t[1] < t[2])) {
      return InvalidArgumentError(what + ": boundary triple " + Str(b) +
                                  " is not strictly ascending");
    }
    for (int v : t) {
      if (!std::binary_search(set.knots.begin(), set.knots.end(), v)) {
        return InvalidArgumentError(what + ": boundary triple " + Str(b) +
                                    " uses knot " + Str(v) +
                                    ", which is not in the set");
      }
    }
    if (b > 0 && !(set.boundaries[b - 1] < t)) {
      return InvalidArgumentError(
          what + ": boundary triples are not sorted or repeat");
    }
  }
  return Status::Ok();
}

}  // namespace

Eigen::MatrixX3d NormalizingTransform::ToInput(
    const Eigen::MatrixX3d& normalized) const {
  Eigen::MatrixX3d out(normalized.rows(), 3);
  for (Eigen::Index i = 0; i < normalized.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      out(i, c) = scale * normalized(i, c) + translation[c];
    }
  }
  return out;
}

Eigen::MatrixX3d NormalizingTransform::ToNormalized(
    const Eigen::MatrixX3d& input) const {
  Eigen::MatrixX3d out(input.rows(), 3);
  for (Eigen::Index i = 0; i < input.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      out(i, c) = (input(i, c) - translation[c]) / scale;
    }
  }
  return out;
}

StatusOr<NormalizingTransform> ComputeNormalizingTransform(
    const TriangleMesh& mesh) {
  if (mesh.vertices.rows() == 0) {
    return InvalidInputError("the mesh has no vertices");
  }
  if (!AllFinite(mesh.vertices)) {
    return InvalidInputError("the mesh has a non-finite vertex coordinate");
  }
  const Eigen::RowVector3d lo = mesh.vertices.colwise().minCoeff();
  const Eigen::RowVector3d hi = mesh.vertices.colwise().maxCoeff();
  NormalizingTransform t;
  // Midpoint as lo + (hi - lo) / 2 would differ in the last bit; (lo + hi)/2
  // is the documented definition (may overflow only beyond 1e308).
  t.translation = (0.5 * (lo + hi)).transpose();
  t.scale = (hi - lo).maxCoeff();
  if (!(t.scale > 0.0) || !std::isfinite(t.scale) ||
      !t.translation.allFinite()) {
    return InvalidInputError(
        "the mesh's bounding box is a single point or overflows; cannot "
        "normalize it");
  }
  return t;
}

uint64_t Fnv1a64(const void* data, size_t size) {
  Fnv1aHasher h;
  const auto* bytes = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < size; ++i) h.Byte(bytes[i]);
  return h.hash();
}

uint64_t HashTriangleMesh(const TriangleMesh& mesh) {
  Fnv1aHasher h;
  h.U64(static_cast<uint64_t>(mesh.vertices.rows()));
  h.U64(static_cast<uint64_t>(mesh.faces.rows()));
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    for (int c = 0; c < 3; ++c) h.Double(mesh.vertices(i, c));
  }
  for (Eigen::Index i = 0; i < mesh.faces.rows(); ++i) {
    for (int c = 0; c < 3; ++c) h.U32(static_cast<uint32_t>(mesh.faces(i, c)));
  }
  return h.hash();
}

Status ValidateSplineModel(const SplineModel& model) {
  const int k = model.degree;
  if (k < 0 || k > kMaxSplineDegree) {
    return InvalidArgumentError("degree " + Str(k) + " is outside 0.." +
                                Str(kMaxSplineDegree));
  }
  if (model.configurations.degree != k) {
    return InvalidArgumentError("the configurations have degree " +
                                Str(model.configurations.degree) +
                                " but the model has degree " + Str(k));
  }
  const int64_t n = model.knots.rows();
  if (n < k + 4) {
    return InvalidArgumentError("the model has " + Str(n) + " knots; degree " +
                                Str(k) + " needs at least " + Str(k + 4));
  }
  if (!AllFinite(model.knots)) {
    return InvalidArgumentError("a knot coordinate is not finite");
  }
  if (const Eigen::Index bad = FirstNonUnitRow(model.knots); bad >= 0) {
    return InvalidArgumentError("knot " + Str(bad) + " is not a unit vector");
  }
  const std::vector<ConfigurationSet>& sets = model.configurations.sets;
  if (sets.empty()) {
    return InvalidArgumentError("the model has no basis functions");
  }
  for (size_t i = 0; i < sets.size(); ++i) {
    SDCB_RETURN_IF_ERROR(
        ValidateSet(sets[i], k, n, "basis function " + Str(i)));
    if (i > 0 && !(sets[i - 1].knots < sets[i].knots)) {
      return InvalidArgumentError("basis function " + Str(i) +
                                  " is out of order or repeats the previous");
    }
  }
  if (model.control_points.rows() != static_cast<Eigen::Index>(sets.size())) {
    return InvalidArgumentError(
        "the model has " + Str(model.control_points.rows()) +
        " control points for " + Str(sets.size()) + " basis functions");
  }
  if (!AllFinite(model.control_points)) {
    return InvalidArgumentError("a control point coordinate is not finite");
  }
  const NormalizingTransform& t = model.transform;
  if (!std::isfinite(t.scale) || !(t.scale > 0.0) ||
      !t.translation.allFinite()) {
    return InvalidArgumentError(
        "the normalizing transform needs a finite scale > 0 and a finite "
        "translation");
  }
  if (model.basis_form != BasisForm::kNormalized &&
      model.basis_form != BasisForm::kRaw) {
    return InvalidArgumentError("unknown basis form");
  }
  SDCB_RETURN_IF_ERROR(ValidateStatistics(model.statistics));
  if (model.source.num_vertices < 0 || model.source.num_faces < 0) {
    return InvalidArgumentError("the source mesh has a negative count");
  }
  if (model.parameters.rows() != 0) {
    if (model.parameters.rows() != model.source.num_vertices) {
      return InvalidArgumentError("the model stores " +
                                  Str(model.parameters.rows()) +
                                  " sphere parameters for a source mesh of " +
                                  Str(model.source.num_vertices) + " vertices");
    }
    if (!AllFinite(model.parameters)) {
      return InvalidArgumentError("a sphere parameter is not finite");
    }
    if (const Eigen::Index bad = FirstNonUnitRow(model.parameters); bad >= 0) {
      return InvalidArgumentError("the sphere parameter of vertex " + Str(bad) +
                                  " is not a unit vector");
    }
  }
  return Status::Ok();
}

}  // namespace sdcb
