#include "sdcb/core/spline/block_arena.h"

#include <algorithm>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace sdcb {
namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;

// `bytes` (a multiple of kHugePage on Linux) of fresh memory: the start of
// the mapping (to free) in *start, the usable part at the return value.
char* MapBlock(std::size_t bytes, void** start) {
#if defined(MAP_ANONYMOUS) && defined(MADV_HUGEPAGE)
  // One huge page more, to align the block.
  void* p = mmap(nullptr, bytes + kHugePage, PROT_READ | PROT_WRITE,
                 MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  *start = p;
  const std::uintptr_t address = reinterpret_cast<std::uintptr_t>(p);
  char* aligned = reinterpret_cast<char*>((address + kHugePage - 1) &
                                          ~std::uintptr_t{kHugePage - 1});
  // Advice only: without huge pages the block works the same.
  madvise(aligned, bytes, MADV_HUGEPAGE);
  return aligned;
#else
  char* p = new char[bytes + 16];
  *start = p;
  const std::uintptr_t address = reinterpret_cast<std::uintptr_t>(p);
  return reinterpret_cast<char*>((address + 15) & ~std::uintptr_t{15});
#endif
}

void UnmapBlock(void* start, std::size_t bytes) {
#if defined(MAP_ANONYMOUS) && defined(MADV_HUGEPAGE)
  munmap(start, bytes + kHugePage);
#else
  (void)bytes;
  delete[] static_cast<char*>(start);
#endif
}

}  // namespace

BlockArena::~BlockArena() {
  for (const Block& block : blocks_) UnmapBlock(block.start, block.bytes);
}

void* BlockArena::Allocate(std::size_t bytes) {
  bytes = (bytes + 15) & ~std::size_t{15};
  std::lock_guard<std::mutex> lock(mutex_);
  if (next_ == nullptr || static_cast<std::size_t>(end_ - next_) < bytes) {
    // A new block (the rest of the current one stays unused).
    std::size_t size = std::max(block_bytes_, bytes);
    size = (size + kHugePage - 1) / kHugePage * kHugePage;
    blocks_.push_back({nullptr, size});
    try {
      next_ = MapBlock(size, &blocks_.back().start);
    } catch (...) {
      blocks_.pop_back();
      throw;
    }
    end_ = next_ + size;
  }
  void* out = next_;
  next_ += bytes;
  return out;
}

}  // namespace sdcb
