#include "sdcb/core/tessellate/adaptive_tessellation.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <tuple>
#include <vector>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/tessellate/sphere_triangulation.h"
#include "sdcb/core/tessellate/triangle_distance.h"

namespace sdcb {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The optimizer aims its predicted errors at the certificate's threshold
// itself: faces the prediction underestimates are split afterwards, which
// costs fewer faces than aiming every face lower.
// The remesher aims its metric edge lengths at kRemeshScale of that (its
// faces spread around the aim; the tail above it is split) for
// kRemeshIterations rounds; then at most kPasses rounds of greedy
// collapses, flips and moves.
constexpr double kRemeshScale = 0.9;
constexpr int kRemeshIterations = 16;
constexpr int kPasses = 6;
// The local optimizer (the alternative to the remesher) aims lower: its
// failures are bisected along LEPP paths.
constexpr double kLocalAim = 0.85;
// The certificate accepts a sampled distance up to (1 - kLatticeMargin /
// m^2) times the tolerance, m the lattice order: for a surface quadratic
// over an affinely mapped face the lattice misses at most 4 / (3 m^2) of
// the maximum.
constexpr double kLatticeMargin = 4.0 / 3.0;
// Where the surface is not quadratic over a face (its curvature changes
// within it) the order-6 lattice missed up to 16 % of the maximum on the
// bunny: faces sampled above kRecheckFraction of the threshold are sampled
// again at kShearedRefinement times the order.
constexpr double kRecheckFraction = 0.7;
// Faces whose lattice image has cells longer than kMaxLatticeStretch times
// the regular lattice's are sampled again on a finer lattice (order at most
// kMaxLattice).
constexpr double kMaxLatticeStretch = 1.2;
constexpr int kMaxLattice = 24;
// Faces sampled above kRecheckFraction of the threshold are sampled again
// at kShearedRefinement times the order (sheared ones at kShearedLattice).
constexpr double kShearedRefinement = 3.0;
// A lattice point may be measured against a neighbour's triangle only if it
// is within kShearFraction of the face's smallest height from its own
// triangle: then splitting the face's edges cannot turn a face over.
constexpr double kShearFraction = 0.25;
// Rounds of edge flips that unfold faces turned over by re-certification.
constexpr int kUnfoldRounds = 4;
// Certified simplification: at most kSimplifyWaves waves; per vertex the
// kSimplifyTargets half-edge collapses of lowest predicted error are
// certified, if predicted within kSimplifyPriorityCap times the threshold
// (on the bunny at 0.01 % no cap gave 0.05 % fewer faces), then, if none
// passed, the full collapse of the edge to the best target, its merged
// vertex at the edge's midpoint and, failing that, at the better by
// prediction of kPlacements - 1 other places (kPlacementsTried in all).
// Then at most kRelocationRounds rounds of certified vertex moves (per
// vertex, the kRelocationsTried of kRelocations candidate places lowest by
// prediction) and collapses around the moved vertices. Bunny00 at 0.03 %
// (bench/tessellation_efficiency_bench): 27 552 faces before; the other
// placements 27 056; with moves that lower their faces' largest distance by
// 3 % at least, 1 / 3 / 6 rounds: 26 526 / 26 372 / 26 358; by any amount,
// 3 rounds: 25 536, 6: 25 354; and 3 half-edge targets instead of 2:
// 25 370 (1 round: 25 846; moves only where the prediction also drops:
// 26 036, 41 % fewer evaluations; one candidate certified per vertex:
// 25 508). They cost evaluations: 115 M without the moves, 280 M with.
constexpr int kSimplifyWaves = 400;
constexpr int kSimplifyTargets = 3;
constexpr double kSimplifyPriorityCap = 2.0;
constexpr int kPlacements = 3;
constexpr size_t kPlacementsTried = 2;
constexpr int kRelocations = 3;
constexpr size_t kRelocationsTried = 2;
constexpr int kRelocationRounds = 3;
// Moves search for places where the certificate passes, and near the
// threshold they found places where it passes short of the true distance
// (the bear at 0.01 %: measured 0.010046 %). The faces of a move sampled
// above kRecheckFraction of the threshold are therefore sampled again at
// kShearedLattice, as sheared faces are (the bear: 0.009933 %, 56 454
// faces), but the bunny still measured 0.010011 %: the collapses after the
// moves find such places too. Keeping moves below 0.98 / 0.99 of the
// threshold cost most of their gain (bear 57 784 / 57 740 faces, 1.51 x
// N_opt); what is kept is the final verification of every face on the
// order-36 lattice (TessellationOptions::verify; bear 56 554 faces,
// measured 0.009675 %, bunny 77 506 faces, 0.009813 %).
// Faces measured against their neighbours' triangles (where the order-18
// lattice missed up to 10 % on the bunny, measured at order 40) are sampled
// again at this order (order 18 with the ascent below measured 0.01015 %
// on the bear at 0.01 % when used for the simplification's collapses, and
// 0.101 % at 0.1 % for the faces split after it: near the edges the
// distance to the nearer of two triangles has kinks the ascent does not
// climb). The same order everywhere keeps the final certificate the one
// each face was accepted with.
constexpr int kShearedLattice = 36;

// The lattice misses sharp interior maxima (on the bear at 0.01 %, a face
// sampled at 0.943 of the tolerance on the order-36 lattice measured 1.013
// at order 200, its maximum inside the face, not near a neighbour): faces whose
// sampled distance is above kAscentFraction of the threshold are hill-climbed
// from their largest sample (the six lattice directions, step half the
// lattice's spacing, halved when no neighbour is higher, down to
// kAscentSmallestStep of the spacing; at most kAscentRounds rounds of
// evaluations).
constexpr double kAscentFraction = 0.8;
constexpr double kAscentSmallestStep = 1.0 / 32.0;
constexpr int kAscentRounds = 10;

// Result of certifying one face.
struct FaceCheck {
  double distance = 0.0;  // largest sampled distance surface -> triangle
  double angle = 0.0;     // largest normal angle (radians), if tested
  bool pass = true;
  // Whether a sample was measured against a neighbour's triangle (then the
  // result depends on the faces across the edges, not on the face alone).
  bool needs_neighbours = false;
};

// A face to certify, with everything its certificate depends on: its
// corners (domain directions, surface points and unit normals) and the flat
// triangles across its three edges (the near-mesh rule). Built from the
// triangulation as it is, or from a change that has not been made yet.
struct FaceToCheck {
  std::array<Eigen::Vector3d, 3> direction, position, normal;
  // across[e]: the triangle across edge (e, e + 1), if has_across[e].
  std::array<std::array<Eigen::Vector3d, 3>, 3> across;
  std::array<bool, 3> has_across{{false, false, false}};
};

// A vertex at a candidate place (a vertex move being certified); vertex -1:
// none.
struct MovedVertex {
  int vertex = -1;
  Eigen::Vector3d direction, position, normal;
};

// A collapse to certify: the half-edge collapse of a into b, or, if
// moved.vertex is b, the full collapse of edge (a, b) to `moved`.
struct Change {
  int a = -1, b = -1;
  MovedVertex moved;
  // With a = -1: the move of b to `moved` alone, made only if its faces'
  // largest distance is below `below`.
  double below = std::numeric_limits<double>::infinity();
  std::vector<std::array<int, 3>> faces;  // the faces it makes
  std::vector<int> recheck;  // faces whose certificate used replaced faces
};

// Where one change is made, with the alternatives tried in order.
struct Site {
  std::vector<int> region;  // the vertices the changes depend on
  std::vector<Change> changes;
};

// Per group (groups[i]: the group of face i, if groups is not null):
// whether one of its faces failed.
std::vector<char> FailedGroups(const std::vector<int>* groups,
                               const std::vector<FaceCheck>& checks) {
  std::vector<char> failed;
  if (!groups) return failed;
  for (size_t i = 0; i < checks.size(); ++i) {
    const size_t g = (*groups)[i];
    if (failed.size() <= g) failed.resize(g + 1, 0);
    if (!checks[i].pass) failed[g] = 1;
  }
  return failed;
}

// The lattice points (i, j, k) / m, i + j + k = m, without the corners.
std::vector<Eigen::Vector3d> LatticeWeights(int m) {
  std::vector<Eigen::Vector3d> w;
  for (int i = 0; i <= m; ++i)
    for (int j = 0; i + j <= m; ++j) {
      const int k = m - i - j;
      if (i == m || j == m || k == m) continue;
      w.emplace_back(i, j, k);
    }
  return w;
}

// The pairs of adjacent points of the lattice of order m, as indices into
// LatticeWeights(m) (corner weights (m,0,0), (0,m,0), (0,0,m) as -1, -2, -3).
std::vector<std::pair<int, int>> LatticeEdges(int m) {
  auto index = [m](int i, int j) {
    const int k = m - i - j;
    if (i == m) return -1;
    if (j == m) return -2;
    if (k == m) return -3;
    int n = 0;
    for (int x = 0; x <= m; ++x)
      for (int y = 0; x + y <= m; ++y) {
        const int z = m - x - y;
        if (x == m || y == m || z == m) continue;
        if (x == i && y == j) return n;
        ++n;
      }
    return n;
  };
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i <= m; ++i)
    for (int j = 0; i + j <= m; ++j) {
      if (i + j < m) {
        edges.push_back({index(i, j), index(i + 1, j)});
        edges.push_back({index(i, j), index(i, j + 1)});
        edges.push_back({index(i + 1, j), index(i, j + 1)});
      }
    }
  return edges;
}

// The edge (a, b), a < b, of face t with the largest measure(a, b); the
// first of equals in the face's order.
template <typename Measure>
std::array<int, 2> LongestEdgeBy(const SphereTriangulation::Face& t,
                                 const Measure& measure) {
  std::array<int, 2> longest{};
  double best = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const int a = t[k], b = t[(k + 1) % 3];
    const double l = measure(a, b);
    if (l > best) {
      best = l;
      longest = {std::min(a, b), std::max(a, b)};
    }
  }
  return longest;
}

// The tessellator's state: the domain triangulation plus the surface at its
// vertices.
class Tessellator {
 public:
  Tessellator(const SurfaceSampler& surface, const TessellationOptions& options)
      : surface_(surface),
        options_(options),
        weights_(LatticeWeights(options.lattice)),
        lattice_edges_(LatticeEdges(options.lattice)),
        accept_(options.tolerance *
                (1.0 - kLatticeMargin / (options.lattice * options.lattice))),
        cos_angle_(std::cos(options.angle_degrees * kPi / 180.0)),
        test_angle_(options.angle_degrees < 180.0) {}

