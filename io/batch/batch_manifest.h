// The manifest of `sdcb batch` (docs/BATCH.md): one asset per line,
//   INPUT OUTPUT [OPTION ...]        # comment
// fields separated by spaces or tabs; a field may be written in double
// quotes to hold spaces ("my scan.ply"; \" and \\ escape inside quotes);
// '#' at the start of a field starts a comment that runs to the end of the
// line; empty and comment-only lines are skipped. The options are kept as
// written (the CLI's own syntax, e.g. `--rmse 0.1 --draco`); what they
// mean is the command line's business (tools/batch_command.cpp).
#ifndef SDCB_IO_BATCH_BATCH_MANIFEST_H_
#define SDCB_IO_BATCH_BATCH_MANIFEST_H_

#include <string>
#include <string_view>
#include <vector>

#include "sdcb/core/common/status.h"

namespace sdcb {

struct ManifestRow {
  int line = 0;                      // 1-based line number in the manifest.
  std::string input;                 // First field, as written.
  std::string output;                // Second field, as written.
  std::vector<std::string> options;  // The remaining fields, in order.
};

// Parses the text of a manifest. A line with one field only, an
// unterminated quote, a quote not followed by a separator, or a NUL byte is
// kCorruptFile with a message "line N: ..." (the caller adds the file
// name). Rows are returned in the order of the lines.
StatusOr<std::vector<ManifestRow>> ParseBatchManifest(std::string_view text);

}  // namespace sdcb

#endif  // SDCB_IO_BATCH_BATCH_MANIFEST_H_
