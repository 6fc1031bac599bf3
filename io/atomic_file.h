// Whole-file writes that never leave a half-written file behind: the data
// goes to a temporary file in the same directory, which is renamed over the
// destination only after everything was written and flushed.
#ifndef SDCB_IO_ATOMIC_FILE_H_
#define SDCB_IO_ATOMIC_FILE_H_

#include <functional>
#include <ostream>
#include <string>

#include "sdcb/core/common/status.h"

namespace sdcb {

// Writers take the data first, then the path (here: what writes the data).
// Calls `write` with a binary stream on a temporary file next to `path`, then
// renames it to `path`. On any failure (including a non-ok Status from
// `write`) the temporary file is removed and `path` is left untouched.
// Messages start with `path`.
Status WriteFileAtomically(const std::function<Status(std::ostream&)>& write,
                           const std::string& path);

// Same, for contents already in memory.
Status WriteFileAtomically(const std::string& contents,
                           const std::string& path);

}  // namespace sdcb

#endif  // SDCB_IO_ATOMIC_FILE_H_