  Status Run(Tessellation* out);

 private:
  double EdgeLength(int a, int b) const {
    // The domain (chord) length orders bisections: a median is shorter than
    // the longest edge, so LEPP paths end. A surface length would not: where
    // the surface spikes, a midpoint's image can be farther from the
    // opposite corner than the split edge was long, and the path never ends.
    return (triangulation_.vertex(a) - triangulation_.vertex(b)).norm();
  }
  double ImageLength(int a, int b) const {
    return (positions_[a] - positions_[b]).norm();
  }
  void AddVertex(int v) {
    Eigen::MatrixX3d d(1, 3), p, n;
    d.row(0) = triangulation_.vertex(v);
    surface_.Sample(d, &p, &n);
    ++evaluations_;
    if (static_cast<int>(positions_.size()) <= v) {
      positions_.resize(v + 1);
      normals_.resize(v + 1);
    }
    positions_[v] = p.row(0).transpose();
    normals_[v] = n.row(0).transpose();
  }
  // Splits faces until every face reachable from `pending` is certified.
  Status Refine(std::vector<int> pending);
  // Certifies `pending` and splits the longest image edge of each face that
  // fails (no LEPP path: after remeshing, the neighbours' longest edges are
  // unrelated and the paths would split far more than needed), until every
  // face is certified or too small to split.
  Status RefineBySplits(std::vector<int> pending);
  // kInvalidInput once the faces exceed options_.max_faces.
  Status CheckFaceBudget() const {
    if (triangulation_.num_faces() <= options_.max_faces) return Status::Ok();
    return InvalidInputError("the tolerance needs more than " +
                             std::to_string(options_.max_faces) + " triangles");
  }
  // The live faces in slots first, first + 1, ... (those made since).
  std::vector<int> AliveSince(int first) const {
    std::vector<int> alive;
    for (int f = first; f < triangulation_.num_face_slots(); ++f) {
      if (triangulation_.alive(f)) alive.push_back(f);
    }
    return alive;
  }
  // `faces` and the faces across their edges (sorted, unique): a face's
  // certificate depends on its edge neighbours' triangles.
  std::vector<int> WithNeighbours(std::vector<int> faces) const {
    const size_t n = faces.size();
    for (size_t i = 0; i < n; ++i) {
      const auto& t = triangulation_.face(faces[i]);
      for (int e = 0; e < 3; ++e) {
        const int g = triangulation_.Opposite(faces[i], t[e], t[(e + 1) % 3]);
        if (g >= 0) faces.push_back(g);
      }
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    return faces;
  }
  double PredictedError(int a, int b, int c) const;
  double PredictedError(const Eigen::Vector3d& pa, const Eigen::Vector3d& pb,
                        const Eigen::Vector3d& pc, const Eigen::Vector3d& na,
                        const Eigen::Vector3d& nb,
                        const Eigen::Vector3d& nc) const;
  // Whether `faces` are positively oriented on the domain with `moved`
  // where its vertex would be.
  bool PositiveOnDomain(const std::vector<SphereTriangulation::Face>& faces,
                        const MovedVertex& moved) const {
    for (const auto& t : faces) {
      Eigen::Vector3d d[3];
      for (int i = 0; i < 3; ++i) {
        d[i] = t[i] == moved.vertex ? moved.direction
                                    : triangulation_.vertex(t[i]);
      }
      if (!SphereTriangulation::IsPositive(d[0], d[1], d[2])) return false;
    }
    return true;
  }
  // The largest predicted error of `faces` with `moved` where its vertex
  // would be.
  double WorstPredicted(const std::vector<SphereTriangulation::Face>& faces,
                        const MovedVertex& moved) const {
    auto p = [&](int v) -> const Eigen::Vector3d& {
      return v == moved.vertex ? moved.position : positions_[v];
    };
    auto n = [&](int v) -> const Eigen::Vector3d& {
      return v == moved.vertex ? moved.normal : normals_[v];
    };
    double w = 0.0;
    for (const auto& t : faces) {
      w = std::max(w, PredictedError(p(t[0]), p(t[1]), p(t[2]), n(t[0]),
                                     n(t[1]), n(t[2])));
    }
    return w;
  }
  double WorstPredicted(
      const std::vector<SphereTriangulation::Face>& faces) const;
  // The worst predicted error after collapsing v into w (inf if invalid).
  double CollapseCost(int v, int w,
                      std::vector<SphereTriangulation::Face>* scratch) const;
  // The remesher, then greedy collapses, flips and vertex moves, all guided
  // by PredictedError.
  void Optimize();
  // Collapses (shortest edges first), flips and moves from the refined
  // pattern, aiming at kLocalAim of the certificate.
  void OptimizeLocally();
  int CollapseShortestFirst(double target);
  int CollapsePass(double target);
  int FlipPass(double target);
  // Vertex moves that lower the largest predicted error of their faces;
  // `weighted` adds candidates pulled toward the worst faces.
  int Smooth(double target, bool weighted);
  // The remesher (Optimize's first stage): edges measured in the metric of
  // the predicted error, split when long, collapsed when short, flipped and
  // relaxed toward metric-equilateral faces.
  double MetricLength2(int a, int b, double target) const;
  // Splits the given edges at their domain midpoints (one batch of surface
  // evaluations).
  int SplitEdges(const std::vector<std::array<int, 2>>& edges);
  int SplitLong(double target);
  int CollapseShort(double target);
  int Relax(double target);
  // Splits the metric-longest edge of every face predicted above `target`
  // until none is (or `rounds` rounds).
  void SplitOverTarget(double target, int rounds);
  // `worst_row` (if not null) gets the row of the largest distance.
  double NearMeshDistance(const FaceToCheck& c, const Eigen::MatrixX3d& samples,
                          Eigen::Index first, Eigen::Index count,
                          bool* used_neighbours = nullptr,
                          Eigen::Index* worst_row = nullptr) const;
  // Hill-climbs from the sampled maximum of each face in `faces` whose
  // check passed near the threshold (see kAscentFraction), raising its
  // distance to the local maximum found.
  void AscendNearThreshold(const std::vector<FaceToCheck>& faces,
                           const std::vector<int>* groups,
                           const std::vector<Eigen::Vector3d>& worst_weights,
                           const std::vector<double>& worst_step,
                           const std::vector<double>* below,
                           std::vector<FaceCheck>* checks);
  double LatticeStretch(const FaceToCheck& c, const Eigen::MatrixX3d& samples,
                        Eigen::Index first) const;
  // Face t with the geometry of the triangulation, except that the faces
  // `replacing` stand where they share its edges (a change being
  // certified) and `moved` is where its vertex would be.
  FaceToCheck ToCheck(const SphereTriangulation::Face& t,
                      const std::vector<SphereTriangulation::Face>& replacing,
                      const MovedVertex& moved = {}) const;
  // Certifies `faces` in one batch. With `groups` (a group per face: the
  // faces of one candidate change), faces of a group that already failed
  // are neither sampled again on the finer lattice nor climbed.
  // With `below` (a bound per face), a face also fails where its distance
  // is not below its bound (then its group is decided early).
  std::vector<FaceCheck> CheckFaces(const std::vector<FaceToCheck>& faces,
                                    const std::vector<int>* groups,
                                    const std::vector<double>* below = nullptr);
  // Whether face f's image faces the way the surface normals at its corners
  // do.
  bool Oriented(int f) const {
    const auto& t = triangulation_.face(f);
    return Oriented(t[0], t[1], t[2]);
  }
  bool Oriented(int a, int b, int c) const {
    const Eigen::Vector3d cross =
        (positions_[b] - positions_[a]).cross(positions_[c] - positions_[a]);
    return cross.dot(normals_[a]) > 0.0 && cross.dot(normals_[b]) > 0.0 &&
           cross.dot(normals_[c]) > 0.0;
  }
  // Certified simplification (see the header): waves of collapses of the
  // vertices whose surroundings changed until none is left.
  void SimplifyCertified();
  int CollapseWaves(std::vector<char>* dirty);
  // Certified vertex moves that lower the largest distance of their faces
  // (toward their worst faces), in waves of disjoint regions; marks the
  // moved vertices' regions dirty. Returns the number of moves.
  // `all`: every vertex, else those around changes made since the last
  // call.
  int RelocateWaves(bool all, std::vector<char>* dirty);
  // The vertices a change replacing the faces `replaced` depends on or
  // affects: theirs and the apexes of the faces across their boundary
  // (`outer` gets those faces).
  std::vector<int> Region(const std::vector<int>& replaced,
                          std::vector<int>* outer) const;
  // Locks `region` for wave `wave` if none of it is locked yet.
  bool Lock(const std::vector<int>& region, int wave);
  // Fills the change's faces' orientation test and the faces to certify
  // again; false if a made face turns over against the surface normals.
  bool Prepare(Change* change) const;
  // Certifies every change of every site in one batch and makes, per site,
  // the first change whose faces all pass; marks the made
  // sites' regions dirty. Returns the number of changes made.
  // `made` (if not null) gets per site whether a change was made.
  int CertifyAndMake(std::vector<Site>* sites, std::vector<char>* dirty,
                     std::vector<char>* made_at = nullptr);
  // Per face slot: whether the face passed its last certificate, whether
  // that used its neighbours' triangles, and the distance it measured.
  void RecordChecks(const std::vector<int>& faces,
                    const std::vector<FaceCheck>& checks);
  // Flips an edge of each face turned over against the surface (a split of
  // a thin, sheared face can put the new vertex beyond the opposite corner)
  // where both new faces are oriented; returns the number of flips.
  int UnfoldByFlips();
  // UnfoldByFlips, then certification of the faces it made, a few rounds.
  Status Unfold();
  // Certifies `faces` (alive face slots) as the triangulation is.
  std::vector<FaceCheck> Check(const std::vector<int>& faces);
  double ShortestDomainEdge(int f) const {
    const auto& t = triangulation_.face(f);
    double s = 4.0;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d& a = triangulation_.vertex(t[i]);
      const Eigen::Vector3d& b = triangulation_.vertex(t[(i + 1) % 3]);
      s = std::min(s, std::atan2(a.cross(b).norm(), a.dot(b)));
    }
    return s;
  }

