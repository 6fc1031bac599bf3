#include "sdcb/core/mesh/self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <string>
#include <utility>
#include <vector>

namespace sdcb {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<
    double, 3, int, CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

// Thrown by the box callback once the budget of box pairs is spent.
struct TooManyPairs {};

// Box pairs are tested in parallel in batches of this many.
constexpr size_t kBatch = size_t{1} << 18;

// Whether faces f and g meet other than in the corners they share (exact
// predicates). Sharing an edge ab, with third corners p and q: they
// overlap iff the four points are coplanar and p, q lie on the same side of
// ab. Sharing a corner v: their intersection is a convex set through v, so
// it reaches beyond v iff the edge of one opposite v meets the other.
bool FacesIntersect(const std::vector<Point>& points, const TriangleMesh& mesh,
                    int f, int g) {
  int fv[3], gv[3];
  for (int k = 0; k < 3; ++k) {
    fv[k] = mesh.faces(f, k);
    gv[k] = mesh.faces(g, k);
  }
  int shared = 0, f_corner = -1, g_corner = -1;
  bool f_shared[3] = {false, false, false};
  bool g_shared[3] = {false, false, false};
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      if (fv[a] != gv[b]) continue;
      ++shared;
      f_shared[a] = g_shared[b] = true;
      f_corner = a;
      g_corner = b;
    }
  }
  auto at = [&](int v) -> const Point& { return points[v]; };
  if (shared >= 3) return true;  // the same triangle twice
  if (shared == 2) {
    int p = -1, q = -1, a = -1, b = -1;
    for (int k = 0; k < 3; ++k) {
      if (!f_shared[k]) p = fv[k];
      if (!g_shared[k]) q = gv[k];
    }
    for (int k = 0; k < 3; ++k) {
      if (f_shared[k]) (a < 0 ? a : b) = fv[k];
    }
    return CGAL::coplanar(at(a), at(b), at(p), at(q)) &&
           CGAL::coplanar_orientation(at(a), at(b), at(p), at(q)) ==
               CGAL::POSITIVE;
  }
  const Kernel::Triangle_3 tf(at(fv[0]), at(fv[1]), at(fv[2]));
  const Kernel::Triangle_3 tg(at(gv[0]), at(gv[1]), at(gv[2]));
  if (shared == 1) {
    const Kernel::Segment_3 sf(at(fv[(f_corner + 1) % 3]),
                               at(fv[(f_corner + 2) % 3]));
    const Kernel::Segment_3 sg(at(gv[(g_corner + 1) % 3]),
                               at(gv[(g_corner + 2) % 3]));
    return CGAL::do_intersect(tf, sg) || CGAL::do_intersect(tg, sf);
  }
  return CGAL::do_intersect(tf, tg);
}

// Intersecting pairs among `pairs`, tested in parallel.
int64_t CountIntersecting(const std::vector<Point>& points,
                          const TriangleMesh& mesh,
                          const std::vector<std::pair<int, int>>& pairs) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, pairs.size(), 1024), int64_t{0},
      [&](const tbb::blocked_range<size_t>& range, int64_t count) {
        for (size_t i = range.begin(); i < range.end(); ++i) {
          count +=
              FacesIntersect(points, mesh, pairs[i].first, pairs[i].second);
        }
        return count;
      },
      [](int64_t a, int64_t b) { return a + b; });
}

// Counts the intersecting face pairs among the box pairs a search reports,
// testing them in parallel batches; throws TooManyPairs once the searches
// sharing `box_pairs` have reported more than `budget` pairs.
class PairCounter {
 public:
  PairCounter(const std::vector<Point>& points, const TriangleMesh& mesh,
              std::atomic<int64_t>* box_pairs, int64_t budget)
      : points_(points), mesh_(mesh), box_pairs_(box_pairs), budget_(budget) {
    batch_.reserve(kBatch);
  }

  void Add(const Box* a, const Box* b) {
    if (++*box_pairs_ > budget_) throw TooManyPairs();
    batch_.emplace_back(a->info(), b->info());
    if (batch_.size() == kBatch) Flush();
  }

