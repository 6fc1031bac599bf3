// The certificate of a coarse tessellation against dense surface samples
// (core/tessellate/surface_samples.h). The coarse faces are faces of the
// samples' own pattern after collapses, flips and splits, so every sample
// lies in exactly one coarse face's domain triangle: the vertices the
// simplification removed are the samples inside the faces that replaced
// them. A coarse face (a, b, c) passes at threshold t when, at every sample
// inside it,
//   - the distance from the sample's surface point to the mesh near the
//     face is at most t: to the flat triangle (S(a), S(b), S(c)), or, for a
//     point within the face's longest edge of it, to the nearest of the
//     triangles across its three edges (where the parameterization shears
//     a patch sideways, its points lie over the neighbour's triangle:
//     "leaning" faces);
//   - its flat normal faces the way the surface normals at its corners do;
//   - if the face's image is larger than the tolerance and the angular test
//     is on, the normal of the triangle the sample is measured to is within
//     angle_degrees of the surface normal there (and the face's at its
//     corners).
// The samples' spacing is what this certificate can see: a maximum between
// samples is found by the tessellator's final verification
// (core/tessellate/face_verification.h), not here. Changes are evaluated
// without being made (Evaluate) and then recorded (Apply) after the caller
// has made them in the triangulation.
#ifndef SDCB_CORE_TESSELLATE_SAMPLED_CERTIFICATE_H_
#define SDCB_CORE_TESSELLATE_SAMPLED_CERTIFICATE_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "sdcb/core/tessellate/sphere_triangulation.h"
#include "sdcb/core/tessellate/surface_samples.h"

namespace sdcb {

struct CertificateOptions {
  double tolerance = 1e-3;       // surface units
  double angle_degrees = 180.0;  // 180: no angular test
};

// A change of the triangulation to certify: the faces `faces` in the slots
// `slots` replace the faces `old_faces` (a superset of the slots); the
// samples inside the old faces and `freed` (vertices the change removes) are
// redistributed among the new faces.
struct FaceChange {
  std::vector<SphereTriangulation::Face> faces;
  std::vector<int> slots;
  std::vector<int> old_faces;
  std::vector<int> freed;
};

// What Evaluate found, for Apply.
struct ChangeResult {
  double worst = 0.0;  // largest distance over the new faces
  // When the change fails: the distance that failed it (a lower bound of
  // the threshold it would need), infinite if it failed whatever the
  // threshold (a face turned over, outside the angle, degenerate).
  double failed_at = 0.0;
  std::vector<double> errors;  // per new face
  std::vector<int> worst_sample;
  std::vector<char> leans;
  std::vector<std::vector<int>> samples;  // per new face
  // Faces outside the change that lean on its faces, measured again.
  std::vector<int> outer;
  std::vector<double> outer_errors;
};

class SampledFaces {
 public:
  // `samples` must outlive this object; its pattern is the triangulation
  // the caller changes. Every face starts with no sample inside.
  SampledFaces(SurfaceSamples* samples, const CertificateOptions& options);

  SurfaceSamples& samples() { return *samples_; }
  const SurfaceSamples& samples() const { return *samples_; }
  const SphereTriangulation& pattern() const { return samples_->pattern; }
  double error(int f) const { return errors_[f]; }
  bool tests_angle() const { return test_angle_; }
  const std::vector<int>& samples_in(int f) const { return inside_[f]; }

  // Whether the change passes at `threshold`; fills `result` when it does
  // (result->worst is then its largest distance). Does not modify this
  // object; thread-safe against other Evaluate calls.
  bool Evaluate(const FaceChange& change, double threshold,
                ChangeResult* result) const;
  // Records an evaluated change the caller has made in the pattern.
  void Apply(const FaceChange& change, ChangeResult* result);
  // Records a change the caller has made without a certificate (a split):
  // its samples are redistributed and measured, whatever they measure.
  void Reassign(const FaceChange& change);

  // The largest distance from the surface points `points` (rows first ..
  // first + count - 1) to the mesh near face f (the rule above, with the
  // neighbours across its edges as the pattern has them). With `normals`,
  // `angle_ok` tells whether the face passes the angular and orientation
  // tests at them (always true for faces the tests do not apply to), and
  // `angle` gets the largest angle (radians) between the flat normal and the
  // surface normals at them and the corners (0 for those faces), and
  // `worst` the row of the point that fails first (a normal outside the
  // angle, else the largest distance).
  double MeasurePoints(int f, const Eigen::MatrixX3d& points,
                       const Eigen::MatrixX3d* normals, Eigen::Index first,
                       Eigen::Index count, double threshold, bool* angle_ok,
                       double* angle, Eigen::Index* worst) const;

  // Makes the samples' coarse pattern (SurfaceSamples::coarse_faces) the
  // pattern, each of the other vertices a sample inside its coarse face,
  // and measures every face. The samples must have a coarse pattern.
  void StartFromCoarse();

  // Grows the per-face state to the pattern's face slots (after splits).
  void Resize();
  // From now on Evaluate also measures each new face on the barycentric
  // lattice of order `order` (fresh points between the samples, evaluated
  // by `surface`, corners excluded) once its samples pass; order 0 turns
  // this off. `surface` must outlive its use.
  void SetLattice(const SurfaceSampler* surface, int order);

 private:
  // Largest distance of face t's samples `ids`, fail-fast at `threshold`:
  // -1 if a sample fails. `across` are the triangles across t's edges.
  struct Geometry;
  // False if the flat face is degenerate, turns over against a corner's
  // normal or fails the angular test at a corner (the geometry is filled
  // either way).
  bool MakeGeometry(const SphereTriangulation::Face& t, Geometry* g) const;
  // The triangles across g's edges: of g's change if it has one, else the
  // pattern's.
  void FillAcross(Geometry* g) const;
  // Distance of point q to the mesh near g; infinite if `normal` (if not
  // null) fails g's angular test.
  double Distance(Geometry& g, const Eigen::Vector3d& q,
                  const Eigen::Vector3d* normal, double threshold,
                  bool* leaned) const;
  bool Measure(const FaceChange& change, double threshold, bool force,
               ChangeResult* result) const;

  SurfaceSamples* samples_;
  CertificateOptions options_;
  double cos_angle_ = -1.0;
  bool test_angle_ = false;
  const SurfaceSampler* lattice_surface_ = nullptr;
  std::vector<Eigen::Vector3d> lattice_weights_;
  std::vector<std::vector<int>> inside_;  // per face slot
  std::vector<double> errors_;
  std::vector<int> worst_;  // the sample of the largest distance, or -1
  std::vector<char> leans_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_TESSELLATE_SAMPLED_CERTIFICATE_H_