  const SurfaceSampler& surface_;
  const TessellationOptions options_;
  const std::vector<Eigen::Vector3d> weights_;
  // Adjacent lattice points as indices into weights_ (corner k as -k - 1).
  const std::vector<std::pair<int, int>> lattice_edges_;
  const double accept_;
  const double cos_angle_;
  const bool test_angle_;
  SphereTriangulation triangulation_;
  std::vector<Eigen::Vector3d> positions_, normals_;
  std::vector<char> slot_certified_, slot_needs_neighbours_;
  std::vector<double> slot_distance_;
  std::vector<int> locked_;  // per vertex: the wave that locked it
  // Per vertex: whether a change was made around it since the last round of
  // moves (a move refused where nothing changed would be refused again).
  std::vector<char> changed_;
  int wave_id_ = 0;
  // Set for the final verification (options_.verify): every face sampled
  // above kRecheckFraction of the threshold is sampled again at
  // kShearedLattice.
  bool verify_densely_ = false;
  int64_t evaluations_ = 0;
  double max_distance_ = 0.0, max_angle_ = 0.0;
  int uncertified_ = 0;
};

// The largest distance from the surface points `samples` (rows first,
// first + 1, ..., of face c's lattice) to the mesh near face c: its own flat
// triangle, or, for a point farther than the threshold from it, the closest
// of the triangles across its three edges. Where the parameterization
// shears the patch sideways, a point beyond the face's edge lies over the
// neighbour's triangle, and the distance to the mesh is measured there.
double Tessellator::NearMeshDistance(const FaceToCheck& c,
                                     const Eigen::MatrixX3d& samples,
                                     Eigen::Index first, Eigen::Index count,
                                     bool* used_neighbours,
                                     Eigen::Index* worst_row) const {
  const Eigen::Vector3d& pa = c.position[0];
  const Eigen::Vector3d& pb = c.position[1];
  const Eigen::Vector3d& pc = c.position[2];
  const double height =
      (pb - pa).cross(pc - pa).norm() /
      std::max({(pa - pb).norm(), (pb - pc).norm(), (pc - pa).norm()});
  double worst = 0.0;
  for (Eigen::Index k = first; k < first + count; ++k) {
    const Eigen::Vector3d q = samples.row(k).transpose();
    double d = PointTriangleDistance(q, pa, pb, pc);
    if (d > accept_ && d <= kShearFraction * height) {
      if (used_neighbours) *used_neighbours = true;
      for (int e = 0; e < 3 && d > accept_; ++e) {
        if (!c.has_across[e]) continue;
        const auto& u = c.across[e];
        d = std::min(d, PointTriangleDistance(q, u[0], u[1], u[2]));
      }
    }
    if (d > worst || (worst_row && *worst_row < 0)) {
      worst = std::max(worst, d);
      if (worst_row) *worst_row = k;
    }
  }
  return worst;
}

// How far from affine the parameterization is over face c: the largest
// ratio of a lattice cell edge's image (between the surface samples) to the
// same edge of the flat triangle's lattice (1 for an affine map). Where a
// thin face is sheared, the image of its lattice leaves gaps that the
// lattice does not sample.
double Tessellator::LatticeStretch(const FaceToCheck& c,
                                   const Eigen::MatrixX3d& samples,
                                   Eigen::Index first) const {
  const double m = options_.lattice;
  auto image = [&](int index) -> Eigen::Vector3d {
    return index < 0 ? c.position[-index - 1]
                     : Eigen::Vector3d(samples.row(first + index).transpose());
  };
  auto flat = [&](int index) -> Eigen::Vector3d {
    if (index < 0) return c.position[-index - 1];
    const Eigen::Vector3d& w = weights_[index];
    return (w[0] * c.position[0] + w[1] * c.position[1] +
            w[2] * c.position[2]) /
           m;
  };
  double stretch2 = 1.0;
  for (const auto& [x, y] : lattice_edges_) {
    const double along = (flat(x) - flat(y)).squaredNorm();
    const double imaged = (image(x) - image(y)).squaredNorm();
    if (imaged > stretch2 * along) {
      stretch2 = along > 0.0 ? imaged / along
                             : std::numeric_limits<double>::infinity();
    }
  }
  return std::sqrt(stretch2);
}

FaceToCheck Tessellator::ToCheck(
    const SphereTriangulation::Face& t,
    const std::vector<SphereTriangulation::Face>& replacing,
    const MovedVertex& moved) const {
  auto position = [&](int v) -> const Eigen::Vector3d& {
    return v == moved.vertex ? moved.position : positions_[v];
  };
  FaceToCheck c;
  for (int k = 0; k < 3; ++k) {
    const int v = t[k];
    c.direction[k] =
        v == moved.vertex ? moved.direction : triangulation_.vertex(v);
    c.position[k] = position(v);
    c.normal[k] = v == moved.vertex ? moved.normal : normals_[v];
  }
  for (int e = 0; e < 3; ++e) {
    const int p = t[e], q = t[(e + 1) % 3];
    // The face with the directed edge q -> p: a replacing face first (the
    // triangulation's face there is being replaced), else the
    // triangulation's.
    const SphereTriangulation::Face* across = nullptr;
    for (const auto& u : replacing) {
      for (int k = 0; k < 3 && !across; ++k) {
        if (u[k] == q && u[(k + 1) % 3] == p) across = &u;
      }
      if (across) break;
    }
    if (!across) {
      const int g = triangulation_.FaceOf(q, p);
      if (g < 0) continue;
      across = &triangulation_.face(g);
    }
    c.has_across[e] = true;
    for (int k = 0; k < 3; ++k) c.across[e][k] = position((*across)[k]);
  }
  return c;
}

std::vector<FaceCheck> Tessellator::Check(const std::vector<int>& faces) {
  // In chunks, so the faces' geometry is not copied all at once.
  constexpr size_t kChunk = size_t{1} << 16;
  std::vector<FaceCheck> checks;
  checks.reserve(faces.size());
  std::vector<FaceToCheck> chunk;
  for (size_t begin = 0; begin < faces.size(); begin += kChunk) {
    const size_t n = std::min(kChunk, faces.size() - begin);
    chunk.resize(n);
    tbb::parallel_for(size_t{0}, n, [&](size_t i) {
      chunk[i] = ToCheck(triangulation_.face(faces[begin + i]), {});
    });
    const std::vector<FaceCheck> part = CheckFaces(chunk, nullptr);
    checks.insert(checks.end(), part.begin(), part.end());
  }
  return checks;
}

std::vector<FaceCheck> Tessellator::CheckFaces(
    const std::vector<FaceToCheck>& faces, const std::vector<int>* groups,
    const std::vector<double>* below) {
  // Whether face i's distance passes: within the threshold and, with
  // `below`, under its bound.
  const auto within = [&](size_t i, double distance) {
    return distance <= accept_ && (!below || distance < (*below)[i]);
  };
  const size_t s = weights_.size();
  Eigen::MatrixX3d directions(faces.size() * s, 3);
  tbb::parallel_for(size_t{0}, faces.size(), [&](size_t i) {
    const FaceToCheck& c = faces[i];
    for (size_t k = 0; k < s; ++k) {
      const Eigen::Vector3d& w = weights_[k];
      directions.row(i * s + k) =
          (w[0] * c.direction[0] + w[1] * c.direction[1] +
           w[2] * c.direction[2])
              .normalized();
    }
  });
  Eigen::MatrixX3d positions, normals;
  surface_.Sample(directions, &positions, test_angle_ ? &normals : nullptr);
  evaluations_ += directions.rows();
  std::vector<FaceCheck> checks(faces.size());
  std::vector<int> finer(faces.size(), 0);
  // Per face: the barycentric weights (summing to 1) of its largest sampled
  // distance and the spacing of the lattice that found it.
  std::vector<Eigen::Vector3d> worst_weights(faces.size());
  std::vector<double> worst_step(faces.size(), 1.0 / options_.lattice);
  tbb::parallel_for(size_t{0}, faces.size(), [&](size_t i) {
    const FaceToCheck& c = faces[i];
    const Eigen::Vector3d& pa = c.position[0];
    const Eigen::Vector3d& pb = c.position[1];
    const Eigen::Vector3d& pc = c.position[2];
    FaceCheck& check = checks[i];
    bool sheared = false;
    Eigen::Index worst_row = -1;
    check.distance =
        NearMeshDistance(c, positions, i * s, s, &sheared, &worst_row);
    worst_weights[i] = weights_[worst_row - i * s] / options_.lattice;
    check.needs_neighbours = sheared;
    check.pass = within(i, check.distance);
    if (check.pass) {
      const double stretch = LatticeStretch(c, positions, i * s);
      if (sheared || stretch > kMaxLatticeStretch ||
          check.distance > kRecheckFraction * accept_) {
        // Clamped before the conversion (the stretch is infinite where a
        // flat lattice edge has no length).
        finer[i] = static_cast<int>(std::min<double>(
            kMaxLattice, std::ceil(options_.lattice *
                                   std::max(stretch, kShearedRefinement))));
      }
      // Sheared faces: where the lattice misses most. Faces of a move near
      // the threshold too (moves search for places where the certificate
      // passes, and find where it passes short), and in the final
      // verification every face near the threshold.
      if (sheared ||
          ((verify_densely_ || (below && std::isfinite((*below)[i]))) &&
           check.distance > kRecheckFraction * accept_)) {
        finer[i] = std::max(finer[i], kShearedLattice);
      }
    }
    const double diameter =
        std::max({(pa - pb).norm(), (pb - pc).norm(), (pc - pa).norm()});
    if (!test_angle_ || diameter <= options_.tolerance) return;
    const Eigen::Vector3d cross = (pb - pa).cross(pc - pa);
    const double area2 = cross.norm();
    if (!(area2 > 0.0)) {
      check.angle = kPi;
      check.pass = false;
      return;
    }
    const Eigen::Vector3d n = cross / area2;
    double min_cos = 1.0;
    for (size_t k = 0; k < s; ++k) {
      min_cos = std::min(min_cos, n.dot(normals.row(i * s + k).transpose()));
    }
    for (int k = 0; k < 3; ++k) min_cos = std::min(min_cos, n.dot(c.normal[k]));
    check.angle = std::acos(std::clamp(min_cos, -1.0, 1.0));
    if (min_cos < cos_angle_) check.pass = false;
  });
  // Groups (candidate changes) with a failed face are decided: their other
  // faces need no finer sampling.
  const std::vector<char> group_failed = FailedGroups(groups, checks);
  // Faces whose lattice image is stretched (the parameterization is far
  // from affine over them) are sampled again on a lattice fine enough that
  // its image is as dense as the regular lattice of the flat triangle.
  std::vector<size_t> again;
  std::vector<Eigen::Index> offsets = {0};
  for (size_t i = 0; i < faces.size(); ++i) {
    if (!checks[i].pass || finer[i] == 0) continue;
    if (groups && group_failed[(*groups)[i]]) continue;
    again.push_back(i);
    const Eigen::Index m = finer[i];
    offsets.push_back(offsets.back() + (m + 1) * (m + 2) / 2 - 3);
  }
  if (again.empty()) {
    AscendNearThreshold(faces, groups, worst_weights, worst_step, below,
                        &checks);
    return checks;
  }
  Eigen::MatrixX3d fine_directions(offsets.back(), 3);
  std::vector<Eigen::Vector3d> fine_weights(offsets.back());
  tbb::parallel_for(size_t{0}, again.size(), [&](size_t j) {
    const FaceToCheck& c = faces[again[j]];
    const int m = finer[again[j]];
    Eigen::Index row = offsets[j];
    for (int x = 0; x <= m; ++x)
      for (int y = 0; x + y <= m; ++y) {
        const int z = m - x - y;
        if (x == m || y == m || z == m) continue;
        fine_weights[row] = Eigen::Vector3d(x, y, z) / m;
        fine_directions.row(row++) =
            (x * c.direction[0] + y * c.direction[1] + z * c.direction[2])
                .normalized()
                .transpose();
      }
  });
  Eigen::MatrixX3d fine_positions;
  surface_.Sample(fine_directions, &fine_positions, nullptr);
  evaluations_ += fine_directions.rows();
  tbb::parallel_for(size_t{0}, again.size(), [&](size_t j) {
    FaceCheck& check = checks[again[j]];
    bool sheared = false;
    Eigen::Index worst_row = -1;
    const double fine =
        NearMeshDistance(faces[again[j]], fine_positions, offsets[j],
                         offsets[j + 1] - offsets[j], &sheared, &worst_row);
    if (fine > check.distance) {
      check.distance = fine;
      worst_weights[again[j]] = fine_weights[worst_row];
      worst_step[again[j]] = 1.0 / finer[again[j]];
    }
    check.needs_neighbours = check.needs_neighbours || sheared;
    check.pass = check.pass && within(again[j], check.distance);
  });
  AscendNearThreshold(faces, groups, worst_weights, worst_step, below, &checks);
  return checks;
}