  int64_t Finish() {
    Flush();
    return intersecting_;
  }

 private:
  void Flush() {
    intersecting_ += CountIntersecting(points_, mesh_, batch_);
    batch_.clear();
  }

  const std::vector<Point>& points_;
  const TriangleMesh& mesh_;
  std::atomic<int64_t>* box_pairs_;
  int64_t budget_;
  std::vector<std::pair<int, int>> batch_;
  int64_t intersecting_ = 0;
};

}  // namespace

StatusOr<SelfIntersectionReport> FindSelfIntersections(
    const TriangleMesh& mesh, const SelfIntersectionOptions& options) {
  SDCB_RETURN_IF_ERROR(CheckFaceIndices(mesh));
  SelfIntersectionReport report;
  std::vector<Point> points;
  points.reserve(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    points.emplace_back(mesh.vertices(v, 0), mesh.vertices(v, 1),
                        mesh.vertices(v, 2));
  }
  // Boxes of the non-degenerate triangles (the degenerate ones are the
  // topology report's).
  std::vector<Box> boxes;
  boxes.reserve(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Point& a = points[mesh.faces(f, 0)];
    const Point& b = points[mesh.faces(f, 1)];
    const Point& c = points[mesh.faces(f, 2)];
    if (CGAL::collinear(a, b, c)) continue;
    boxes.emplace_back(a.bbox() + b.bbox() + c.bbox(), f);
  }
  // Pointers (the box algorithm reorders what it is given, and a box's id
  // is its address) in three sets split by the plane x = the median of the
  // boxes' centers: left of it, right of it, and across it. Left and right
  // boxes never overlap, so every overlapping pair is found once by the
  // searches left x left and right x right (run side by side, the bulk of
  // the work) and across x {across, left, right}.
  double split = 0.0;
  if (!boxes.empty()) {
    std::vector<double> centers(boxes.size());
    for (size_t i = 0; i < boxes.size(); ++i) {
      centers[i] = boxes[i].min_coord(0) + boxes[i].max_coord(0);
    }
    auto middle = centers.begin() + centers.size() / 2;
    std::nth_element(centers.begin(), middle, centers.end());
    split = 0.5 * *middle;
  }
  std::vector<const Box*> left, right, across;
  for (const Box& box : boxes) {
    (box.max_coord(0) <= split  ? left
     : box.min_coord(0) > split ? right
                                : across)
        .push_back(&box);
  }

  const int64_t budget =
      options.max_pairs_per_face * mesh.num_faces() + options.max_extra_pairs;
  std::atomic<int64_t> box_pairs{0};
  constexpr std::ptrdiff_t kCutoff = 2000;
  PairCounter pairs(points, mesh, &box_pairs, budget);
  PairCounter right_pairs(points, mesh, &box_pairs, budget);
  try {
    auto search_self = [&](std::vector<const Box*>* set, PairCounter* pairs) {
      CGAL::box_self_intersection_d(
          set->begin(), set->end(),
          [&](const Box* a, const Box* b) { pairs->Add(a, b); }, kCutoff);
    };
    tbb::task_group side;
    side.run([&] { search_self(&right, &right_pairs); });
    search_self(&left, &pairs);
    side.wait();
    search_self(&across, &pairs);
    for (std::vector<const Box*>* other : {&left, &right}) {
      CGAL::box_intersection_d(
          across.begin(), across.end(), other->begin(), other->end(),
          [&](const Box* a, const Box* b) { pairs.Add(a, b); }, kCutoff);
    }
    report.intersecting_pairs = pairs.Finish() + right_pairs.Finish();
  } catch (const TooManyPairs&) {
    report.intersecting_pairs = 0;
    report.skipped_because =
        "more than " + std::to_string(budget) +
        " pairs of triangles overlap in their bounding boxes (a fan of very "
        "many triangles around one vertex?)";
    return report;
  }
  report.checked = true;
  return report;
}

}  // namespace sdcb
