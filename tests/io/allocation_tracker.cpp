// The io test binary's malloc: glibc's, recording the largest single request
// while tracking is on (tests/testing/allocation_tracker.h).
#include "testing/allocation_tracker.h"

#include <atomic>

namespace {
std::atomic<bool> g_track_allocations{false};
std::atomic<size_t> g_largest_allocation{0};

void Record(size_t size) {
  if (g_track_allocations.load(std::memory_order_relaxed)) {
    size_t seen = g_largest_allocation.load(std::memory_order_relaxed);
    while (size > seen && !g_largest_allocation.compare_exchange_weak(
                              seen, size, std::memory_order_relaxed)) {
    }
  }
}
}  // namespace

#if defined(__SANITIZE_ADDRESS__)
// With AddressSanitizer (scripts/sanitize.sh) its allocator must see every
// allocation: the tracker listens through the sanitizer's malloc hook
// instead of replacing malloc.
extern "C" int __sanitizer_install_malloc_and_free_hooks(
    void (*malloc_hook)(const volatile void*, size_t),
    void (*free_hook)(const volatile void*));
namespace {
[[maybe_unused]] const int kHooksInstalled =
    __sanitizer_install_malloc_and_free_hooks(
        [](const volatile void*, size_t size) { Record(size); },
        [](const volatile void*) {});
}  // namespace
#else
extern "C" void* __libc_malloc(size_t size);  // glibc's own allocator
extern "C" void* malloc(size_t size) {
  Record(size);
  return __libc_malloc(size);
}
#endif

namespace sdcb::testing {

size_t LargestAllocationDuring(const std::function<void()>& f) {
  g_largest_allocation = 0;
  g_track_allocations = true;
  f();
  g_track_allocations = false;
  return g_largest_allocation;
}

}  // namespace sdcb::testing