void Tessellator::AscendNearThreshold(
    const std::vector<FaceToCheck>& faces, const std::vector<int>* groups,
    const std::vector<Eigen::Vector3d>& worst_weights,
    const std::vector<double>& worst_step, const std::vector<double>* below,
    std::vector<FaceCheck>* checks) {
  // Groups (candidate changes) with a failed face are decided.
  const std::vector<char> group_failed = FailedGroups(groups, *checks);
  std::vector<size_t> which;
  for (size_t i = 0; i < faces.size() && options_.ascend; ++i) {
    const FaceCheck& check = (*checks)[i];
    if (!check.pass || check.distance <= kAscentFraction * accept_) continue;
    if (groups && group_failed[(*groups)[i]]) continue;
    which.push_back(i);
  }
  // The six barycentric directions of the lattice.
  static const std::array<Eigen::Vector3d, 6> kSteps = {
      Eigen::Vector3d(1, -1, 0), Eigen::Vector3d(-1, 1, 0),
      Eigen::Vector3d(1, 0, -1), Eigen::Vector3d(-1, 0, 1),
      Eigen::Vector3d(0, 1, -1), Eigen::Vector3d(0, -1, 1)};
  std::vector<Eigen::Vector3d> at(which.size());
  std::vector<double> step(which.size()), value(which.size());
  std::vector<char> sheared(which.size(), 0);
  for (size_t j = 0; j < which.size(); ++j) {
    at[j] = worst_weights[which[j]];
    step[j] = 0.5 * worst_step[which[j]];
    value[j] = (*checks)[which[j]].distance;
  }
  for (int round = 0; round < kAscentRounds; ++round) {
    std::vector<size_t> active;
    for (size_t j = 0; j < which.size(); ++j) {
      if (step[j] >= kAscentSmallestStep * worst_step[which[j]]) {
        active.push_back(j);
      }
    }
    if (active.empty()) break;
    Eigen::MatrixX3d directions(active.size() * kSteps.size(), 3);
    std::vector<char> inside(directions.rows(), 0);
    tbb::parallel_for(size_t{0}, active.size(), [&](size_t a) {
      const size_t j = active[a];
      const FaceToCheck& c = faces[which[j]];
      for (size_t k = 0; k < kSteps.size(); ++k) {
        const size_t row = a * kSteps.size() + k;
        Eigen::Vector3d w = at[j] + step[j] * kSteps[k];
        inside[row] = w.minCoeff() >= 0.0;
        if (!inside[row]) w = at[j];
        directions.row(row) = (w[0] * c.direction[0] + w[1] * c.direction[1] +
                               w[2] * c.direction[2])
                                  .normalized()
                                  .transpose();
      }
    });
    Eigen::MatrixX3d positions;
    surface_.Sample(directions, &positions, nullptr);
    evaluations_ += directions.rows();
    tbb::parallel_for(size_t{0}, active.size(), [&](size_t a) {
      const size_t j = active[a];
      double best = value[j];
      int best_k = -1;
      for (size_t k = 0; k < kSteps.size(); ++k) {
        const Eigen::Index row = a * kSteps.size() + k;
        if (!inside[row]) continue;
        bool used = false;
        const double d =
            NearMeshDistance(faces[which[j]], positions, row, 1, &used);
        if (used) sheared[j] = 1;
        if (d > best) {
          best = d;
          best_k = static_cast<int>(k);
        }
      }
      if (best_k < 0) {
        step[j] *= 0.5;
      } else {
        at[j] += step[j] * kSteps[best_k];
        value[j] = best;
      }
    });
  }
  for (size_t j = 0; j < which.size(); ++j) {
    FaceCheck& check = (*checks)[which[j]];
    check.distance = std::max(check.distance, value[j]);
    check.needs_neighbours = check.needs_neighbours || sheared[j];
    check.pass = check.pass && check.distance <= accept_ &&
                 (!below || check.distance < (*below)[which[j]]);
  }
}

Status Tessellator::Refine(std::vector<int> pending) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  const auto on_vertex = [this](int v) { AddVertex(v); };
  while (!pending.empty()) {
    const std::vector<FaceCheck> checks = Check(pending);
    const int first_new = triangulation_.num_face_slots();
    for (size_t i = 0; i < pending.size(); ++i) {
      const int f = pending[i];
      if (checks[i].pass || !triangulation_.alive(f)) continue;
      if (ShortestDomainEdge(f) < options_.min_edge_radians) continue;
      triangulation_.Bisect(f, length, on_vertex);
      SDCB_RETURN_IF_ERROR(CheckFaceBudget());
    }
    pending = WithNeighbours(AliveSince(first_new));
  }
  return Status::Ok();
}

Status Tessellator::RefineBySplits(std::vector<int> pending) {
  while (!pending.empty()) {
    const std::vector<FaceCheck> checks = Check(pending);
    const int first_new = triangulation_.num_face_slots();
    std::vector<std::array<int, 2>> edges;
    for (size_t i = 0; i < pending.size(); ++i) {
      const int f = pending[i];
      if (checks[i].pass) continue;
      if (ShortestDomainEdge(f) < options_.min_edge_radians) continue;
      edges.push_back(LongestEdgeBy(triangulation_.face(f), [&](int a, int b) {
        return ImageLength(a, b);
      }));
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    SplitEdges(edges);
    SDCB_RETURN_IF_ERROR(CheckFaceBudget());
    pending = WithNeighbours(AliveSince(first_new));
  }
  return Status::Ok();
}

int Tessellator::UnfoldByFlips() {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  std::vector<SphereTriangulation::Face> faces;
  int flipped = 0;
  const int slots = triangulation_.num_face_slots();
  for (int f = 0; f < slots; ++f) {
    if (!triangulation_.alive(f) || Oriented(f)) continue;
    const auto t = triangulation_.face(f);
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (!triangulation_.PreviewFlip(a, b, &faces)) continue;
      if (!Oriented(faces[0][0], faces[0][1], faces[0][2]) ||
          !Oriented(faces[1][0], faces[1][1], faces[1][2])) {
        continue;
      }
      triangulation_.Flip(a, b, length);
      ++flipped;
      break;
    }
  }
  return flipped;
}

Status Tessellator::Unfold() {
  for (int round = 0; round < kUnfoldRounds; ++round) {
    const int first_new = triangulation_.num_face_slots();
    if (UnfoldByFlips() == 0) break;
    SDCB_RETURN_IF_ERROR(RefineBySplits(WithNeighbours(AliveSince(first_new))));
  }
  return Status::Ok();
}

// Chordal error of face (a, b, c) predicted from its corners' positions and
// normals: for a quadratic surface over the triangle, linear interpolation
// misses by (1/2) |sum_{i<j} l_i l_j Q_ij| at barycentric point l, with
// Q_ij = (n_j - n_i) . (p_j - p_i) = d_ij^T H d_ij exactly. Infinite where a
// normal is missing (singular point) or the normal test fails.
double Tessellator::PredictedError(int a, int b, int c) const {
  return PredictedError(positions_[a], positions_[b], positions_[c],
                        normals_[a], normals_[b], normals_[c]);
}

