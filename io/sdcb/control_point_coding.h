// The coding of quantized control points in the `.sdcb` PCTL chunk
// (docs/FORMAT.md, "Chunks of versions 2 and 3", PCTL): each control point's
// grid codes predicted from the control points of neighbouring basis functions
// already decoded, the residuals range-coded (io/sdcb/range_coder.h).
//
// Neighbours: two basis functions whose configuration sets share all but
// one knot (k + 2 of their k + 3) are adjacent; their control points lie
// close (their supports overlap most). The coding order is a breadth-first
// traversal of that adjacency graph from set 0, each set's neighbours in
// ascending index order, a new traversal from the smallest set not yet
// reached when one ends. A control point's prediction is the rounded mean of
// the codes of its adjacent sets coded before it (the previous control point
// in the order if there is none, 0 for the first): integer arithmetic only,
// so every reader predicts the same codes. Residuals are coded in contexts
// of the coordinate and the size of the residuals around (the neighbours',
// and the point's own of the coordinates coded before). The plan depends
// only on the configurations, which the reader recomputes from the knots.
#ifndef SDCB_IO_SDCB_CONTROL_POINT_CODING_H_
#define SDCB_IO_SDCB_CONTROL_POINT_CODING_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/delaunay_configurations.h"

namespace sdcb {

struct PredictionPlan {
  // The sets (control points) in coding order: a permutation of 0..m-1.
  std::vector<int> order;
  // For order[p]: the adjacent sets coded before it (positions offsets[p]
  // to offsets[p + 1] of `neighbours`), ascending.
  std::vector<int> offsets;
  std::vector<int> neighbours;
};

// The plan of `configurations` (see above). Cost: O(m (k + 3) log m).
PredictionPlan PlanControlPointPrediction(
    const DelaunayConfigurations& configurations);

// `codes` (3 m grid codes by coordinate: all x, then all y, then all z, each
// below 2^bits) as one range-coded stream following `plan`.
std::string EncodePredictedCodes(const std::vector<uint32_t>& codes,
                                 const PredictionPlan& plan);

// The inverse: 3 m codes, each checked below 2^bits (1..32); kCorruptFile
// naming the problem for an invalid bit length, a code out of range, a
// stream that ends early or has bytes left over. Allocates 3 m codes and
// the models' fixed tables, whatever the stream holds.
StatusOr<std::vector<uint32_t>> DecodePredictedCodes(std::string_view stream,
                                                     const PredictionPlan& plan,
                                                     int bits);

}  // namespace sdcb

#endif  // SDCB_IO_SDCB_CONTROL_POINT_CODING_H_
