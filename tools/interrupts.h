// What the CLI does when it is interrupted (SIGINT, SIGTERM, SIGHUP): the
// temporary files of outputs being written (io/common/atomic_file.h) are
// removed, then the process ends by the signal as it would have without this.
// The libraries change no process-wide settings; this lives in the CLI.
#ifndef SDCB_TOOLS_INTERRUPTS_H_
#define SDCB_TOOLS_INTERRUPTS_H_

#include <string>

namespace sdcb::cli {

// Blocks the three signals in the calling thread and in every thread
// started later (TBB's workers included), and starts one thread that waits
// for them. Call first thing in main(), before any other thread exists.
void InstallInterruptCleanup();

// Called when the run is over, before main returns: an interrupt sent
// before then (pending, or being handled) ends the process by its signal
// (this blocks until it does); one sent later leaves the finished run's
// exit status alone.
void EndRunBeforeAnyInterrupt();

// Registers `output_path`: when the process is interrupted, files starting
// with TemporaryFilePrefix(output_path) are removed. A finished output
// (renamed into place) is a complete file and stays.
void RemoveTemporariesOnInterrupt(const std::string& output_path);

// Removes the files of `prefix`'s folder whose names start with `prefix`'s
// file name (e.g. a TemporaryFilePrefix, io/common/atomic_file.h).
void RemoveFilesStartingWith(const std::string& prefix);

}  // namespace sdcb::cli

#endif  // SDCB_TOOLS_INTERRUPTS_H_
