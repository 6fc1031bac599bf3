// What the CLI does when it is interrupted (SIGINT, SIGTERM, SIGHUP): the
// temporary files of outputs being written (io/atomic_file.h) are removed,
// then the process ends by the signal as it would have without this. The
// libraries change no process-wide settings; this lives in the CLI.
#ifndef SDCB_TOOLS_INTERRUPTS_H_
#define SDCB_TOOLS_INTERRUPTS_H_

#include <string>

namespace sdcb::cli {

// Blocks the three signals in the calling thread and in every thread
// started later (TBB's workers included), and starts one thread that waits
// for them. Call first thing in main(), before any other thread exists.
void InstallInterruptCleanup();

// Registers `output_path`: when the process is interrupted, files starting
// with TemporaryFilePrefix(output_path) are removed. A finished output
// (renamed into place) is a complete file and stays.
void RemoveTemporariesOnInterrupt(const std::string& output_path);

}  // namespace sdcb::cli

#endif  // SDCB_TOOLS_INTERRUPTS_H_