double Tessellator::PredictedError(const Eigen::Vector3d& pa,
                                   const Eigen::Vector3d& pb,
                                   const Eigen::Vector3d& pc,
                                   const Eigen::Vector3d& na,
                                   const Eigen::Vector3d& nb,
                                   const Eigen::Vector3d& nc) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (na.isZero(0.0) || nb.isZero(0.0) || nc.isZero(0.0)) return kInf;
  const Eigen::Vector3d cross = (pb - pa).cross(pc - pa);
  const double area2 = cross.norm();
  if (!(area2 > 0.0)) return kInf;
  const Eigen::Vector3d n = cross / area2;
  // The image must not turn over against the surface normals.
  const double min_cos = std::min({n.dot(na), n.dot(nb), n.dot(nc)});
  if (min_cos <= 0.0) return kInf;
  if (test_angle_ && min_cos < cos_angle_) {
    const double diameter =
        std::max({(pa - pb).norm(), (pb - pc).norm(), (pc - pa).norm()});
    if (diameter > options_.tolerance) return kInf;
  }
  const double qab = (nb - na).dot(pb - pa), qbc = (nc - nb).dot(pc - pb),
               qca = (na - nc).dot(pa - pc);
  double worst = 0.0;
  constexpr int kOrder = 8;
  for (int i = 0; i <= kOrder; ++i)
    for (int j = 0; i + j <= kOrder; ++j) {
      const double la = double(i) / kOrder, lb = double(j) / kOrder,
                   lc = 1.0 - la - lb;
      worst = std::max(worst,
                       std::abs(la * lb * qab + lb * lc * qbc + lc * la * qca));
    }
  return 0.5 * worst;
}

double Tessellator::WorstPredicted(
    const std::vector<SphereTriangulation::Face>& faces) const {
  double w = 0.0;
  for (const auto& t : faces) w = std::max(w, PredictedError(t[0], t[1], t[2]));
  return w;
}

double Tessellator::CollapseCost(
    int v, int w, std::vector<SphereTriangulation::Face>* scratch) const {
  if (!triangulation_.PreviewCollapse(v, w, scratch)) {
    return std::numeric_limits<double>::infinity();
  }
  return WorstPredicted(*scratch);
}

// Greedy half-edge collapses, cheapest first: the cost of collapsing v into
// w is the largest predicted error of the faces that replace v's; only
// collapses within `target` are done. Costs go stale as the mesh changes:
// a popped candidate is re-evaluated and re-queued if it got dearer.
int Tessellator::CollapsePass(double target) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  struct Candidate {
    double cost;
    int from, to;
    bool operator>(const Candidate& o) const {
      return std::tie(cost, from, to) > std::tie(o.cost, o.from, o.to);
    }
  };
  std::priority_queue<Candidate, std::vector<Candidate>,
                      std::greater<Candidate>>
      heap;
  std::vector<SphereTriangulation::Face> scratch;
  auto push_best = [&](int a, int b) {
    const double ab = CollapseCost(a, b, &scratch);
    const double ba = CollapseCost(b, a, &scratch);
    if (std::min(ab, ba) > target) return;
    if (ab <= ba) {
      heap.push({ab, a, b});
    } else {
      heap.push({ba, b, a});
    }
  };
  const std::vector<std::array<int, 2>> edges = triangulation_.Edges();
  {
    // Initial costs in parallel (read-only), queued in edge order.
    std::vector<Candidate> initial(edges.size());
    tbb::parallel_for(size_t{0}, edges.size(), [&](size_t i) {
      std::vector<SphereTriangulation::Face> local;
      const int a = edges[i][0], b = edges[i][1];
      const double ab = CollapseCost(a, b, &local);
      const double ba = CollapseCost(b, a, &local);
      initial[i] = ab <= ba ? Candidate{ab, a, b} : Candidate{ba, b, a};
    });
    for (const Candidate& c : initial) {
      if (c.cost <= target) heap.push(c);
    }
  }
  int collapsed = 0;
  while (!heap.empty()) {
    const Candidate c = heap.top();
    heap.pop();
    if (!triangulation_.vertex_alive(c.from) ||
        !triangulation_.vertex_alive(c.to) ||
        !triangulation_.HasEdge(c.from, c.to)) {
      continue;
    }
    const double cost = CollapseCost(c.from, c.to, &scratch);
    if (cost > target) continue;
    if (cost > c.cost) {
      heap.push({cost, c.from, c.to});
      continue;
    }
    triangulation_.Collapse(c.from, c.to, length);
    ++collapsed;
    for (int x : triangulation_.Ring(c.to)) push_best(c.to, x);
  }
  return collapsed;
}

// One sweep of half-edge collapses, shortest image edges first, each to the
// end that gives the lower predicted error, within `target`.
int Tessellator::CollapseShortestFirst(double target) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  const std::vector<std::array<int, 2>> edges = triangulation_.Edges();
  std::vector<double> lengths(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    lengths[i] = (positions_[edges[i][0]] - positions_[edges[i][1]]).norm();
  }
  std::vector<size_t> order(edges.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t x, size_t y) { return lengths[x] < lengths[y]; });
  std::vector<SphereTriangulation::Face> scratch;
  int collapsed = 0;
  for (size_t o : order) {
    const int a = edges[o][0], b = edges[o][1];
    if (!triangulation_.HasEdge(a, b)) continue;
    const double ab = CollapseCost(a, b, &scratch);
    const double ba = CollapseCost(b, a, &scratch);
    if (std::min(ab, ba) > target) continue;
    if (ab <= ba) {
      triangulation_.Collapse(a, b, length);
    } else {
      triangulation_.Collapse(b, a, length);
    }
    ++collapsed;
  }
  return collapsed;
}

void Tessellator::OptimizeLocally() {
  const double target = kLocalAim * accept_;
  for (int pass = 0; pass < kPasses; ++pass) {
    int changes = CollapseShortestFirst(target);
    changes += FlipPass(target);
    changes += Smooth(target, false);
    if (changes == 0) break;
  }
}

// Flips that lower the larger predicted error of the two faces.
int Tessellator::FlipPass(double target) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  std::vector<SphereTriangulation::Face> faces, old_faces;
  int flipped = 0;
  for (const auto& [a, b] : triangulation_.Edges()) {
    if (!triangulation_.HasEdge(a, b)) continue;
    if (!triangulation_.PreviewFlip(a, b, &faces)) continue;
    const double after = WorstPredicted(faces);
    // New faces (a, d, c), (d, b, c) replace (a, b, c), (b, a, d).
    const int c = faces[0][2], d = faces[0][1];
    old_faces = {{a, b, c}, {b, a, d}};
    if (after < 0.98 * WorstPredicted(old_faces) && after <= target) {
      triangulation_.Flip(a, b, length);
      ++flipped;
    }
  }
  return flipped;
}

// |Q_ab| / (6 target) with Q_ab = (n_b - n_a) . (p_b - p_a) = d^T H d: the
// squared length of edge (a, b) in the metric of the second fundamental
// form, in units of the side of the equilateral face whose predicted error
// (at its centroid, Q / 6) is `target`. A face whose three edges have
// length <= 1 is predicted within `target` (the error is at most
// max |Q| / 6 for any H). 0 where a normal is missing.
double Tessellator::MetricLength2(int a, int b, double target) const {
  const Eigen::Vector3d& na = normals_[a];
  const Eigen::Vector3d& nb = normals_[b];
  if (na.isZero(0.0) || nb.isZero(0.0)) return 0.0;
  return std::abs((nb - na).dot(positions_[b] - positions_[a])) /
         (6.0 * target);
}

int Tessellator::SplitEdges(const std::vector<std::array<int, 2>>& edges) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  Eigen::MatrixX3d midpoints(edges.size(), 3);
  for (size_t i = 0; i < edges.size(); ++i) {
    midpoints.row(i) = (triangulation_.vertex(edges[i][0]) +
                        triangulation_.vertex(edges[i][1]))
                           .normalized()
                           .transpose();
  }
  Eigen::MatrixX3d positions, normals;
  surface_.Sample(midpoints, &positions, &normals);
  evaluations_ += midpoints.rows();
  int split = 0;
  for (size_t i = 0; i < edges.size(); ++i) {
    if (!triangulation_.HasEdge(edges[i][0], edges[i][1])) continue;
    triangulation_.SplitEdge(edges[i][0], edges[i][1], length, [&](int v) {
      if (static_cast<int>(positions_.size()) <= v) {
        positions_.resize(v + 1);
        normals_.resize(v + 1);
      }
      positions_[v] = positions.row(i).transpose();
      normals_[v] = normals.row(i).transpose();
    });
    ++split;
  }
  return split;
}

int Tessellator::SplitLong(double target) {
  constexpr double kLong2 = (4.0 / 3.0) * (4.0 / 3.0);
  std::vector<std::array<int, 2>> long_edges;
  for (const auto& e : triangulation_.Edges()) {
    if (MetricLength2(e[0], e[1], target) > kLong2) long_edges.push_back(e);
  }
  return SplitEdges(long_edges);
}

// Half-edge collapses of metric-short edges (shortest first) whose new
// edges stay short of the split threshold.
int Tessellator::CollapseShort(double target) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  constexpr double kShort2 = (4.0 / 5.0) * (4.0 / 5.0);
  constexpr double kLong2 = (4.0 / 3.0) * (4.0 / 3.0);
  std::vector<std::pair<double, std::array<int, 2>>> short_edges;
  for (const auto& e : triangulation_.Edges()) {
    const double l2 = MetricLength2(e[0], e[1], target);
    if (l2 < kShort2) short_edges.push_back({l2, e});
  }
  std::sort(short_edges.begin(), short_edges.end());
  std::vector<SphereTriangulation::Face> faces;
  int collapsed = 0;
  for (const auto& [l2, e] : short_edges) {
    if (!triangulation_.HasEdge(e[0], e[1])) continue;
    for (const auto& [v, w] :
         {std::make_pair(e[0], e[1]), std::make_pair(e[1], e[0])}) {
      if (!triangulation_.PreviewCollapse(v, w, &faces)) continue;
      bool fine = true;
      for (const auto& t : faces) {
        fine = fine && MetricLength2(t[1], t[0], target) < kLong2 &&
               MetricLength2(t[1], t[2], target) < kLong2 &&
               std::isfinite(PredictedError(t[0], t[1], t[2]));
      }
      if (!fine) continue;
      triangulation_.Collapse(v, w, length);
      ++collapsed;
      break;
    }
  }
  return collapsed;
}

