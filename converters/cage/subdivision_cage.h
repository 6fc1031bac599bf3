// A subdivision cage fitted to a spherical spline (docs/CAGE.md): a
// Catmull-Clark (quads) or Loop (triangles) control mesh whose limit surface
// follows the spline within a measured distance.
//
// Each round: the cage's topology lives on the sphere
// (core/cage/sphere_cage_topology.h), so every cage face has a sphere region;
// dense samples of the spline in each region (its fast evaluator,
// core/spline/piecewise_surface.h) are the targets, weighted by the area
// they stand for, the rows of
// the least-squares system are OpenSubdiv's limit stencils at the samples'
// (face, u, v) (converters/cage/limit_surface.h), plus a light umbrella fairing
// of the cage; solved by the fit's solver (core/fit/least_squares.h). The
// samples' (u, v) are then moved to their closest limit points (parameter
// correction, Newton steps) and the cage solved again. The limit surface is
// measured against the spline both ways (converters/cage/cage_deviation.h), and
// the leaves of the cage that hold the largest share of the squared error
// are refined, until the two-sided rms is within the tolerance or the next
// round would exceed the face budget.
#ifndef SDCB_CONVERTERS_CAGE_SUBDIVISION_CAGE_H_
#define SDCB_CONVERTERS_CAGE_SUBDIVISION_CAGE_H_

#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "sdcb/converters/cage/cage_deviation.h"
#include "sdcb/converters/cage/limit_surface.h"
#include "sdcb/core/cage/sphere_cage_topology.h"
#include "sdcb/core/common/progress.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/measure/surface_sampler.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

struct CageRound {
  int round = 0;
  int faces = 0;
  int vertices = 0;
  double limit_rmse_percent = 0.0;
  double limit_max_error_percent = 0.0;
  double seconds = 0.0;  // since the start of the fit
};

struct CageOptions {
  SubdivisionScheme scheme = SubdivisionScheme::kCatmullClark;
  // Target two-sided rms distance between the limit surface and the spline,
  // percent of `length_unit`.
  double tolerance_percent = 0.1;
  // The cage never has more faces.
  int max_faces = 20000;
  int max_rounds = 40;
  // Uniform refinements of the cube / icosahedron before the first round.
  int initial_levels = 2;
  // Samples per cage face: k^2 at the centres of a k by k grid (quads) or
  // of the k^2 triangles of a level-k lattice (triangles).
  int samples_per_side = 5;
  // Weight of the umbrella fairing relative to the data term.
  double fairing = 1e-4;
  // Parameter corrections (each followed by a new solve) per round.
  int parameter_corrections = 2;
  // Dorfler marking: the leaves holding this share of the squared error
  // are refined each round.
  double refine_share = 0.5;
  // ... but a round at most multiplies the face count by this (> 1), so
  // that the cage stops near the smallest size that meets the tolerance.
  double max_growth = 1.5;
  // The length that is 100 % (1 in a model's normalized frame).
  double length_unit = 1.0;
  // Points of each surface in the measurement of the returned cage; that of
  // every round (which decides the refinement and the stop) takes this many
  // per cage face, at least 10000 and at most measure_samples.
  int measure_samples = 100000;
  int round_samples_per_face = 16;
  // Called after every round and before the final measurement with a stage
  // name ("round 3, 260 faces") and an estimate of the finished fraction in
  // [0, 1], from the calling thread.
  ProgressCallback progress;
};

struct SubdivisionCage {
  SubdivisionScheme scheme = SubdivisionScheme::kCatmullClark;
  // #V by 3 cage positions, in the spline's frame.
  Eigen::MatrixX3d vertices;
  // The faces and the sphere layout (SphereCage::faces: quads, or
  // triangles with -1 as fourth entry).
  SphereCage layout;
  // Infinitely sharp edges (vertex pairs): a spline's creases.
  std::vector<std::array<int, 2>> creases;
};

struct CageFit {
  SubdivisionCage cage;
  CageDeviation deviation;  // of the returned cage
  std::vector<CageRound> rounds;
  std::string stop_reason;
  double seconds = 0.0;
  // Where they went: the fast evaluator and the spline's image, the rounds'
  // fits (limit surfaces and solves) and measurements, the final
  // measurement.
  struct StageSeconds {
    double setup = 0.0, fit = 0.0, measure = 0.0, final_measure = 0.0;
  } stage_seconds;
};

// Fits a cage to `spline` (any frame; distances in percent of
// options.length_unit). kInvalidArgument for bad options. A Catmull-Clark
// cage of a spline whose knots hold feature arcs (a fit that kept its sharp
// edges, core/knots/feature_knots.h) that cut the sphere into quads is first
// tried as those quads with every arc an infinitely sharp crease (the cube: 8
// vertices, 6 faces, 12 creases), kept if its limit surface meets the
// tolerance.
StatusOr<CageFit> FitSubdivisionCage(const SphericalSpline& spline,
                                     const CageOptions& options = {});

// The positions of a cage with the topology `layout` that fit `spline` best
// (one solve with parameter corrections, no refinement). Exposed for tests
// and benchmarks. `spline` as a sampler: a PiecewiseSplineSampler (the
// first form makes one).
StatusOr<Eigen::MatrixX3d> FitCagePositions(const SphericalSpline& spline,
                                            const SphereCage& layout,
                                            const LimitSurface& limit,
                                            const CageOptions& options = {});
StatusOr<Eigen::MatrixX3d> FitCagePositions(const SurfaceSampler& spline,
                                            const SphereCage& layout,
                                            const LimitSurface& limit,
                                            const CageOptions& options = {});

// The cage's faces as files write them, counter-clockwise seen from
// outside: the layout's (SphereCage::faces), each reversed when the cage at
// `positions` encloses a negative volume (a spline fitted to a mesh stored
// inward turns its faces as that mesh did).
std::vector<std::array<int, 4>> OutwardCageFaces(
    const SubdivisionCage& cage, const Eigen::MatrixX3d& positions);

// The cage as Wavefront OBJ text: "v x y z" per vertex (%.17g), "f a b c
// [d]" per face (1-based, OutwardCageFaces), after a comment header naming the
// scheme; each crease as OpenSubdiv's shape tag "t crease 2/1/0 a b 10"
// (0-based vertices, sharpness 10 = infinitely sharp), which OBJ readers that
// do not know it skip.
std::string CageObjText(const SubdivisionCage& cage,
                        const Eigen::MatrixX3d& positions);

// One cage per part of a model (docs/CAGE.md): the part's name in files
// (its own, or "part1", "part2", ...), its fit, and the cage's vertices in
// the input's coordinates (the part's transform).
struct PartCage {
  std::string name;
  CageFit fit;
  Eigen::MatrixX3d positions;
};

// Ok, or kInvalidInput naming the first open part: "part 2 is open (1 trim
// loop); cages of open parts are not supported yet".
Status CheckCageParts(const Model& model);

// CheckCageParts, then FitSubdivisionCage for every part in order, each in
// its part's normalized frame (options.length_unit as given); errors name
// the part ("part 2: ...") when there are several.
StatusOr<std::vector<PartCage>> FitModelCages(const Model& model,
                                              const CageOptions& options = {});

// Several cages in one OBJ: each as CageObjText writes it alone, with
// "o NAME" after its header line and its face and crease indices offset by
// the vertices of the cages before it (OBJ indices are file-wide). One cage
// gives CageObjText's text.
std::string CageObjText(const std::vector<PartCage>& parts);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAGE_SUBDIVISION_CAGE_H_
