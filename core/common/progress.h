// The progress callback of the library's long stages: called with the name
// of the stage running and the estimated finished fraction of the whole
// call, in [0, 1], from the calling thread. Libraries report through it and
// never print; the command line draws it (tools/progress.h).
#ifndef SDCB_CORE_COMMON_PROGRESS_H_
#define SDCB_CORE_COMMON_PROGRESS_H_

#include <functional>
#include <string>

namespace sdcb {

using ProgressCallback =
    std::function<void(const std::string& stage, double fraction)>;

}  // namespace sdcb

#endif  // SDCB_CORE_COMMON_PROGRESS_H_