// Tangential relaxation on the domain: each vertex moves halfway toward the
// centroid of its faces' domain centroids weighted by their predicted errors
// (for metric-equilateral faces the error is proportional to the metric
// area, so this is a centroidal step in the metric), where its faces stay
// positively oriented.
int Tessellator::Relax(double target) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  const std::vector<int> vertices = triangulation_.AliveVertices();
  Eigen::MatrixX3d candidates(vertices.size(), 3);
  tbb::parallel_for(size_t{0}, vertices.size(), [&](size_t i) {
    const int v = vertices[i];
    const std::vector<int> ring = triangulation_.Ring(v);
    const int n = static_cast<int>(ring.size());
    const Eigen::Vector3d& x = triangulation_.vertex(v);
    Eigen::Vector3d pull = Eigen::Vector3d::Zero();
    double weight = 0.0;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d& y = triangulation_.vertex(ring[k]);
      const Eigen::Vector3d& z = triangulation_.vertex(ring[(k + 1) % n]);
      double e = PredictedError(v, ring[k], ring[(k + 1) % n]);
      if (!std::isfinite(e)) e = 0.0;
      // Faces of no predicted error (flat) still hold the vertex in place.
      e = std::max(e, 1e-3 * target);
      pull += e * (x + y + z) / 3.0;
      weight += e;
    }
    candidates.row(i) = (x + (pull / weight).normalized()).normalized();
  });
  Eigen::MatrixX3d positions, normals;
  surface_.Sample(candidates, &positions, &normals);
  evaluations_ += candidates.rows();
  int moved = 0;
  // Per vertex: whether all its faces were predictable before the move
  // (then they must stay so).
  std::vector<char> predictable(vertices.size(), 0);
  for (size_t i = 0; i < vertices.size(); ++i) {
    const int v = vertices[i];
    const std::vector<int> ring = triangulation_.Ring(v);
    const int n = static_cast<int>(ring.size());
    predictable[i] = 1;
    for (int k = 0; k < n && predictable[i]; ++k) {
      predictable[i] =
          std::isfinite(PredictedError(v, ring[k], ring[(k + 1) % n]));
    }
    const Eigen::Vector3d old_direction = triangulation_.vertex(v);
    triangulation_.MoveVertex(v, candidates.row(i).transpose(), length);
    const Eigen::Vector3d old_position = positions_[v],
                          old_normal = normals_[v];
    positions_[v] = positions.row(i).transpose();
    normals_[v] = normals.row(i).transpose();
    // Valid: positive on the domain, and no face the prediction rejects
    // (normal test, turned-over image) that was not predictable before.
    bool valid = normals.row(i).squaredNorm() > 0.0;
    for (int k = 0; k < n && valid; ++k) {
      valid = triangulation_.IsPositive(v, ring[k], ring[(k + 1) % n]) &&
              (!predictable[i] ||
               std::isfinite(PredictedError(v, ring[k], ring[(k + 1) % n])));
    }
    if (!valid) {
      positions_[v] = old_position;
      normals_[v] = old_normal;
      triangulation_.MoveVertex(v, old_direction, length);
      continue;
    }
    ++moved;
  }
  return moved;
}

void Tessellator::SplitOverTarget(double target, int rounds) {
  for (int round = 0; round < rounds; ++round) {
    std::vector<std::array<int, 2>> edges;
    for (int f = 0; f < triangulation_.num_face_slots(); ++f) {
      if (!triangulation_.alive(f)) continue;
      const auto& t = triangulation_.face(f);
      const double error = PredictedError(t[0], t[1], t[2]);
      if (error <= target) continue;
      // Faces too small to split, and rejected faces (normal test) whose
      // image is within the tolerance (where the certificate does not test
      // normals: at a fold of the surface no face would pass), are left to
      // the certificate.
      if (ShortestDomainEdge(f) < options_.min_edge_radians) continue;
      if (!std::isfinite(error)) {
        const Eigen::Vector3d& pa = positions_[t[0]];
        const Eigen::Vector3d& pb = positions_[t[1]];
        const Eigen::Vector3d& pc = positions_[t[2]];
        if (std::max({(pa - pb).norm(), (pb - pc).norm(), (pc - pa).norm()}) <=
            options_.tolerance) {
          continue;
        }
      }
      // The metric-longest edge (domain length for ties and missing
      // normals); the image-longest where the prediction rejects the face.
      edges.push_back(LongestEdgeBy(t, [&](int a, int b) {
        return std::isfinite(error)
                   ? MetricLength2(a, b, target) + 1e-9 * EdgeLength(a, b)
                   : ImageLength(a, b);
      }));
    }
    if (edges.empty()) return;
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    SplitEdges(edges);
  }
}

void Tessellator::RecordChecks(const std::vector<int>& faces,
                               const std::vector<FaceCheck>& checks) {
  const size_t slots = triangulation_.num_face_slots();
  slot_certified_.resize(slots, 0);
  slot_needs_neighbours_.resize(slots, 0);
  slot_distance_.resize(slots, 0.0);
  for (size_t i = 0; i < faces.size(); ++i) {
    slot_certified_[faces[i]] = checks[i].pass;
    slot_needs_neighbours_[faces[i]] = checks[i].needs_neighbours;
    slot_distance_[faces[i]] = checks[i].distance;
  }
}

std::vector<int> Tessellator::Region(const std::vector<int>& replaced,
                                     std::vector<int>* outer) const {
  std::vector<int> region;
  outer->clear();
  for (int f : replaced) {
    const auto& t = triangulation_.face(f);
    region.insert(region.end(), t.begin(), t.end());
  }
  for (int f : replaced) {
    const auto& t = triangulation_.face(f);
    for (int e = 0; e < 3; ++e) {
      const int g = triangulation_.FaceOf(t[(e + 1) % 3], t[e]);
      if (g < 0 ||
          std::find(replaced.begin(), replaced.end(), g) != replaced.end()) {
        continue;
      }
      outer->push_back(g);
      const auto& u = triangulation_.face(g);
      region.insert(region.end(), u.begin(), u.end());
    }
  }
  std::sort(region.begin(), region.end());
  region.erase(std::unique(region.begin(), region.end()), region.end());
  return region;
}

bool Tessellator::Lock(const std::vector<int>& region, int wave) {
  if (locked_.size() < static_cast<size_t>(triangulation_.num_vertices())) {
    locked_.resize(triangulation_.num_vertices(), -1);
  }
  for (int x : region) {
    if (locked_[x] == wave) return false;
  }
  for (int x : region) locked_[x] = wave;
  return true;
}

bool Tessellator::Prepare(Change* change) const {
  const MovedVertex& m = change->moved;
  auto position = [&](int v) -> const Eigen::Vector3d& {
    return v == m.vertex ? m.position : positions_[v];
  };
  auto normal = [&](int v) -> const Eigen::Vector3d& {
    return v == m.vertex ? m.normal : normals_[v];
  };
  for (const auto& t : change->faces) {
    const Eigen::Vector3d cross = (position(t[1]) - position(t[0]))
                                      .cross(position(t[2]) - position(t[0]));
    for (int v : t) {
      if (!(cross.dot(normal(v)) > 0.0)) return false;
    }
  }
  // The faces across the made faces' boundary (edges no other made face
  // shares), if their certificate used the triangles across their edges.
  change->recheck.clear();
  for (const auto& t : change->faces) {
    for (int e = 0; e < 3; ++e) {
      const int p = t[e], q = t[(e + 1) % 3];
      bool inner = false;
      for (const auto& u : change->faces) {
        for (int k = 0; k < 3 && !inner; ++k) {
          inner = u[k] == q && u[(k + 1) % 3] == p;
        }
      }
      if (inner) continue;
      const int g = triangulation_.FaceOf(q, p);
      if (g >= 0 && slot_certified_[g] && slot_needs_neighbours_[g]) {
        change->recheck.push_back(g);
      }
    }
  }
  return true;
}

int Tessellator::CertifyAndMake(std::vector<Site>* sites,
                                std::vector<char>* dirty,
                                std::vector<char>* made_at) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  struct Ref {
    size_t site, change;
  };
  std::vector<Ref> refs;
  for (size_t i = 0; i < sites->size(); ++i) {
    for (size_t j = 0; j < (*sites)[i].changes.size(); ++j) {
      refs.push_back({i, j});
    }
  }
  std::vector<size_t> offsets = {0};
  for (const Ref& r : refs) {
    const Change& c = (*sites)[r.site].changes[r.change];
    offsets.push_back(offsets.back() + c.faces.size() + c.recheck.size());
  }
  std::vector<FaceToCheck> faces(offsets.back());
  std::vector<int> groups(offsets.back());
  std::vector<double> below(offsets.back(),
                            std::numeric_limits<double>::infinity());
  tbb::parallel_for(size_t{0}, refs.size(), [&](size_t k) {
    const Change& c = (*sites)[refs[k].site].changes[refs[k].change];
    size_t row = offsets[k];
    for (const auto& t : c.faces) {
      groups[row] = static_cast<int>(k);
      below[row] = c.below;
      faces[row++] = ToCheck(t, c.faces, c.moved);
    }
    for (int g : c.recheck) {
      groups[row] = static_cast<int>(k);
      faces[row++] = ToCheck(triangulation_.face(g), c.faces, c.moved);
    }
  });
  const std::vector<FaceCheck> checks = CheckFaces(faces, &groups, &below);
  std::vector<char> done(sites->size(), 0);
  int made = 0;
  for (size_t k = 0; k < refs.size(); ++k) {
    if (done[refs[k].site]) continue;
    const Change& c = (*sites)[refs[k].site].changes[refs[k].change];
    bool pass = true;
    for (size_t r = offsets[k]; r < offsets[k + 1] && pass; ++r) {
      pass = checks[r].pass;
    }
    if (!pass) continue;
    done[refs[k].site] = 1;
    const int first = triangulation_.num_face_slots();
    if (c.a >= 0) triangulation_.Collapse(c.a, c.b, length);
    std::vector<int> slots = AliveSince(first);
    if (c.moved.vertex == c.b) {
      // A full edge collapse: b moves to the new place.
      triangulation_.MoveVertex(c.b, c.moved.direction, length);
      positions_[c.b] = c.moved.position;
      normals_[c.b] = c.moved.normal;
      slots = triangulation_.Star(c.b);
    }
    std::vector<FaceCheck> made_checks(slots.size());
    for (size_t m = 0; m < slots.size(); ++m) {
      const auto& t = triangulation_.face(slots[m]);
      for (size_t f = 0; f < c.faces.size(); ++f) {
        if (std::is_permutation(t.begin(), t.end(), c.faces[f].begin())) {
          made_checks[m] = checks[offsets[k] + f];
        }
      }
    }
    RecordChecks(slots, made_checks);
    RecordChecks(c.recheck, std::vector<FaceCheck>(
                                checks.begin() + offsets[k] + c.faces.size(),
                                checks.begin() + offsets[k + 1]));
    for (int x : (*sites)[refs[k].site].region) {
      (*dirty)[x] = 1;
      if (static_cast<size_t>(x) >= changed_.size()) changed_.resize(x + 1, 0);
      changed_[x] = 1;
    }
    if (c.a >= 0) (*dirty)[c.a] = 0;
    ++made;
  }
  if (made_at) *made_at = std::move(done);
  return made;
}

