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
//   parts                (the Model overload) per part the keys above, plus
//                        number, name, kept, trimmed, trims; a kept part has
//                        reason, vertices (#V x 3, input coordinates) and
//                        faces (#F x 3, 0-based) instead of a spline's keys
// Doubles are printed with the shortest text that parses back to the same
// bits; key order is fixed (sorted), so equal models give equal text.
#ifndef SDCB_IO_REPORT_MODEL_JSON_H_
#define SDCB_IO_REPORT_MODEL_JSON_H_

#include <string>

#include "sdcb/core/spline/model.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// Compact JSON text ending in a newline. Bytes of `source.file_name` that are
// not valid UTF-8 are replaced by U+FFFD.
std::string ModelToJson(const SplineModel& model);

// A Model (core/spline/model.h): `format_version`, `source` (the whole
// input's), and `parts`, one object per part in order with the keys above
// (but format_version; `source` the part's) plus `number` (from 1), `name`,
// `kept`, `trimmed` and `trims` (loops of #points x 3 unit vectors); a kept
// part has `reason`, `vertices` and `faces` instead of the spline's keys. A
// model of one fitted part also has that part's spline keys at the top, as
// ModelToJson of its SplineModel gives them (its `source` is the model's).
std::string ModelToJson(const Model& model);

}  // namespace sdcb

#endif  // SDCB_IO_REPORT_MODEL_JSON_H_
