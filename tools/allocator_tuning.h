// Process-wide malloc settings of the programs (the `sdcb` command and the
// benchmarks). The libraries never change them; a program that links them
// decides, as these do.
#ifndef SDCB_TOOLS_ALLOCATOR_TUNING_H_
#define SDCB_TOOLS_ALLOCATOR_TUNING_H_

#include <cstdlib>  // defines __GLIBC__ with glibc
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace sdcb::cli {

// The fit allocates and frees tens of megabytes per round (design matrix,
// its column-major copy, the normal matrix's columns) from TBB's threads.
// With glibc's defaults every thread's arena gives that memory back to the
// kernel at each free (trim) and faults it in again, zeroed, at the next
// round: on bunny00 at --rmse 0.067 that was 0.74 of 6.7 CPU seconds in the
// kernel and 0.46 s of 3.9 s wall when these settings were added
// (docs/FITTING.md, "bunny00 at 0.067 %: where the time goes"). Keeping
// 128 MiB of slack at the top of each heap, and serving blocks below
// 32 MiB from the heaps, removes most of it (the same output bytes; peak
// memory +24 MB on the bunny). Call first thing in main(), before any
// thread starts. Not for a library: it changes the whole process.
inline void TuneAllocatorForRounds() {
#ifdef __GLIBC__
  mallopt(M_TOP_PAD, 128 << 20);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
#endif
}

}  // namespace sdcb::cli

#endif  // SDCB_TOOLS_ALLOCATOR_TUNING_H_