int Tessellator::CollapseWaves(std::vector<char>* dirty) {
  struct Target {
    double cost;
    int to;
  };
  int total = 0;
  for (int wave = 0; wave < kSimplifyWaves; ++wave) {
    dirty->resize(triangulation_.num_vertices(), 0);
    std::vector<int> vertices;
    for (int v = 0; v < triangulation_.num_vertices(); ++v) {
      if ((*dirty)[v] && triangulation_.vertex_alive(v)) vertices.push_back(v);
    }
    if (vertices.empty()) break;
    // The best targets of each vertex by predicted error (the cheap
    // priority; the certificate decides).
    std::vector<std::array<Target, kSimplifyTargets>> targets(vertices.size());
    tbb::parallel_for(size_t{0}, vertices.size(), [&](size_t i) {
      const int v = vertices[i];
      std::vector<SphereTriangulation::Face> scratch;
      std::vector<Target> all;
      for (int w : triangulation_.Ring(v)) {
        const double cost = CollapseCost(v, w, &scratch);
        if (cost <= kSimplifyPriorityCap * accept_) all.push_back({cost, w});
      }
      std::sort(all.begin(), all.end(), [](const Target& a, const Target& b) {
        return std::tie(a.cost, a.to) < std::tie(b.cost, b.to);
      });
      for (int k = 0; k < kSimplifyTargets; ++k) {
        targets[i][k] =
            k < static_cast<int>(all.size())
                ? all[k]
                : Target{std::numeric_limits<double>::infinity(), -1};
      }
    });
    std::vector<size_t> order;
    for (size_t i = 0; i < vertices.size(); ++i) {
      if (targets[i][0].to < 0) {
        (*dirty)[vertices[i]] = 0;  // no collapse predicted to be possible
      } else {
        order.push_back(i);
      }
    }
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return std::tie(targets[a][0].cost, vertices[a]) <
             std::tie(targets[b][0].cost, vertices[b]);
    });
    // A wave: vertices whose regions are disjoint, cheapest first (then no
    // collapse of the wave changes what another's certificate depends on).
    // The region covers the faces of v and of its best target (for the
    // full edge collapse).
    std::vector<Site> sites;
    std::vector<std::array<int, 2>> site_edges;  // v and its best target
    std::vector<int> outer;
    for (size_t i : order) {
      const int v = vertices[i];
      std::vector<int> replaced = triangulation_.Star(v);
      const std::vector<int> star_v = replaced;
      for (int f : triangulation_.Star(targets[i][0].to)) {
        if (std::find(star_v.begin(), star_v.end(), f) == star_v.end()) {
          replaced.push_back(f);
        }
      }
      Site site;
      site.region = Region(replaced, &outer);
      if (!Lock(site.region, wave_id_)) continue;
      (*dirty)[v] = 0;
      for (const Target& target : targets[i]) {
        if (target.to < 0) break;
        Change c;
        c.a = v;
        c.b = target.to;
        if (!triangulation_.PreviewCollapse(v, target.to, &c.faces)) continue;
        if (!Prepare(&c)) continue;
        site.changes.push_back(std::move(c));
      }
      sites.push_back(std::move(site));
      site_edges.push_back({v, targets[i][0].to});
    }
    ++wave_id_;
    if (sites.empty()) break;
    std::vector<char> made_at;
    int made = CertifyAndMake(&sites, dirty, &made_at);
    // Where no half-edge collapse passed: the full collapse of the edge to
    // v's best target, the merged vertex at the edge's domain midpoint,
    // then at the better by prediction of the centroid of the merged
    // vertex's link and the point between the two.
    std::vector<size_t> open;
    for (size_t j = 0; j < sites.size(); ++j) {
      if (!made_at[j]) open.push_back(j);
    }
    Eigen::MatrixX3d places(open.size() * kPlacements, 3), positions, normals;
    for (size_t k = 0; k < open.size(); ++k) {
      const auto [v, w] = site_edges[open[k]];
      const Eigen::Vector3d mid =
          (triangulation_.vertex(v) + triangulation_.vertex(w)).normalized();
      Eigen::Vector3d link = Eigen::Vector3d::Zero();
      for (int x : {v, w}) {
        for (int y : triangulation_.Ring(x)) {
          if (y != v && y != w) link += triangulation_.vertex(y);
        }
      }
      link = link.squaredNorm() > 0.0 ? link.normalized() : mid;
      places.row(k * kPlacements + 0) = mid.transpose();
      places.row(k * kPlacements + 1) = link.transpose();
      places.row(k * kPlacements + 2) = (mid + link).normalized().transpose();
    }
    surface_.Sample(places, &positions, &normals);
    evaluations_ += places.rows();
    std::vector<Site> full;
    for (size_t k = 0; k < open.size(); ++k) {
      const auto [v, w] = site_edges[open[k]];
      std::vector<SphereTriangulation::Face> preview;
      if (!triangulation_.PreviewCollapse(v, w, &preview)) continue;
      // w's other faces, which move with it.
      for (int f : triangulation_.Star(w)) {
        const auto& t = triangulation_.face(f);
        if (std::find(t.begin(), t.end(), v) == t.end()) preview.push_back(t);
      }
      std::vector<std::pair<double, Change>> ranked;
      for (int j = 0; j < kPlacements; ++j) {
        const Eigen::Index row = k * kPlacements + j;
        Change c;
        c.a = v;
        c.b = w;
        c.moved.vertex = w;
        c.moved.direction = places.row(row).transpose();
        c.moved.position = positions.row(row).transpose();
        c.moved.normal = normals.row(row).transpose();
        if (!(c.moved.normal.squaredNorm() > 0.0)) continue;
        c.faces = preview;
        if (!PositiveOnDomain(c.faces, c.moved) || !Prepare(&c)) continue;
        const double predicted = WorstPredicted(c.faces, c.moved);
        ranked.emplace_back(j == 0 ? -1.0 : predicted, std::move(c));
      }
      if (ranked.empty()) continue;
      std::stable_sort(
          ranked.begin(), ranked.end(),
          [](const auto& x, const auto& y) { return x.first < y.first; });
      Site site;
      site.region = sites[open[k]].region;
      for (size_t j = 0; j < ranked.size() && j < kPlacementsTried; ++j) {
        site.changes.push_back(std::move(ranked[j].second));
      }
      full.push_back(std::move(site));
    }
    if (!full.empty()) made += CertifyAndMake(&full, dirty);
    total += made;
  }
  return total;
}

int Tessellator::RelocateWaves(bool all, std::vector<char>* dirty) {
  std::vector<int> vertices;
  changed_.resize(triangulation_.num_vertices(), 0);
  for (int v : triangulation_.AliveVertices()) {
    if (all || changed_[v]) vertices.push_back(v);
  }
  std::fill(changed_.begin(), changed_.end(), 0);
  // Per vertex: its faces' largest certified distance; worst first.
  std::vector<double> worst(vertices.size(), 0.0);
  for (size_t i = 0; i < vertices.size(); ++i) {
    for (int f : triangulation_.Star(vertices[i])) {
      worst[i] = std::max(worst[i], slot_distance_[f]);
    }
  }
  std::vector<size_t> order(vertices.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t x, size_t y) { return worst[x] > worst[y]; });
  int total = 0;
  std::vector<char> tried(vertices.size(), 0);
  for (int wave = 0; wave < kSimplifyWaves; ++wave) {
    std::vector<size_t> chosen;
    std::vector<std::vector<int>> regions;
    std::vector<int> outer;
    for (size_t i : order) {
      if (tried[i] || !triangulation_.vertex_alive(vertices[i])) continue;
      std::vector<int> region =
          Region(triangulation_.Star(vertices[i]), &outer);
      if (!Lock(region, wave_id_)) continue;
      tried[i] = 1;
      chosen.push_back(i);
      regions.push_back(std::move(region));
    }
    ++wave_id_;
    if (chosen.empty()) break;
    // Candidates: toward the centroid of the faces weighted by their
    // certified distance^4 (shrinks the worst), half and full step, and
    // half a step toward the ring's centroid.
    Eigen::MatrixX3d places(chosen.size() * kRelocations, 3), positions,
        normals;
    for (size_t j = 0; j < chosen.size(); ++j) {
      const int v = vertices[chosen[j]];
      const Eigen::Vector3d& x = triangulation_.vertex(v);
      Eigen::Vector3d pull = Eigen::Vector3d::Zero(), ring = pull;
      for (int f : triangulation_.Star(v)) {
        const auto& t = triangulation_.face(f);
        const double e = slot_distance_[f] / accept_;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int y : t) c += triangulation_.vertex(y);
        pull += e * e * e * e * c;
      }
      for (int y : triangulation_.Ring(v)) ring += triangulation_.vertex(y);
      const Eigen::Vector3d pulled =
          pull.squaredNorm() > 0.0 ? Eigen::Vector3d(pull.normalized()) : x;
      places.row(j * kRelocations + 0) = (x + pulled).normalized().transpose();
      places.row(j * kRelocations + 1) = pulled.transpose();
      places.row(j * kRelocations + 2) =
          (x + ring.normalized()).normalized().transpose();
    }
    surface_.Sample(places, &positions, &normals);
    evaluations_ += places.rows();
    std::vector<Site> sites;
    for (size_t j = 0; j < chosen.size(); ++j) {
      const int v = vertices[chosen[j]];
      const std::vector<int> star = triangulation_.Star(v);
      std::vector<std::pair<double, Change>> ranked;
      for (int k = 0; k < kRelocations; ++k) {
        const Eigen::Index row = j * kRelocations + k;
        Change c;
        c.b = v;
        c.moved.vertex = v;
        c.moved.direction = places.row(row).transpose();
        c.moved.position = positions.row(row).transpose();
        c.moved.normal = normals.row(row).transpose();
        c.below = worst[chosen[j]];
        if (!(c.moved.normal.squaredNorm() > 0.0)) continue;
        for (int f : star) c.faces.push_back(triangulation_.face(f));
        if (!PositiveOnDomain(c.faces, c.moved) || !Prepare(&c)) continue;
        ranked.emplace_back(WorstPredicted(c.faces, c.moved), std::move(c));
      }
      if (ranked.empty()) continue;
      std::stable_sort(
          ranked.begin(), ranked.end(),
          [](const auto& x, const auto& y) { return x.first < y.first; });
      Site site;
      site.region = std::move(regions[j]);
      for (size_t k = 0; k < ranked.size() && k < kRelocationsTried; ++k) {
        site.changes.push_back(std::move(ranked[k].second));
      }
      sites.push_back(std::move(site));
    }
    total += CertifyAndMake(&sites, dirty);
  }
  return total;
}

