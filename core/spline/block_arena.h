// Memory for many small objects that all live as long as their owner (the
// regions of a PiecewiseSurface): carved in order from large blocks, freed
// together when the arena is destroyed. One allocation costs a lock and an
// addition; consecutive allocations of one thread are adjacent. On Linux the
// blocks are 2 MB-aligned mappings that may be backed by transparent huge
// pages (madvise): the first touch of a region's memory then costs one page
// fault per 2 MB instead of one per 4 KB.
#ifndef SDCB_CORE_SPLINE_BLOCK_ARENA_H_
#define SDCB_CORE_SPLINE_BLOCK_ARENA_H_

#include <cstddef>
#include <mutex>
#include <new>
#include <type_traits>
#include <vector>

namespace sdcb {

class BlockArena {
 public:
  // `block_bytes`: the size of the blocks requested from the system.
  explicit BlockArena(std::size_t block_bytes = std::size_t{8} << 20)
      : block_bytes_(block_bytes) {}
  ~BlockArena();
  BlockArena(const BlockArena&) = delete;
  BlockArena& operator=(const BlockArena&) = delete;

  // `bytes` uninitialized bytes aligned to 16, valid until the arena is
  // destroyed. Thread-safe. Throws std::bad_alloc when out of memory.
  void* Allocate(std::size_t bytes);

  // `n` value-initialized objects of a trivially destructible type (never
  // destroyed, only freed with the arena).
  template <typename T>
  T* New(std::size_t n = 1) {
    static_assert(std::is_trivially_destructible_v<T>);
    static_assert(alignof(T) <= 16);
    T* out = static_cast<T*>(Allocate(n * sizeof(T)));
    for (std::size_t i = 0; i < n; ++i) new (out + i) T();
    return out;
  }

 private:
  struct Block {
    void* start;
    std::size_t bytes;
  };

  const std::size_t block_bytes_;
  std::mutex mutex_;
  std::vector<Block> blocks_;
  char* next_ = nullptr;
  char* end_ = nullptr;
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_BLOCK_ARENA_H_
