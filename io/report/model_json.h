// The whole model as JSON, for `sdcb dump` (keys: docs/FORMAT.md, "`sdcb dump`
// JSON"):
//   format_version       the .sdcb format version this code writes
//   degree               k
//   knots                n x 3, unit vectors on S^2
//   basis                [{"knots": k+3 knot indices,
//                          "configurations": [[a,b,c], ...] boundary triples}]
//   control_points       m x 3, in INPUT coordinates
//                        (scale * normalized + translation)
//   control_points_normalized  m x 3, as stored (normalized frame)
//   transform            {"scale", "translation": [x,y,z], "definition"}
//   statistics           {"rounds", "final", "timings", "options"}
//                        (io/report/fit_statistics_json.h)
//   source               {"vertices", "faces", "hash" ("0x" + 16 hex digits),
//                         "file_name"}
//   parameters           N x 3 sphere points, only when the model stores them
// Doubles are printed with the shortest text that parses back to the same
// bits; key order is fixed (sorted), so equal models give equal text.
#ifndef SDCB_IO_REPORT_MODEL_JSON_H_
#define SDCB_IO_REPORT_MODEL_JSON_H_

#include <string>

#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// Compact JSON text ending in a newline. Bytes of `source.file_name` that are
// not valid UTF-8 are replaced by U+FFFD.
std::string ModelToJson(const SplineModel& model);

}  // namespace sdcb

#endif  // SDCB_IO_REPORT_MODEL_JSON_H_
