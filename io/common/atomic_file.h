// Whole-file writes that never leave a half-written file behind: the data
// goes to a temporary file in the same directory, which is renamed over the
// destination only after everything was written and flushed.
#ifndef SDCB_IO_COMMON_ATOMIC_FILE_H_
#define SDCB_IO_COMMON_ATOMIC_FILE_H_

#include <cstdint>
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

// Checks, before any work, that WriteFileAtomically(..., path) could succeed
// as far as the file system tells: `path` is not a directory, its folder
// exists, and a temporary file can be created there (it is created and
// removed at once; `path` itself is not touched). Messages start with
// `path`.
Status CheckWritableDestination(const std::string& path);

// Every temporary file WriteFileAtomically(..., path) creates in this
// process has a name that starts with this prefix (in the folder of
// `path`): "<folder>/.<name>.tmp.<pid>.". A program that must remove them
// when it is interrupted (the CLI's signal handling) matches it.
std::string TemporaryFilePrefix(const std::string& path);
// The same for the process `pid`: what a parent removes after a child
// writing `path` was killed (SIGKILL leaves the child no time to clean up).
std::string TemporaryFilePrefix(const std::string& path, int64_t pid);

}  // namespace sdcb

#endif  // SDCB_IO_COMMON_ATOMIC_FILE_H_
