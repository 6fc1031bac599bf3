// The io test binary's malloc: glibc's, recording the largest single request
// while tracking is on (tests/testing/allocation_tracker.h).
#include "testing/allocation_tracker.h"

#include <atomic>

namespace {
std::atomic<bool> g_track_allocations{false};
std::atomic<size_t> g_largest_allocation{0};
}  // namespace

extern "C" void* __libc_malloc(size_t size);  // glibc's own allocator
extern "C" void* malloc(size_t size) {
  if (g_track_allocations.load(std::memory_order_relaxed)) {
    size_t seen = g_largest_allocation.load(std::memory_order_relaxed);
    while (size > seen && !g_largest_allocation.compare_exchange_weak(
                              seen, size, std::memory_order_relaxed)) {
    }
  }
  return __libc_malloc(size);
}

namespace sdcb::testing {

size_t LargestAllocationDuring(const std::function<void()>& f) {
  g_largest_allocation = 0;
  g_track_allocations = true;
  f();
  g_track_allocations = false;
  return g_largest_allocation;
}

}  // namespace sdcb::testing