void Tessellator::SimplifyCertified() {
  std::vector<int> all;
  for (int f = 0; f < triangulation_.num_face_slots(); ++f) {
    if (triangulation_.alive(f)) all.push_back(f);
  }
  RecordChecks(all, Check(all));
  std::vector<char> dirty(triangulation_.num_vertices(), 1);
  CollapseWaves(&dirty);
  for (int round = 0; round < kRelocationRounds && options_.relocate; ++round) {
    dirty.assign(triangulation_.num_vertices(), 0);
    if (RelocateWaves(round == 0, &dirty) == 0) break;
    if (CollapseWaves(&dirty) == 0) break;
  }
}

void Tessellator::Optimize() {
  const double target = accept_;
  const double remesh_target = kRemeshScale * target;
  for (int it = 0; it < kRemeshIterations; ++it) {
    SplitLong(remesh_target);
    CollapseShort(remesh_target);
    FlipPass(std::numeric_limits<double>::infinity());
    Relax(remesh_target);
  }
  SplitOverTarget(target, 12);
  for (int pass = 0; pass < kPasses; ++pass) {
    int changes = CollapsePass(target);
    changes += FlipPass(target);
    changes += Smooth(target, true);
    if (changes == 0) break;
  }
}

// Moves vertices on the domain where that lowers the largest predicted
// error of their faces (equalizing errors leaves room for more collapses).
// Candidates per vertex: half and full steps toward the centroid of its
// neighbours, and toward the centroid of its faces weighted by their
// errors (which shrinks the worst faces). One batch of surface evaluations
// for all candidates; acceptance is sequential, best candidate first.
int Tessellator::Smooth(double target, bool weighted) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  const std::vector<int> vertices = triangulation_.AliveVertices();
  const int kCandidates = weighted ? 4 : 1;
  Eigen::MatrixX3d candidates(vertices.size() * kCandidates, 3);
  tbb::parallel_for(size_t{0}, vertices.size(), [&](size_t i) {
    const int v = vertices[i];
    const std::vector<int> ring = triangulation_.Ring(v);
    const int n = static_cast<int>(ring.size());
    const Eigen::Vector3d& x = triangulation_.vertex(v);
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Vector3d pull = Eigen::Vector3d::Zero();
    double weight = 0.0;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d& y = triangulation_.vertex(ring[k]);
      const Eigen::Vector3d& z = triangulation_.vertex(ring[(k + 1) % n]);
      centroid += y;
      const double e = PredictedError(v, ring[k], ring[(k + 1) % n]);
      const double w = std::isfinite(e) ? e * e * e * e : 0.0;
      pull += w * ((x + y + z) / 3.0);
      weight += w;
    }
    centroid = centroid.normalized();
    const Eigen::Vector3d pulled =
        weight > 0.0 ? Eigen::Vector3d(pull / weight).normalized() : x;
    candidates.row(i * kCandidates + 0) = (x + centroid).normalized();
    if (kCandidates == 1) return;
    candidates.row(i * kCandidates + 1) = centroid;
    candidates.row(i * kCandidates + 2) = (x + pulled).normalized();
    candidates.row(i * kCandidates + 3) = pulled;
  });
  Eigen::MatrixX3d positions, normals;
  surface_.Sample(candidates, &positions, &normals);
  evaluations_ += candidates.rows();
  int moved = 0;
  for (size_t i = 0; i < vertices.size(); ++i) {
    const int v = vertices[i];
    const std::vector<int> ring = triangulation_.Ring(v);
    const int n = static_cast<int>(ring.size());
    auto ring_error = [&] {
      double e = 0.0;
      for (int k = 0; k < n; ++k) {
        e = std::max(e, PredictedError(v, ring[k], ring[(k + 1) % n]));
      }
      return e;
    };
    const double before = ring_error();
    const Eigen::Vector3d old_direction = triangulation_.vertex(v);
    const Eigen::Vector3d old_position = positions_[v],
                          old_normal = normals_[v];
    double best = std::min(0.98 * before, std::max(target, before));
    int best_k = -1;
    for (int k = 0; k < kCandidates; ++k) {
      const Eigen::Index row = i * kCandidates + k;
      positions_[v] = positions.row(row).transpose();
      normals_[v] = normals.row(row).transpose();
      triangulation_.MoveVertex(v, candidates.row(row).transpose(), length);
      bool valid = true;
      for (int j = 0; j < n && valid; ++j) {
        valid = triangulation_.IsPositive(v, ring[j], ring[(j + 1) % n]);
      }
      if (!valid) continue;
      const double after = ring_error();
      if (after < best) {
        best = after;
        best_k = k;
      }
    }
    if (best_k >= 0) {
      const Eigen::Index row = i * kCandidates + best_k;
      positions_[v] = positions.row(row).transpose();
      normals_[v] = normals.row(row).transpose();
      triangulation_.MoveVertex(v, candidates.row(row).transpose(), length);
      ++moved;
      continue;
    }
    positions_[v] = old_position;
    normals_[v] = old_normal;
    triangulation_.MoveVertex(v, old_direction, length);
  }
  return moved;
}

Status Tessellator::Run(Tessellation* out) {
  const auto length = [this](int a, int b) { return EdgeLength(a, b); };
  // The icosahedron's vertices are evaluated before its edges are ordered.
  triangulation_ =
      SphereTriangulation::Icosahedron([](int, int) { return 0.0; });
  for (int v = 0; v < triangulation_.num_vertices(); ++v) AddVertex(v);
  triangulation_ = SphereTriangulation::Icosahedron(length);
  auto alive_faces = [this] {
    std::vector<int> all;
    for (int f = 0; f < triangulation_.num_face_slots(); ++f) {
      if (triangulation_.alive(f)) all.push_back(f);
    }
    return all;
  };
  SDCB_RETURN_IF_ERROR(Refine(alive_faces()));
  if (options_.optimize) {
    // Two optimizations of the certified refinement; the one with fewer
    // faces is kept. The predictions are not a certificate: both certify
    // every face again and split those that fail.
    const SphereTriangulation refined = triangulation_;
    const std::vector<Eigen::Vector3d> refined_positions = positions_,
                                       refined_normals = normals_;
    // The remesher: near-optimal where the surface is smooth at the scale
    // of the faces (the sphere, ellipsoids; the bunny at 0.1 %).
    Optimize();
    SDCB_RETURN_IF_ERROR(RefineBySplits(alive_faces()));
    SDCB_RETURN_IF_ERROR(Unfold());
    SphereTriangulation remeshed = std::move(triangulation_);
    std::vector<Eigen::Vector3d> remeshed_positions = std::move(positions_),
                                 remeshed_normals = std::move(normals_);
    // Local collapses, flips and moves from the bisection pattern: better
    // where the quadratic prediction fails on the remesher's long faces (the
    // bunny at 0.01 %).
    triangulation_ = refined;
    positions_ = refined_positions;
    normals_ = refined_normals;
    OptimizeLocally();
    SDCB_RETURN_IF_ERROR(Refine(alive_faces()));
    SDCB_RETURN_IF_ERROR(Unfold());
    if (remeshed.num_faces() < triangulation_.num_faces()) {
      triangulation_ = std::move(remeshed);
      positions_ = std::move(remeshed_positions);
      normals_ = std::move(remeshed_normals);
    }
  }
  if (options_.simplify) SimplifyCertified();
  // The final verification: every face certified again, near the threshold
  // on the order-36 lattice (with `verify`). A face the moves or collapses
  // left where the order-6/18 lattice and its climb read short, or whose
  // climb now reaches another local maximum, fails and is split as after
  // the optimizations; the faces the splits make are verified the same way.
  verify_densely_ = options_.verify;
  std::vector<FaceCheck> checks;
  {
    const std::vector<int> all = alive_faces();
    checks = Check(all);
    std::vector<int> failing;
    for (size_t i = 0; i < all.size(); ++i) {
      if (!checks[i].pass) failing.push_back(all[i]);
    }
    if (!failing.empty()) {
      SDCB_RETURN_IF_ERROR(RefineBySplits(WithNeighbours(failing)));
      SDCB_RETURN_IF_ERROR(Unfold());
      checks = Check(alive_faces());  // the numbers reported
    }
  }
  const double scale =
      1.0 / (1.0 - kLatticeMargin / (options_.lattice * options_.lattice));
  for (const FaceCheck& c : checks) {
    max_distance_ = std::max(max_distance_, c.distance * scale);
    max_angle_ = std::max(max_angle_, c.angle);
    if (!c.pass) ++uncertified_;
  }

  const std::vector<int> vertices = triangulation_.AliveVertices();
  out->faces = triangulation_.Faces();
  const int nv = static_cast<int>(vertices.size());
  out->directions.resize(nv, 3);
  out->positions.resize(nv, 3);
  out->normals.resize(nv, 3);
  for (int i = 0; i < nv; ++i) {
    const int v = vertices[i];
    out->directions.row(i) = triangulation_.vertex(v).transpose();
    out->positions.row(i) = positions_[v].transpose();
    out->normals.row(i) = normals_[v].transpose();
  }
  out->certified_distance = max_distance_;
  out->max_normal_angle_degrees = max_angle_ * 180.0 / kPi;
  out->uncertified_faces = uncertified_;
  out->evaluations = evaluations_;
  return Status::Ok();
}

}  // namespace

StatusOr<Tessellation> TessellateAdaptively(
    const SurfaceSampler& surface, const TessellationOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    return InvalidArgumentError("tessellation tolerance must be > 0");
  }
  if (!(options.angle_degrees > 0.0 && options.angle_degrees <= 180.0)) {
    return InvalidArgumentError("tessellation angle must be in (0, 180]");
  }
  if (options.lattice < 2 || options.lattice > 16) {
    return InvalidArgumentError("tessellation lattice order must be in 2..16");
  }
  Tessellator tessellator(surface, options);
  Tessellation out;
  SDCB_RETURN_IF_ERROR(tessellator.Run(&out));
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
